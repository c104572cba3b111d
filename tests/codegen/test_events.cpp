// Events of generated models (docs/language.md, *Events*; runtime simulate/events.hpp) against
// closed forms: the bouncing ball's every impact, the pendulum striking a wall (elliptic
// integrals), `stop` at a `>` guard and at a velocity guard, simultaneous events, resets
// read from the pre-event state, re-arming, Zeno and its remedy — with every integrator.
#include "bouncing_ball.hpp"
#include "launch.hpp"
#include "pendulum_wall.hpp"
#include "swap.hpp"
#include "two_balls.hpp"
#include "wrap.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <string>

using namespace phynjo::runtime;

namespace {

struct Run {
    World w;
    std::vector<EventRecord> log;
    bool stopped = false;
};

/// `system` from its initial state to t_end in run steps of dt with `integrator` (rk4,
/// midpoint, rattle, dopri, cvode, ida), every step watched by an EventMonitor.
Run run(const LagrangianSystem& s, const std::string& integrator, double t_end, double dt, EventOptions eo = {}) {
    Run r{make_lagrangian_world(s), {}, false};
    World& w = r.w;
    EventMonitor monitor(s, eo);
    const long steps = std::lround(t_end / dt);
    auto drive = [&](auto&& step_to) {
        for (long k = 1; k <= steps && !r.stopped; ++k)
            r.stopped = !advance_with_events(monitor, w, static_cast<double>(k) * dt, dt, step_to);
    };
    if (integrator == "dopri") {
        DormandPrince45 dp(s, {.rtol = 1e-12, .atol = 1e-14});
        const EventMonitor::Extension dense = [&](double t, std::span<double> q, std::span<double> v) { dp.dense(t, q, v); };
        for (long k = 1; k <= steps && !r.stopped; ++k)
            r.stopped = !advance_with_events(
                monitor, w, static_cast<double>(k) * dt, dt,
                [&](double target, double h) { dp.step(w, std::min(dp.next_dt() > 0 ? dp.next_dt() : h, target - w.time), target); },
                &dense);
    } else if (integrator == "cvode") {
        Cvode cv(s, {.rtol = 1e-12, .atol = 1e-14});
        drive([&](double target, double) { cv.advance(w, target); });
    } else if (integrator == "ida") {
        Ida ida(s, {.rtol = 1e-12, .atol = 1e-14});
        drive([&](double target, double) { ida.advance(w, target); });
    } else {
        Stepper stepper(integrator == "rk4"        ? lagrangian_rk4(s, w.layout_ptr())
                        : integrator == "midpoint" ? lagrangian_midpoint(s, w.layout_ptr())
                                                   : lagrangian_rattle(s, w.layout_ptr()));
        drive([&](double target, double h) {
            stepper.step(w, h);
            w.time = target;
        });
    }
    r.log = monitor.log();
    return r;
}

const char* const kIntegrators[] = {"rk4", "midpoint", "rattle", "dopri", "cvode", "ida"};

} // namespace

// Bugs caught: the crossing rounded to the step (errors of dt), a root finder that stops
// early, the reset evaluated after the state moved on, a wrong sign of the reset, an event
// that fires twice at one impact (the guard still across after the reset), an event that
// never re-arms, and — with dt = 0.1 s, flights down to 7 ms — a ball that falls through
// the floor once its flight is shorter than a step (no re-arming inside the step).
TEST_CASE("Bouncing ball: every impact time (1e-10 s) and speed against the closed form, every integrator",
          "[codegen][events]") {
    const double g = 9.81, h = 1, e = 0.8, t1 = std::sqrt(2 * h / g), v1 = std::sqrt(2 * g * h);
    for (const char* integrator : kIntegrators)
        for (const double dt : {1e-3, 0.1}) {
            INFO(integrator << ", dt = " << dt);
            const Run r = run(bouncing_ball::system({}), integrator, 3.9, dt);
            // impacts before 3.9 s: t_{n+1} = t_n + 2 e^n v1/g
            std::vector<double> times;
            for (double t = t1, v = v1; t < 3.9; v *= e, t += 2 * v / g) times.push_back(t);
            REQUIRE(times.size() == 14);
            REQUIRE(r.log.size() == times.size());
            for (std::size_t n = 0; n < times.size(); ++n) {
                INFO("impact " << n);
                CHECK(std::fabs(r.log[n].time - times[n]) < 1e-10);
                const double speed = v1 * std::pow(e, static_cast<double>(n + 1)); // after the impact
                CHECK(std::fabs(r.log[n].qdot[0] - speed) < 1e-9 * v1);
                CHECK(std::fabs(r.log[n].q[0]) < 1e-9); // at the floor
                CHECK(r.log[n].event == 0);
            }
            CHECK(r.w.at(kGQ, 0) > -1e-9); // never below the floor
            CHECK(!r.stopped);
        }
}

