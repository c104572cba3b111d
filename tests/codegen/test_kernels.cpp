// Generated code's fused kernels (rk4_step, accelerations_energy_guards, rk4_step_values) and
// run_one's path over them, against the functions and the generic paths they replace, bit
// for bit: they are an optimization only, never a different answer.
// Bugs caught: a stage of the fused RK4 with another weight, time or order of operations than
// lagrangian_rk4's; accelerations_energy_guards computing q'', E or a guard by another
// expression (another CSE pass, another summation order) than the functions; a kernel that
// throws where accelerations returns or returns where it throws; run_one's fused path reusing
// the q'' of the state before an event's reset or a resting event's hold, skipping the
// accelerations' exception, evaluating at another time than the workflow, or ending a step,
// a stop, a failure or a trajectory differently from the workflow's path.
#include "bouncing_ball.hpp"
#include "cartesian_pendulum.hpp"
#include "coupled_balls.hpp"
#include "double_pendulum.hpp"
#include "driven.hpp"
#include "flip_pendulum.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "triple_pendulum.hpp"
#include "two_balls.hpp"

#include "phynjo/runtime/simulate/ensemble.hpp"
#include "same_bits.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace phynjo::runtime;
using phynjo::test::same_bits;
using phynjo::test::same_summary;

namespace {


/// The system without the fused kernels: the integrators and run_one take their generic paths.
LagrangianSystem generic(LagrangianSystem s) {
    s.rk4_step = nullptr;
    s.accelerations_energy_guards = nullptr;
    s.rk4_step_values = nullptr;
    return s;
}

/// One step of `workflow` from (t, q, q') on a fresh world of `s`.
std::pair<std::vector<double>, std::vector<double>> workflow_step(const LagrangianSystem& s, bool kernels, double t,
                                                                  const std::vector<double>& q,
                                                                  const std::vector<double>& v, double h) {
    World w = make_lagrangian_world(s);
    std::copy(q.begin(), q.end(), w.field(kGQ).begin());
    std::copy(v.begin(), v.end(), w.field(kGV).begin());
    w.time = t;
    Stepper stepper(lagrangian_rk4(kernels ? s : generic(s), w.layout_ptr()));
    stepper.step(w, h);
    return {std::vector<double>(w.field(kGQ).begin(), w.field(kGQ).end()),
            std::vector<double>(w.field(kGV).begin(), w.field(kGV).end())};
}

/// At random states of model NS: the kernels against the functions and the generic RK4 step.
#define PHYNJO_KERNELS_AGREE(NS)                                                                                       \
    do {                                                                                                               \
        namespace M = NS;                                                                                              \
        INFO(#NS);                                                                                                     \
        const M::Parameters P{};                                                                                       \
        const LagrangianSystem s = M::system(P);                                                                       \
        REQUIRE(s.rk4_step);                                                                                           \
        REQUIRE(s.accelerations_energy_guards);                                                                        \
        REQUIRE(s.rk4_step_values);                                                                                    \
        constexpr std::size_t n = M::dof, ne = M::n_events;                                                            \
        std::mt19937_64 rng(20261202);                                                                                 \
        std::uniform_real_distribution<double> d(-1.0, 1.0);                                                           \
        for (int k = 0; k < 40; ++k) {                                                                                 \
            std::vector<double> q(n), v(n);                                                                            \
            for (auto& x : q) x = d(rng);                                                                              \
            for (auto& x : v) x = d(rng);                                                                              \
            const double t = 0.5 * (1 + d(rng)), h = 0.01 * (1.5 + d(rng));                                             \
            if (M::n_constraints > 0) M::initial_state(P, q, v); /* a consistent state */                              \
            /* accelerations_energy_guards = accelerations, energy, event_guards */                                    \
            std::vector<double> a(n), g(ne), a2(n), g2(ne);                                                            \
            M::accelerations(P, t, q, v, a);                                                                           \
            M::event_guards(P, t, q, v, g);                                                                            \
            double E2 = 0;                                                                                             \
            CHECK(M::accelerations_energy_guards(P, t, q, v, a2, E2, g2));                                             \
            CHECK(same_bits(a, a2));                                                                                   \
            CHECK(same_bits(g, g2));                                                                                   \
            CHECK(same_bits(M::energy(P, t, q, v), E2));                                                               \
            /* rk4_step = lagrangian_rk4's step (the generic rule; constrained: before the projection) */              \
            const auto [qg, vg] = workflow_step(s, false, t, q, v, h);                                                 \
            const auto [qk, vk] = workflow_step(s, true, t, q, v, h);                                                  \
            CHECK(same_bits(qg, qk));                                                                                  \
            CHECK(same_bits(vg, vk));                                                                                  \
            std::vector<double> q1 = q, v1 = v;                                                                        \
            M::rk4_step(P, t, h, q1, v1, a);                                                                           \
            if (M::n_constraints == 0) {                                                                               \
                CHECK(same_bits(qg, q1));                                                                              \
                CHECK(same_bits(vg, v1));                                                                              \
            }                                                                                                          \
            /* rk4_step_values = rk4_step, then accelerations_energy_guards at t1 */                                   \
            std::vector<double> q3 = q, v3 = v, a3 = a, g3(ne), a4(n), g4(ne);                                         \
            double E3 = 0, E4 = 0;                                                                                     \
            const double t1 = t + h;                                                                                   \
            const bool ok3 = M::rk4_step_values(P, t, h, t1, q3, v3, a3, E3, g3);                                      \
            const bool ok4 = M::accelerations_energy_guards(P, t1, q1, v1, a4, E4, g4);                                \
            CHECK(ok3 == ok4);                                                                                         \
            CHECK(same_bits(q3, q1));                                                                                  \
            CHECK(same_bits(v3, v1));                                                                                  \
            CHECK(same_bits(a3, a4));                                                                                  \
            CHECK(same_bits(E3, E4));                                                                                  \
            CHECK(same_bits(g3, g4));                                                                                  \
        }                                                                                                              \
    } while (0)

/// run_one on the kernels and on the workflow: the same summary and trajectory.
RunSummary same_runs(const LagrangianSystem& s, std::vector<std::pair<std::size_t, double>> q0,
                     std::vector<std::pair<std::size_t, double>> v0, const RunSettings& settings) {
    REQUIRE(s.rk4_step_values);
    std::string ta, tb;
    const RunSummary a = run_one(s, q0, v0, settings, &ta);
    const RunSummary b = run_one(generic(s), q0, v0, settings, &tb);
    same_summary(a, b);
    CHECK(ta == tb);
    return a;
}

} // namespace

TEST_CASE("fused kernels: rk4_step, accelerations_energy_guards and rk4_step_values give the functions' bits",
          "[kernels]") {
    PHYNJO_KERNELS_AGREE(pendulum);           // 1×1 M
    PHYNJO_KERNELS_AGREE(double_pendulum);    // 2×2 closed form
    PHYNJO_KERNELS_AGREE(flip_pendulum);      // 2×2, four guards
    PHYNJO_KERNELS_AGREE(triple_pendulum);    // LDLᵀ
    PHYNJO_KERNELS_AGREE(nlink_cart_5);       // LDLᵀ, 6 coordinates
    PHYNJO_KERNELS_AGREE(two_balls);          // diagonal M, guards with resets
    PHYNJO_KERNELS_AGREE(driven);             // time and inputs in the forces
    PHYNJO_KERNELS_AGREE(cartesian_pendulum); // constrained: the KKT solve per stage, then the projection
    PHYNJO_KERNELS_AGREE(bouncing_ball);
    PHYNJO_KERNELS_AGREE(coupled_balls);
}

TEST_CASE("fused kernels: accelerations_energy_guards returns false exactly where accelerations throws",
          "[kernels]") {
    const std::vector<double> q{2.0, -1.0}, v{0.5, 0.25};
    std::vector<double> a(2), g(4), g2(4);
    double E = 0;
    // M singular: no second bob (m2 = 0 leaves its row of M zero)
    flip_pendulum::Parameters massless;
    massless.m2 = 0;
    CHECK_THROWS_AS(flip_pendulum::accelerations(massless, 0, q, v, a), SingularMassMatrix);
    CHECK_FALSE(flip_pendulum::accelerations_energy_guards(massless, 0, q, v, a, E, g));
    flip_pendulum::event_guards(massless, 0, q, v, g2);
    CHECK(same_bits(g, g2)); // E and the guards are set all the same
    CHECK(same_bits(E, flip_pendulum::energy(massless, 0, q, v)));
    // a non-finite result: velocities whose squares overflow
    const std::vector<double> fast{1e200, -1e200};
    CHECK_THROWS_AS(flip_pendulum::accelerations({}, 0, q, fast, a), NonFiniteResult);
    CHECK_FALSE(flip_pendulum::accelerations_energy_guards({}, 0, q, fast, a, E, g));
    // LDLᵀ: M singular (massless bobs)
    triple_pendulum::Parameters none;
    none.m1 = none.m2 = none.m3 = 0;
    const std::vector<double> q3{0.1, 0.2, 0.3}, v3{0, 0, 0};
    std::vector<double> a3(3), g3;
    CHECK_THROWS_AS(triple_pendulum::accelerations(none, 0, q3, v3, a3), Error);
    CHECK_FALSE(triple_pendulum::accelerations_energy_guards(none, 0, q3, v3, a3, E, g3));
    CHECK(triple_pendulum::accelerations_energy_guards({}, 0, q3, v3, a3, E, g3));
    // and rk4_step throws what accelerations throws, the stage where it did in q and q'
    std::vector<double> qs = q, vs = fast, k{0, 0};
    CHECK_THROWS_AS(flip_pendulum::rk4_step({}, 0, 0.01, qs, vs, k), NonFiniteResult);
}

TEST_CASE("run_one on the fused kernels: the summary and trajectory of the workflow's path, bit for bit",
          "[kernels][ensemble]") {
    RunSettings settings;
    settings.every = 7;
    SECTION("the flip map: flips (stop events) and runs to the end") {
        settings.t_end = 3;
        int stopped = 0, finished = 0;
        for (double th1 = -3; th1 <= 3; th1 += 1.2)
            for (double th2 = -3; th2 <= 3; th2 += 1.5) {
                const RunSummary r = same_runs(flip_pendulum::system({}), {{0, th1}, {1, th2}}, {}, settings);
                stopped += r.status == RunSummary::Status::stopped;
                finished += r.status == RunSummary::Status::finished;
            }
        CHECK(stopped > 3); // both kinds compared
        CHECK(finished > 3);
    }
    SECTION("events with resets: a bouncing ball, chattering to Zeno and resting on the floor") {
        settings.t_end = 6;
        CHECK(same_runs(bouncing_ball::system({}), {}, {}, settings).status == RunSummary::Status::failed); // Zeno
        settings.events.rest_speed = 0.05;
        CHECK(same_runs(bouncing_ball::system({}), {}, {}, settings).status == RunSummary::Status::finished);
        settings.events.rest_speed = 0;
        settings.t_end = 2.5;
        same_runs(two_balls::system({}), {}, {{1, 1.5}}, settings); // one reset writes the other's velocity
        // one ball held on the floor while the other, pulled by the spring between them, bounces
        settings.t_end = 8;
        settings.events.rest_speed = 0.3;
        same_runs(coupled_balls::system({}), {}, {}, settings);
    }
    SECTION("no events, a last step shorter than dt, time-dependent forces") {
        settings.t_end = 2.355;
        settings.dt = 0.01;
        same_runs(pendulum::system({}), {{0, 2.5}}, {}, settings);
        same_runs(driven::system({}), {}, {{0, 0.3}}, settings);
        same_runs(triple_pendulum::system({}), {{1, 1.0}}, {}, settings);
    }
    SECTION("failures: singular at the start, non-finite along the way") {
        settings.t_end = 1;
        flip_pendulum::Parameters massless;
        massless.m2 = 0;
        const RunSummary r = same_runs(flip_pendulum::system(massless), {}, {}, settings);
        CHECK(r.status == RunSummary::Status::failed);
        CHECK_THAT(r.reason, Catch::Contains("singular"));
        const RunSummary f = same_runs(flip_pendulum::system({}), {}, {{0, 1e160}}, settings);
        CHECK(f.status == RunSummary::Status::failed);
    }
}
