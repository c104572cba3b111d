// Locating event crossings (simulate/detail/crossing.hpp): the Illinois root finder against closed
// forms, and the continuous extensions of a step (Hermite, Dormand–Prince dense output)
// against the exact harmonic oscillator.
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/integrators/dormand_prince.hpp"
#include "phynjo/runtime/simulate/detail/crossing.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>
#include <vector>

using namespace phynjo::runtime;

// Bugs caught: regula falsi without the Illinois halving (one end never moves: the bracket
// does not close, or only after many more evaluations), the bracket updated on the wrong
// side, `time` taken from the side not yet across, an endpoint root missed.
TEST_CASE("locate_crossing: the Illinois method closes the bracket to 1e-12 in few evaluations", "[runtime][events]") {
    const double root = std::acos(0.3);
    auto g = [](double t) { return std::cos(t) - 0.3; };
    const Crossing c = locate_crossing(g, 0.0, 2.0, g(0.0), g(2.0));
    CHECK(c.hi - c.lo <= 1e-12);
    CHECK(c.lo <= root + 1e-15);
    CHECK(c.hi >= root - 1e-15);
    CHECK(c.time == c.hi);
    CHECK(g(c.time) <= 0); // across: the guard went from + to −
    CHECK(c.evaluations <= 10); // Illinois: 8; plain regula falsi with the bisection fallback: 15; bisection alone: 41
    // the other direction (− to +), the root near an end
    auto h = [](double t) { return t * t * t - 1e-3; };
    const Crossing d = locate_crossing(h, 0.0, 5.0, h(0.0), h(5.0));
    CHECK(d.hi - d.lo <= 1e-12);
    CHECK(std::fabs(d.time - 0.1) <= 1e-12);
    CHECK(h(d.time) >= 0);
    // a root at an end is the crossing, found without evaluating
    CHECK(locate_crossing(g, root, 2.0, 0.0, g(2.0)).time == root);
    CHECK(locate_crossing(g, 0.0, 2.0, g(0.0), 0.0).evaluations == 0);
}

// Bugs caught: no bisection fallback (a triple root keeps Illinois slow), no stop when the
// bracket is two adjacent doubles (a crossing at t ≈ 1e6 would spin to max_evaluations).
TEST_CASE("locate_crossing: flat roots, large times, and bad brackets", "[runtime][events]") {
    auto flat = [](double t) { return std::pow(t - 0.3, 3); };
    const Crossing c = locate_crossing(flat, 0.0, 1.0, flat(0.0), flat(1.0));
    CHECK(c.hi - c.lo <= 1e-12);
    CHECK(std::fabs(c.time - 0.3) <= 1e-12);
    CHECK(c.evaluations <= 200);
    const double T = 1e6 + 0.123456789;
    auto late = [T](double t) { return T - t; };
    const Crossing d = locate_crossing(late, 1e6, 1e6 + 1, late(1e6), late(1e6 + 1));
    CHECK(std::fabs(d.time - T) <= 2e-10); // one ulp of 1e6 is 1.2e-10
    CHECK(d.evaluations < 200);
    auto g = [](double t) { return t + 1; };
    CHECK_THROWS_AS(locate_crossing(g, 0.0, 1.0, g(0.0), g(1.0)), std::invalid_argument); // no sign change
    CHECK_THROWS_AS(locate_crossing(g, 1.0, 0.0, -1.0, 1.0), std::invalid_argument);      // a > b
    auto nan_inside = [](double t) { return t < 0.4 ? 1.0 : t < 0.6 ? std::nan("") : -1.0; };
    CHECK_THROWS_AS(locate_crossing(nan_inside, 0.0, 1.0, 1.0, -1.0), ConvergenceError);
}

