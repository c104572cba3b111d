// SUNDIALS CVODE for generated models (integrators/cvode.hpp): against RK4 at tight
// tolerances, with the exact Jacobian and with CVODE's difference quotients, constraints
// kept by its projection, errors as the runtime's typed errors, restarts.
#include "cartesian_pendulum.hpp"
#include "double_pendulum.hpp"
#include "driven.hpp"
#include "four_bar.hpp"
#include "spherical_pendulum.hpp"
#include "stiff_chain.hpp"

#include "rk4_reference.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace phynjo::runtime;
using test::difference;
using test::rk4_reference;


// Bugs caught: a wrong right side (q' and q'' swapped), the Jacobian's layout (row-major
// handed to CVODE's column-major matrix: Newton then diverges or crawls), the interpolated
// output at the end of a call, the continuation across calls; with either linear solver
// (block elimination of q' = v, SUNDIALS' dense LU) and with difference quotients.
TEST_CASE("CVODE = RK4 at tight tolerances (double pendulum 2 s, driven model with inputs and t)", "[codegen][cvode]") {
    using Solver = Cvode::Options::LinearSolver;
    struct Variant {
        bool exact;
        Solver solver;
    };
    for (const LagrangianSystem& s : {double_pendulum::system({}), driven::system({})}) {
        INFO(s.coordinate_names[0]);
        const World ref = rk4_reference(s, 2.0, 1e-4);
        for (const Variant v : {Variant{true, Solver::second_order}, Variant{true, Solver::dense}, Variant{false, Solver::dense}}) {
            INFO("exact " << v.exact << ", solver " << static_cast<int>(v.solver));
            World w = make_lagrangian_world(s);
            Cvode cv(s, {.rtol = 1e-12, .atol = 1e-12, .exact_jacobian = v.exact, .linear_solver = v.solver});
            for (int k = 1; k <= 20; ++k) cv.advance(w, 0.1 * k); // 20 calls: the history carries over
            CHECK(w.time == 2.0);
            CHECK(difference(w, ref, s.dof) < 1e-8);
            const auto st = cv.stats();
            CHECK(st.steps > 0);
            if (v.exact) {
                CHECK(st.jacobian_evaluations > 0);
                CHECK(st.difference_quotient_rhs == 0); // the exact Jacobian, not difference quotients
                CHECK(st.newton_failures == 0);         // and a right one: Newton converges at every step
            } else
                CHECK(st.difference_quotient_rhs > 0);
        }
    }
}

// Bug caught: CVODE on the index-1 equations without the projection: the Cartesian pendulum's
// rod length drifts; a projection correction with the wrong sign.
TEST_CASE("CVODE keeps the constraints (projection): Cartesian pendulum, four-bar over 10 s", "[codegen][cvode]") {
    for (const LagrangianSystem& s : {cartesian_pendulum::system({}), four_bar::system({})}) {
        World w = make_lagrangian_world(s);
        Cvode cv(s, {.rtol = 1e-8, .atol = 1e-10});
        double worst = 0;
        for (int k = 1; k <= 100; ++k) {
            cv.advance(w, 0.1 * k);
            worst = std::max(worst, worst_constraint_violation(s, w.time, w.field(kGQ), w.field(kGV)).scaled);
        }
        INFO(s.coordinate_names[0]);
        CHECK(worst < 1e-10);
        CHECK(s.energy(w.time, w.field(kGQ), w.field(kGV)) ==
              Approx(s.energy(0, make_lagrangian_world(s).field(kGQ), make_lagrangian_world(s).field(kGV))).epsilon(1e-5));
    }
}

// Bugs caught: an exception thrown through CVODE's C code (undefined behaviour), a NaN
// state returned as if fine, the time reached lost.
TEST_CASE("CVODE: errors are the runtime's typed errors, at the time reached", "[codegen][cvode]") {
    const LagrangianSystem s = spherical_pendulum::system({});
    World w = make_lagrangian_world(s);
    w.at(kGQ, 0) = 0; // the pole: M = diag(m l^2, m l^2 sin(th)^2) is singular
    Cvode cv(s, {});
    CHECK_THROWS_AS(cv.advance(w, 1.0), SingularMassMatrix);
    CHECK(w.time == 0);
    CHECK_THROWS_AS((Cvode(s, {.rtol = -1})), std::invalid_argument);
    LagrangianSystem no_jacobian = s;
    no_jacobian.rhs_jacobian = nullptr;
    CHECK_THROWS_AS((Cvode(no_jacobian, {})), std::invalid_argument);
    // too few internal steps allowed: a ConvergenceError naming CVODE's flag and the time
    World d = make_lagrangian_world(double_pendulum::system({}));
    Cvode tight(double_pendulum::system({}), {.rtol = 1e-12, .atol = 1e-14, .max_steps = 10});
    try {
        tight.advance(d, 5.0);
        FAIL("expected a ConvergenceError");
    } catch (const ConvergenceError& e) {
        CHECK(std::string(e.what()).find("CV_TOO_MUCH_WORK") != std::string::npos);
        CHECK(d.time > 0);
        CHECK(d.time < 5.0);
    }
}

// Bugs caught: the workflow rule advancing the time twice, a world changed between steps not
// restarting the solver (the old history applied to a new state).
TEST_CASE("CVODE as a workflow: the generated workflow(\"cvode\"), restarts on a changed world", "[codegen][cvode]") {
    const double_pendulum::Parameters P;
    World a = double_pendulum::make_world(P), b = a;
    Stepper st(double_pendulum::workflow(P, a, "cvode"));
    for (int k = 0; k < 10; ++k) st.step(a, 0.1);
    Cvode cv(double_pendulum::system(P), {});
    // the targets the rule computes, t + dt with t = (k − 1) dt the Stepper's time; one history
    // throughout (the Stepper's time differs from the solver's by an ulp: no restart)
    for (int k = 1; k <= 10; ++k) cv.advance(b, (k - 1) * 0.1 + 0.1);
    CHECK(std::fabs(a.time - 1.0) < 1e-15);
    CHECK(difference(a, b, 2) == 0); // the same solver, the same calls: bit for bit
    // change the state by hand: the next step starts afresh from it, as a new solver would
    a.at(kGV, 0) = 0.5;
    World c = a;
    st.step(a, 0.1);
    Cvode fresh(double_pendulum::system(P), {});
    fresh.advance(c, c.time + 0.1);
    CHECK(difference(a, c, 2) == 0);
}

// Bugs caught: a wrong Jacobian handed to CVODE (transposed, a block misplaced). On a
// non-stiff model Newton converges with almost any matrix (I − γJ with γ small); on a stiff
// one it needs the right J: the stiff chain takes 677 steps without a Newton failure, and
// agrees with RK4 at its stability limit.
TEST_CASE("CVODE on the stiff chain: few steps, no Newton failure, = RK4 (dt = 1 ms)", "[codegen][cvode]") {
    const LagrangianSystem s = stiff_chain::system({});
    const World ref = rk4_reference(s, 20.0, 1e-3);
    for (const auto solver : {Cvode::Options::LinearSolver::second_order, Cvode::Options::LinearSolver::dense}) {
        World w = make_lagrangian_world(s);
        Cvode cv(s, {.rtol = 1e-8, .atol = 1e-10, .linear_solver = solver});
        cv.advance(w, 20.0);
        const auto st = cv.stats();
        INFO(st.steps << " steps, " << st.newton_failures << " Newton failures, solver " << static_cast<int>(solver));
        CHECK(st.steps < 1000);
        CHECK(st.newton_failures == 0);
        CHECK(difference(w, ref, s.dof) < 1e-5);
    }
}
