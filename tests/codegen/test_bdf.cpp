// phynjo's own BDF for generated models (integrators/bdf.hpp): against RK4 at tight
// tolerances, the error falling with the tolerance, the stiff chain in few steps with one
// Jacobian and a tridiagonal Schur complement, determinism, the workflow, restarts, and bad
// input and failures as the runtime's typed errors.
#include "cartesian_pendulum.hpp"
#include "double_pendulum.hpp"
#include "driven.hpp"
#include "spherical_pendulum.hpp"
#include "stiff_chain.hpp"

#include "rk4_reference.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

using namespace phynjo::runtime;
using test::difference;
using test::rk4_reference;

namespace {

World run_bdf(const LagrangianSystem& s, double t_end, int calls, Bdf::Options o, Bdf::Stats* stats = nullptr) {
    World w = make_lagrangian_world(s);
    Bdf bdf(s, o);
    for (int k = 1; k <= calls; ++k) bdf.advance(w, t_end * k / calls);
    if (stats) *stats = bdf.stats();
    return w;
}

bool same_bits(const World& a, const World& b, std::size_t n) {
    for (auto f : {kGQ, kGV})
        for (std::size_t i = 0; i < n; ++i)
        {
            const double x = a.at(f, static_cast<Index>(i)), y = b.at(f, static_cast<Index>(i));
            if (std::memcmp(&x, &y, sizeof(double)) != 0) return false;
        }
    return a.time == b.time;
}

} // namespace

// Bugs caught: a wrong NDF coefficient (κ, γ or α: the corrector solves another formula and
// the error is O(h) whatever the tolerance), the differences rescaled wrongly when the step
// changes (R or U of change_D), the interpolant at t_end between steps, the history lost
// across calls, the order never raised (hundreds of times more steps at 1e-12).
TEST_CASE("Bdf = RK4 at tight tolerances (double pendulum 2 s, driven model with inputs and t)", "[codegen][bdf]") {
    for (const LagrangianSystem& s : {double_pendulum::system({}), driven::system({})}) {
        INFO(s.coordinate_names[0]);
        const World ref = rk4_reference(s, 2.0, 1e-4);
        Bdf::Stats st;
        const World w = run_bdf(s, 2.0, 20, {.rtol = 1e-12, .atol = 1e-12}, &st); // 20 calls: the history carries over
        CHECK(w.time == 2.0);
        CHECK(difference(w, ref, s.dof) < 1e-8);
        INFO(st.steps << " steps, order " << st.order);
        CHECK(st.steps < 3000);
        CHECK(st.order >= 4); // smooth solutions: the high orders pay
        CHECK(st.jacobian_evaluations >= 1);
        CHECK(st.newton_failures == 0);
    }
}

// Bug caught: an error estimate that does not control the error (a wrong error constant, the
// weights of the wrong y): the error must fall with the tolerance, by at least 100 over
// four decades.
TEST_CASE("Bdf: the error falls with the tolerance (double pendulum 2 s)", "[codegen][bdf]") {
    const LagrangianSystem s = double_pendulum::system({});
    const World ref = rk4_reference(s, 2.0, 1e-4);
    double previous = std::numeric_limits<double>::infinity(), first = 0, last = 0;
    for (const double rtol : {1e-5, 1e-7, 1e-9}) {
        const double e = difference(run_bdf(s, 2.0, 1, {.rtol = rtol, .atol = rtol * 1e-2}), ref, s.dof);
        INFO("rtol " << rtol << ": error " << e);
        CHECK(e < previous);
        CHECK(e < 1e4 * rtol);
        previous = e;
        (first == 0 ? first : last) = e;
    }
    CHECK(last < first / 100);
}

// Bugs caught: a wrong Jacobian or Newton matrix (on a stiff model Newton needs the right J:
// failures, re-evaluations, tiny steps), the band of S misread (the chain's S is
// tridiagonal), the convergence test accepting unconverged corrections (the solution drifts
// from RK4 at its stability limit).
TEST_CASE("Bdf on the stiff chain: few steps, one Jacobian, a tridiagonal S, = RK4 (dt = 0.1 ms)", "[codegen][bdf]") {
    const LagrangianSystem s = stiff_chain::system({});
    const World ref = rk4_reference(s, 20.0, 1e-4);
    Bdf::Stats st;
    const World w = run_bdf(s, 20.0, 1, {.rtol = 1e-8, .atol = 1e-10}, &st);
    INFO(st.steps << " steps, " << st.newton_iterations << " Newton iterations, " << st.jacobian_evaluations << " Jacobians");
    CHECK(st.steps < 1000); // RK4 needs 200 000 here
    CHECK(st.newton_failures == 0);
    CHECK(st.jacobian_evaluations == 1); // the chain is linear: J never goes stale
    CHECK(st.newton_iterations < 2 * st.steps);
    CHECK(st.lower_bandwidth == 1);
    CHECK(st.upper_bandwidth == 1);
    CHECK(difference(w, ref, s.dof) < 1e-5); // CVODE's bound at these tolerances (test_cvode)
    const World tight = run_bdf(s, 20.0, 1, {.rtol = 1e-11, .atol = 1e-13});
    CHECK(difference(tight, ref, s.dof) < 1e-8);
}