// Bugs caught: the apex ratio e² (energy bookkeeping across resets) and identical inputs
// giving identical bits (determinism of the located times).
TEST_CASE("Bouncing ball: apex heights shrink by e^2, and the event log is bit-identical run to run", "[codegen][events]") {
    const Run a = run(bouncing_ball::system({}), "rk4", 3.5, 1e-3), b = run(bouncing_ball::system({}), "rk4", 3.5, 1e-3);
    REQUIRE(a.log.size() >= 8);
    REQUIRE(a.log.size() == b.log.size());
    for (std::size_t n = 0; n < a.log.size(); ++n) {
        CHECK(std::memcmp(&a.log[n].time, &b.log[n].time, sizeof(double)) == 0);
        CHECK(std::memcmp(a.log[n].qdot.data(), b.log[n].qdot.data(), sizeof(double)) == 0);
    }
    for (std::size_t n = 1; n < a.log.size(); ++n) {
        const double apex0 = a.log[n - 1].qdot[0] * a.log[n - 1].qdot[0] / (2 * 9.81);
        const double apex1 = a.log[n].qdot[0] * a.log[n].qdot[0] / (2 * 9.81);
        CHECK(apex1 / apex0 == Approx(0.64).epsilon(1e-9));
    }
}

// Bugs caught: located crossings on a nonlinear arc (a linear interpolation of the guard is
// off by the arc's curvature), the restitution applied to the angular velocity, the
// re-arming after each impact. Reference: the free pendulum's travel times, K and F.
TEST_CASE("Pendulum striking a wall: impact times against the elliptic integrals", "[codegen][events]") {
    const double w0 = std::sqrt(9.81), th0 = 1, wall = -0.3, e = 0.9;
    // from the amplitude a through 0 to the wall
    auto travel = [&](double a) {
        const double k = std::sin(a / 2);
        return (std::comp_ellint_1(k) + std::ellint_1(k, std::asin(std::sin(-wall / 2) / k))) / w0;
    };
    std::vector<double> times{travel(th0)};
    double a = th0;
    for (int n = 1; n < 6; ++n) {
        // speed at the wall from the energy at amplitude a, scaled by e; the new amplitude
        const double speed = std::sqrt(2 * w0 * w0 * (std::cos(wall) - std::cos(a))) * e;
        a = std::acos(std::cos(wall) - speed * speed / (2 * w0 * w0));
        times.push_back(times.back() + 2 * travel(a));
    }
    for (const char* integrator : {"rk4", "dopri", "cvode"}) {
        INFO(integrator);
        const Run r = run(pendulum_wall::system({}), integrator, times.back() + 0.01, 1e-4);
        REQUIRE(r.log.size() == times.size());
        for (std::size_t n = 0; n < times.size(); ++n) {
            INFO("impact " << n);
            CHECK(std::fabs(r.log[n].time - times[n]) < 1e-9);
            CHECK(std::fabs(r.log[n].q[0] - wall) < 1e-9);
        }
    }
}

