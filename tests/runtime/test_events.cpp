// The Boolean layer: a contact sensor with one-tick hysteresis, combined in
// parallel with a second sensor, through the same Process interpreter.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

using namespace phynjo::runtime;

namespace {

/// A sensor: `raw` is the input signal (written by the environment), `latched` is set when
/// raw is seen and cleared on the next tick: seq(set, clear) gives exactly one tick of
/// hysteresis, like sensorWF = ESeq (ERun setRule) (ERun clearRule).
EventWorkflow sensor(const FlagWorld& shape, Index raw, Index latched, const std::string& name) {
    EventRule set{name + ".set", ComponentSet{latched}, ComponentSet{raw},
                  [raw](const FlagLit& in, std::span<std::uint8_t> out) {
                      if (in.lookup(raw)) out[0] = 1;
                  },
                  nullptr};
    EventRule clear{name + ".clear", ComponentSet{latched}, {},
                    [](const FlagLit&, std::span<std::uint8_t> out) { out[0] = 0; },
                    [latched, name](std::uint64_t tick, std::span<const std::uint8_t> slice, Phenomenon& events) {
                        if (slice[0]) events.push_back(epsilon(latched, tick, name + " fired"));
                    }};
    return EventWorkflow::seq(EventWorkflow::run(set, shape), EventWorkflow::run(clear, shape));
}

} // namespace

TEST_CASE("contact sensor with one-tick hysteresis in parallel with a second sensor", "[runtime][events]") {
    Registry flags;
    const Index penetration = flags.add("penetration"), on_ground = flags.add("on_ground");
    const Index door_signal = flags.add("door_signal"), door_open = flags.add("door_open");
    FlagWorld world(flags);
    const auto ground = sensor(world, penetration, on_ground, "ground");
    const auto door = sensor(world, door_signal, door_open, "door");
    const auto full = EventWorkflow::par(ground, door); // disjoint domains: allowed
    CHECK(full.domain().components(0) == ComponentSet{on_ground, door_open});
    CHECK_THROWS_AS(EventWorkflow::par(ground, sensor(world, door_signal, on_ground, "clash")), DomainOverlapError);

    Interpreter<FlagWorld> run(full.process());
    Phenomenon log;
    // The set rule runs at tick 2k, the clear rule at 2k+1 (seq: one tick each; par: the
    // branches share ticks). Raw signals: penetration at steps 1 and 2, door at step 2.
    std::vector<bool> ground_seen, door_seen;
    for (int step = 0; step < 4; ++step) {
        world.flags.set(penetration, step == 1 || step == 2);
        world.flags.set(door_signal, step == 2);
        run.step(world, 0.0, &log);
        ground_seen.push_back(world.flags.lookup(on_ground));
        door_seen.push_back(world.flags.lookup(door_open));
        CHECK(world.tick == static_cast<std::uint64_t>(2 * (step + 1)));
    }
    // after each full step the latch has been cleared again: hysteresis of exactly one tick
    CHECK(ground_seen == std::vector<bool>{false, false, false, false});
    // the clear rule fires at the tick after the set tick, in branch order (ground, door)
    const Phenomenon expected{{3, on_ground, "ground fired"}, {5, on_ground, "ground fired"}, {5, door_open, "door fired"}};
    CHECK(log == expected);
}

TEST_CASE("an event rule sees the flags of the tick it runs at", "[runtime][events]") {
    Registry flags;
    const Index a = flags.add("a"), b = flags.add("b");
    FlagWorld world(flags);
    // b ← a, then a ← not a: in seq the copy sees the old a; in par both see the same input
    EventRule copy{"copy", ComponentSet{b}, ComponentSet{a},
                   [a](const FlagLit& in, std::span<std::uint8_t> out) { out[0] = in.lookup(a); }, nullptr};
    EventRule flip{"flip", ComponentSet{a}, {}, [](const FlagLit&, std::span<std::uint8_t> out) { out[0] = !out[0]; },
                   nullptr};
    Interpreter<FlagWorld> seq(EventWorkflow::seq(EventWorkflow::run(copy, world), EventWorkflow::run(flip, world)).process());
    seq.step(world, 0);
    CHECK_FALSE(world.flags.lookup(b));
    CHECK(world.flags.lookup(a));
    // par(copy, flip) is rejected: flip writes a, which copy reads
    CHECK_THROWS_AS(EventWorkflow::par(EventWorkflow::run(copy, world), EventWorkflow::run(flip, world)),
                    DomainOverlapError);
}