// Bugs caught: state kept between runs that is not the world's (a second solver differs), the
// workflow rule advancing the time twice, a world changed between steps not restarting the
// history (the old differences applied to a new state).
TEST_CASE("Bdf: bit-for-bit deterministic, the workflow(\"bdf\") = the solver, restarts on a changed world", "[codegen][bdf]") {
    const double_pendulum::Parameters P;
    const LagrangianSystem s = double_pendulum::system(P);
    CHECK(same_bits(run_bdf(s, 3.0, 30, {}), run_bdf(s, 3.0, 30, {}), 2));
    World a = double_pendulum::make_world(P), b = a;
    Stepper st(double_pendulum::workflow(P, a, "bdf"));
    for (int k = 0; k < 10; ++k) st.step(a, 0.1);
    Bdf bdf(s, {});
    // the targets the rule computes, t + dt with t = (k − 1) dt the Stepper's time; one history
    // throughout (the Stepper's time differs from the solver's by an ulp: no restart)
    for (int k = 1; k <= 10; ++k) bdf.advance(b, (k - 1) * 0.1 + 0.1);
    CHECK(std::fabs(a.time - 1.0) < 1e-15);
    CHECK(difference(a, b, 2) == 0);
    a.at(kGV, 0) = 0.5; // by hand: the next step starts afresh from it, as a new solver would
    World c = a;
    st.step(a, 0.1);
    Bdf fresh(s, {});
    fresh.advance(c, c.time + 0.1);
    CHECK(difference(a, c, 2) == 0);
}

// Bugs caught: a silent NaN (a right side that turns non-finite accepted as a step), a model's
// exception lost or the world left mid-step, max_steps ignored (a hang), bad options or a
// constrained model accepted.
TEST_CASE("Bdf: errors are the runtime's typed errors, at the time reached", "[codegen][bdf]") {
    const LagrangianSystem sp = spherical_pendulum::system({});
    World w = make_lagrangian_world(sp);
    w.at(kGQ, 0) = 0; // the pole: M singular
    Bdf pole(sp, {});
    CHECK_THROWS_AS(pole.advance(w, 1.0), SingularMassMatrix);
    CHECK(w.time == 0);
    CHECK_THROWS_AS((Bdf(sp, {.rtol = -1})), std::invalid_argument);
    CHECK_THROWS_AS((Bdf(sp, {.max_step = 0})), std::invalid_argument);
    CHECK_THROWS_AS((Bdf(cartesian_pendulum::system({}), {})), std::invalid_argument); // constraints: Cvode or Ida
    LagrangianSystem no_jacobian = sp;
    no_jacobian.rhs_jacobian = nullptr;
    CHECK_THROWS_AS((Bdf(no_jacobian, {})), std::invalid_argument);
    const LagrangianSystem dp = double_pendulum::system({});
    {
        World d = make_lagrangian_world(dp);
        d.time = 1;
        Bdf back(dp, {});
        CHECK_THROWS_AS(back.advance(d, 0.5), std::invalid_argument);
    }
    {
        World d = make_lagrangian_world(dp);
        Bdf tight(dp, {.rtol = 1e-12, .atol = 1e-14, .max_steps = 10});
        try {
            tight.advance(d, 5.0);
            FAIL("expected a ConvergenceError");
        } catch (const ConvergenceError& e) {
            CHECK(std::string(e.what()).find("max_steps") != std::string::npos);
            CHECK(d.time > 0);
            CHECK(d.time < 5.0);
        }
    }
    {
        LagrangianSystem nan_after = dp; // accelerations NaN from t = 0.5 s on
        auto acc = dp.accelerations;
        nan_after.accelerations = [acc](double t, std::span<const double> q, std::span<const double> v, std::span<double> a) {
            acc(t, q, v, a);
            if (t > 0.5) a[0] = std::numeric_limits<double>::quiet_NaN();
        };
        World d = make_lagrangian_world(nan_after);
        Bdf bdf(nan_after, {});
        CHECK_THROWS_AS(bdf.advance(d, 1.0), ConvergenceError);
        CHECK(d.time <= 0.5);
        CHECK(d.time > 0.4);
        for (auto f : {kGQ, kGV})
            for (Index i = 0; i < 2; ++i) CHECK(std::isfinite(d.at(f, i)));
    }
}