// Bugs caught: `stop` ignored, the run ending at the step instead of the crossing, a `>`
// guard treated as `<`, a guard on a velocity.
TEST_CASE("stop ends the run at the crossing: a `>` guard on y, a guard on y'", "[codegen][events]") {
    const double g = 9.81, v0 = 10;
    for (const char* integrator : kIntegrators) {
        INFO(integrator);
        launch::Parameters P;
        Run r = run(launch::system(P), integrator, 5, 1e-3);
        REQUIRE(r.stopped);
        REQUIRE(r.log.size() == 1);
        CHECK(r.log[0].event == 0); // high
        const double t_high = (v0 - std::sqrt(v0 * v0 - 2 * g * 2)) / g;
        CHECK(std::fabs(r.w.time - t_high) < 1e-10);
        CHECK(std::fabs(r.w.at(kGQ, 0) - 2) < 1e-9);
        P.H = 100; // out of reach: the apex stops it
        r = run(launch::system(P), integrator, 5, 1e-3);
        REQUIRE(r.stopped);
        REQUIRE(r.log.size() == 1);
        CHECK(r.log[0].event == 1);
        CHECK(std::fabs(r.w.time - v0 / g) < 1e-10);
    }
}

// Bugs caught: one of two simultaneous events lost, or fired a step later; their resets
// mixed up; the second event's right side read after the first event's reset (b2 reads y1').
TEST_CASE("Simultaneous events fire together, each with its own reset", "[codegen][events]") {
    const Run r = run(two_balls::system({}), "rk4", 0.5, 1e-3);
    REQUIRE(r.log.size() == 2);
    CHECK(r.log[0].event == 0);
    CHECK(r.log[1].event == 1);
    CHECK(r.log[0].time == r.log[1].time);
    const double v1 = std::sqrt(2 * 9.81);
    CHECK(r.log[1].qdot[0] == Approx(0.8 * v1).epsilon(1e-12));
    CHECK(r.log[1].qdot[1] == Approx(0.5 * v1).epsilon(1e-12));
}

// Bug caught: the resets stored one by one, the second reading the first's result (both
// velocities end equal instead of swapped).
TEST_CASE("Every right side is read from the state before the event (velocities swap)", "[codegen][events]") {
    const Run r = run(swap::system({}), "rk4", 1.5, 1e-3);
    REQUIRE(r.log.size() == 1);
    CHECK(std::fabs(r.log[0].time - 1) < 1e-12);
    CHECK(r.w.at(kGV, 0) == 0);
    CHECK(r.w.at(kGV, 1) == 1);
}

// Bugs caught: an event re-firing while its guard stays across (mark every step), an event
// that never re-arms after a reset brings its guard back (wrap once only).
TEST_CASE("Re-arming: across after the actions, an event waits until its guard has crossed back", "[codegen][events]") {
    const Run r = run(wrap::system({}), "rk4", 5.2, 1e-3);
    // mark at 0.5, wrap at 1, mark at 2.5, wrap at 3, mark at 4.5, wrap at 5
    REQUIRE(r.log.size() == 6);
    for (std::size_t n = 0; n < 6; ++n) {
        INFO(n);
        CHECK(r.log[n].event == (n % 2 == 0 ? 1u : 0u));
        CHECK(std::fabs(r.log[n].time - (n % 2 == 0 ? 0.5 : 1.0) - 2.0 * static_cast<double>(n / 2)) < 1e-10);
    }
}