// Bugs caught: a wrong Hermite basis (h10 and h01 swapped), the step h missing from the
// derivative terms, v interpolated from (q, v) instead of (v, a); and the order: the error
// over a step must fall 16-fold when h halves (O(h⁴)).
TEST_CASE("HermiteStep: exact ends, fourth-order accurate between them (harmonic oscillator)", "[runtime][events]") {
    // q = cos t, v = −sin t, a = −cos t
    auto max_error = [](double t0, double h) {
        const double t1 = t0 + h;
        const std::vector<double> q0{std::cos(t0)}, v0{-std::sin(t0)}, a0{-std::cos(t0)}, q1{std::cos(t1)}, v1{-std::sin(t1)},
            a1{-std::cos(t1)};
        const HermiteStep s(t0, t1, q0, v0, a0, q1, v1, a1);
        double worst = 0, q[1], v[1];
        for (int k = 0; k <= 64; ++k) {
            const double t = k == 64 ? t1 : t0 + h * k / 64.0;
            s.at(t, q, v);
            worst = std::max({worst, std::fabs(q[0] - std::cos(t)), std::fabs(v[0] + std::sin(t))});
        }
        return worst;
    };
    for (double t0 : {0.0, 0.4, 2.1}) {
        INFO("t0 = " << t0);
        const double e1 = max_error(t0, 0.2), e2 = max_error(t0, 0.1), e3 = max_error(t0, 0.05);
        CHECK(e1 < 1e-4);
        CHECK(e1 / e2 == Approx(16).margin(3));
        CHECK(e2 / e3 == Approx(16).margin(3));
    }
    const std::vector<double> q0{1.0, 2.0}, v0{0.5, -1.0}, a0{0.1, 0.2}, q1{1.2, 1.9}, v1{0.4, -0.9}, a1{0.0, 0.3};
    const HermiteStep s(1.0, 1.5, q0, v0, a0, q1, v1, a1);
    double q[2], v[2];
    s.at(1.0, q, v);
    CHECK((q[0] == 1.0 && q[1] == 2.0 && v[0] == 0.5 && v[1] == -1.0));
    s.at(1.5, q, v);
    CHECK((q[0] == 1.2 && q[1] == 1.9 && v[0] == 0.4 && v[1] == -0.9));
    CHECK_THROWS_AS(s.at(1.6, q, v), std::invalid_argument);
    CHECK_THROWS_AS(HermiteStep(1.0, 1.0, q0, v0, a0, q1, v1, a1), std::invalid_argument);
}

// Bugs caught: a wrong constant of Shampine's dense output (its order drops: the error
// halves with h instead of falling 32-fold), the stages mixed up (k7 for k6), the output
// not exact at the step's ends, the step's start forgotten after a rejected trial.
TEST_CASE("Dormand-Prince dense output: exact at the ends, local error O(h^5) between them", "[runtime][events]") {
    LagrangianSystem s; // q'' = -q: q = cos t, q' = -sin t
    s.dof = 1;
    s.coordinate_names = {"x"};
    s.accelerations = [](double, std::span<const double> q, std::span<const double>, std::span<double> a) { a[0] = -q[0]; };
    s.initial_state = [](std::span<double> q, std::span<double> v) {
        q[0] = 1;
        v[0] = 0;
    };
    auto error_at_mid = [&](double h) {
        DormandPrince45 dp(s, {.rtol = 1, .atol = 1, .dt_min = 1e-12, .dt_max = 1}); // loose: every step accepted
        World w = make_lagrangian_world(s);
        CHECK_THROWS_AS(dp.dense(0, std::span<double>(), std::span<double>()), std::logic_error);
        REQUIRE(dp.step(w, h, 1.0) == h);
        double q = 0, v = 0;
        dp.dense(0, {&q, 1}, {&v, 1});
        CHECK(q == 1); // exactly y0 at the start
        CHECK(v == 0);
        dp.dense(h, {&q, 1}, {&v, 1});
        CHECK(std::fabs(q - w.at(kGQ, 0)) < 1e-15); // and y1 at the end
        CHECK(std::fabs(v - w.at(kGV, 0)) < 1e-15);
        CHECK_THROWS_AS(dp.dense(2 * h, {&q, 1}, {&v, 1}), std::invalid_argument);
        double worst = 0;
        for (double th : {0.25, 0.5, 0.75}) {
            dp.dense(th * h, {&q, 1}, {&v, 1});
            worst = std::max({worst, std::fabs(q - std::cos(th * h)), std::fabs(v + std::sin(th * h))});
        }
        return worst;
    };
    const double e1 = error_at_mid(0.2), e2 = error_at_mid(0.1);
    INFO("errors " << e1 << ", " << e2);
    CHECK(e1 < 1e-6);
    CHECK(e1 / e2 > 25); // 2^5 = 32 for a local error O(h^5)
}
