// A contact sensor: a latch set when a penetration signal is seen and cleared on
// the next tick (one tick of hysteresis), run in parallel with a second, unrelated sensor.
//   sensorWF = seq(run(set), run(clear));   fullWF = par(sensorWF, otherSensorWF)
#include "phynjo/runtime/runtime.hpp"

#include <cstdio>

using namespace phynjo::runtime;

static EventWorkflow sensor(const FlagWorld& shape, Index raw, Index latch, const std::string& name) {
    EventRule set{name + ".set", ComponentSet{latch}, ComponentSet{raw},
                  [raw](const FlagLit& in, std::span<std::uint8_t> out) {
                      if (in.lookup(raw)) out[0] = 1;
                  },
                  nullptr};
    EventRule clear{name + ".clear", ComponentSet{latch}, {}, [](const FlagLit&, std::span<std::uint8_t> out) { out[0] = 0; },
                    [latch, name](std::uint64_t tick, std::span<const std::uint8_t> slice, Phenomenon& events) {
                        if (slice[0]) events.push_back(epsilon(latch, tick, name + " latched"));
                    }};
    return EventWorkflow::seq(EventWorkflow::run(set, shape), EventWorkflow::run(clear, shape));
}

int main() {
    Registry flags;
    const Index penetration = flags.add("penetration"), on_ground = flags.add("on_ground");
    const Index door_signal = flags.add("door_signal"), door_open = flags.add("door_open");
    FlagWorld world(flags);
    const EventWorkflow full = EventWorkflow::par(sensor(world, penetration, on_ground, "ground"),
                                                  sensor(world, door_signal, door_open, "door"));
    try {
        (void)EventWorkflow::par(sensor(world, penetration, on_ground, "ground"),
                                 sensor(world, door_signal, on_ground, "miswired"));
    } catch (const DomainOverlapError& e) {
        std::printf("refused at build time: %s\n", e.what());
    }
    Interpreter<FlagWorld> run(full.process());
    Phenomenon log;
    for (int step = 0; step < 6; ++step) {
        world.flags.set(penetration, step == 1 || step == 2 || step == 4);
        world.flags.set(door_signal, step == 2);
        run.step(world, 0, &log);
    }
    for (const Event& e : log) std::printf("tick %llu: %s\n", static_cast<unsigned long long>(e.tick), e.what.c_str());
    return 0;
}