// Bugs caught: a Zeno run that hangs or loops forever (each impact closer than the last),
// the error not naming the event and time; the remedy not coming to rest, or sinking.
TEST_CASE("Zeno: the accumulation stops the run with an error, and the rest speed lets the ball come to rest",
          "[codegen][events]") {
    const double t_inf = 9 * std::sqrt(2 / 9.81); // (1 + 2e/(1 - e)) sqrt(2h/g), e = 0.8
    try {
        (void)run(bouncing_ball::system({}), "rk4", 6, 1e-3);
        FAIL("no ZenoError");
    } catch (const ZenoError& z) {
        const std::string what = z.what();
        CHECK(what.find("event 'bounce'") != std::string::npos);
        CHECK(what.find("4.06") != std::string::npos); // the time, and the estimate of t_inf = 4.0637
        INFO(what << " (t_inf = " << t_inf << ")");
        CHECK(what.find("Zeno") != std::string::npos);
    }
    for (const char* integrator : kIntegrators) {
        INFO(integrator);
        const Run r = run(bouncing_ball::system({}), integrator, 6, 1e-3, {.rest_speed = 0.05});
        CHECK(std::fabs(r.w.at(kGQ, 0)) < 1e-9);
        CHECK(r.w.at(kGV, 0) == 0);
        REQUIRE(!r.log.empty());
        CHECK(r.log.back().qdot[0] == 0);
        CHECK(r.log.back().time < t_inf);
    }
    // the per-step limit: a tiny one trips on the first step with two events
    CHECK_THROWS_AS(run(two_balls::system({}), "rk4", 0.5, 1e-3, {.max_events_per_step = 1}), ZenoError);
}

// Bugs caught: model events missing from the event layer's Phenomenon or stamped with the
// wrong tick, a pulse that stays raised (every later tick would report it), rules of the
// user's that cannot see the model's events, and a par that lets two rules write a model
// event's flag.
TEST_CASE("The model's events on the event layer: flags, a user's latch, the Phenomenon", "[codegen][events]") {
    const LagrangianSystem s = bouncing_ball::system({});
    Registry flags;
    const std::vector<Index> ev = add_event_flags(flags, s, "ball.");
    const Index landed = flags.add("landed");
    REQUIRE(flags.label(ev[0]) == "ball.bounce");
    FlagWorld fw(flags);
    // the user's rule: a latch raised by the first bounce, read before the model rule lowers it
    const EventRule latch{"latch", ComponentSet{landed}, ComponentSet{ev[0]},
                          [b = ev[0]](const FlagLit& in, std::span<std::uint8_t> out) {
                              if (in.lookup(b)) out[0] = 1;
                          },
                          nullptr};
    const EventRule model = model_events_rule("ball", s, ev);
    const EventWorkflow wf = EventWorkflow::seq(EventWorkflow::run(latch, fw), EventWorkflow::run(model, fw));
    const EventRule other{"other", ComponentSet{ev[0]}, {}, [](const FlagLit&, std::span<std::uint8_t>) {}, nullptr};
    CHECK_THROWS_AS(EventWorkflow::par(EventWorkflow::run(model, fw), EventWorkflow::run(other, fw)), DomainOverlapError);
    Interpreter<FlagWorld> layer(wf.process());
    Phenomenon phenomenon;
    World w = make_lagrangian_world(s);
    Stepper stepper(lagrangian_rk4(s, w.layout_ptr()));
    EventMonitor monitor(s);
    std::size_t cursor = 0;
    std::vector<std::uint64_t> ticks_of_bounces;
    bool latched_before_first = false;
    for (long k = 1; k <= 3500; ++k) {
        advance_with_events(monitor, w, static_cast<double>(k) * 1e-3, 1e-3, [&](double target, double h) {
            stepper.step(w, h);
            w.time = target;
        });
        const std::size_t before = cursor;
        cursor = signal_events(monitor, cursor, ev, fw);
        if (cursor > before) ticks_of_bounces.push_back(fw.tick);
        if (ticks_of_bounces.empty() && fw.flags.lookup(landed)) latched_before_first = true;
        layer.step(fw, 0, &phenomenon);
        CHECK(!fw.flags.lookup(ev[0])); // a pulse: lowered at the tick it was raised
    }
    CHECK(!latched_before_first);
    CHECK(fw.flags.lookup(landed));
    REQUIRE(monitor.log().size() == 9);
    REQUIRE(phenomenon.size() == 9);
    for (std::size_t n = 0; n < 9; ++n) {
        CHECK(phenomenon[n].tick == ticks_of_bounces[n] + 1); // the second rule of a seq: one tick after the first
        CHECK(phenomenon[n].component == ev[0]);
        CHECK(phenomenon[n].what == "bounce fired");
    }
}
