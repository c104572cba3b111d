// SUNDIALS IDA for generated models (integrators/ida.hpp): the stabilized index-2 equations
// against RK4 at tight tolerances, constraints held at IDA's own steps (holonomic,
// nonholonomic, rheonomic), a Lagrangian whose M depends on q', errors as the runtime's typed
// errors, the workflow and its restarts, the stiff chain.
#include "atwood.hpp"
#include "bead_on_rod.hpp"
#include "cartesian_pendulum.hpp"
#include "double_pendulum.hpp"
#include "driven.hpp"
#include "four_bar.hpp"
#include "relativistic.hpp"
#include "rolling_disk.hpp"
#include "slider_crank.hpp"
#include "spherical_pendulum.hpp"
#include "stiff_chain.hpp"

#include "rk4_reference.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace phynjo::runtime;
using test::difference;
using test::rk4_reference;

namespace {

double energy(const LagrangianSystem& s, const World& w) { return s.energy(w.time, w.field(kGQ), w.field(kGV)); }

} // namespace

// Bugs caught: a wrong entry of the Jacobian handed to IDA (a sign of ∂F/∂q, the constraints'
// curvature ∂(Gᵀλ)/∂q or ∂ψ/∂q left out, a block misplaced, row- for column-major): against
// central differences of the residual itself at random (Y, Ẏ) with λ, μ ≠ 0.
TEST_CASE("IDA's equations: the Jacobian = central differences of the residual", "[codegen][ida]") {
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    for (const LagrangianSystem& s : {double_pendulum::system({}), relativistic::system({}), driven::system({}),
                                      cartesian_pendulum::system({}), four_bar::system({}), rolling_disk::system({}),
                                      bead_on_rod::system({}), slider_crank::system({})}) {
        INFO(s.coordinate_names[0] << " (" << s.n_constraints << " constraints)");
        GglEquations eq(s);
        const std::size_t N = eq.size();
        REQUIRE(N == 3 * s.dof + s.n_constraints +
                         static_cast<std::size_t>(std::count(s.constraint_holonomic.begin(), s.constraint_holonomic.end(), 1)));
        std::vector<double> Y(N), Yd(N), J(N * N), Rp(N), Rm(N), R(N);
        for (int trial = 0; trial < 3; ++trial) {
            for (auto& y : Y) y = 0.5 * d(rng);
            for (auto& y : Yd) y = d(rng);
            const double t = 0.3 + 0.1 * trial, cj = 7.5;
            eq.jacobian(t, cj, Y, J);
            double worst = 0, scale = 0;
            for (std::size_t j = 0; j < N; ++j) {
                // ∂R/∂Y_j + cj ∂R/∂Ẏ_j by central differences
                std::vector<double> num(N, 0.0);
                for (int which = 0; which < 2; ++which) {
                    std::vector<double>& x = which == 0 ? Y : Yd;
                    const double x0 = x[j], h = 1e-5 * std::max(1.0, std::fabs(x0));
                    x[j] = x0 + h;
                    eq.residual(t, Y, Yd, Rp);
                    x[j] = x0 - h;
                    eq.residual(t, Y, Yd, Rm);
                    x[j] = x0;
                    for (std::size_t i = 0; i < N; ++i) num[i] += (which == 0 ? 1.0 : cj) * (Rp[i] - Rm[i]) / (2 * h);
                }
                for (std::size_t i = 0; i < N; ++i) {
                    worst = std::max(worst, std::fabs(J[j * N + i] - num[i])); // column-major
                    scale = std::max(scale, std::fabs(num[i]));
                }
            }
            CHECK(worst <= 1e-6 * std::max(1.0, scale));
        }
    }
}

// Bugs caught: inconsistent initial values (ṗ without the constraint forces Gᵀλ, p not ∂L/∂q',
// λ stale, a state off the constraints not projected): IDA then starts from a point that is
// not a solution and its first steps absorb the jump.
TEST_CASE("IDA's equations: consistent initial values solve them (off-constraint states projected first)", "[codegen][ida]") {
    for (const LagrangianSystem& s : {double_pendulum::system({}), relativistic::system({}), driven::system({}),
                                      cartesian_pendulum::system({}), four_bar::system({}), rolling_disk::system({}),
                                      bead_on_rod::system({}), slider_crank::system({})}) {
        INFO(s.coordinate_names[0] << " (" << s.n_constraints << " constraints)");
        GglEquations eq(s);
        World w = make_lagrangian_world(s);
        std::vector<double> q(w.field(kGQ).begin(), w.field(kGQ).end()), v(w.field(kGV).begin(), w.field(kGV).end());
        for (std::size_t i = 0; i < s.dof; ++i) { // a little off the constraints, at once
            q[i] += 1e-4 * static_cast<double>(i + 1);
            v[i] += 0.3 - 0.1 * static_cast<double>(i);
        }
        std::vector<double> Y(eq.size()), Yd(eq.size()), R(eq.size());
        const double t = 0.25;
        eq.consistent_values(t, q, v, {}, Y, Yd);
        eq.residual(t, Y, Yd, R);
        double worst = 0, scale = 1;
        for (std::size_t i = 0; i < eq.size(); ++i) {
            worst = std::max(worst, std::fabs(R[i]));
            scale = std::max({scale, std::fabs(Y[i]), std::fabs(Yd[i])});
        }
        CHECK(worst <= 1e-12 * scale);
    }
}

// Bugs caught: a wrong residual (a sign of Gᵀλ, q̇ rows against q' swapped), the momentum rows
// (p − ∂L/∂q' with the wrong p), a wrong exact Jacobian (Newton fails or crawls), inconsistent
// initial values (IDA's first step fails), the output interpolated at the wrong time.
TEST_CASE("IDA = RK4 at tight tolerances: unconstrained, constrained, M depending on q'", "[codegen][ida]") {
    struct Case {
        LagrangianSystem s;
        double t_end, tolerance;
    };
    for (const Case& c : {Case{double_pendulum::system({}), 2.0, 1e-8}, Case{driven::system({}), 2.0, 1e-8},
                          Case{relativistic::system({}), 2.0, 1e-8}, Case{cartesian_pendulum::system({}), 2.0, 1e-8},
                          Case{four_bar::system({}), 2.0, 1e-7}, Case{rolling_disk::system({}), 2.0, 1e-8},
                          Case{bead_on_rod::system({}), 1.0, 1e-8}, Case{atwood::system({}), 2.0, 1e-8}}) {
        const LagrangianSystem& s = c.s;
        INFO(s.coordinate_names[0] << " (" << s.dof << " coordinates, " << s.n_constraints << " constraints)");
        const World ref = rk4_reference(s, c.t_end, 1e-4);
        Ida::Stats with_dq;
        for (bool exact : {false, true}) {
            INFO((exact ? "exact Jacobian" : "IDA's difference quotients"));
            World w = make_lagrangian_world(s);
            Ida ida(s, {.rtol = 1e-12, .atol = 1e-12, .exact_jacobian = exact});
            for (int k = 1; k <= 20; ++k) ida.advance(w, c.t_end * k / 20); // the history carries over
            CHECK(w.time == c.t_end);
            CHECK(difference(w, ref, s.dof) < c.tolerance);
            const auto st = ida.stats();
            CHECK(st.steps > 0);
            if (exact) {
                // ours, not IDA's difference quotients, and a right one: Newton converges as
                // with IDA's own (a wrong matrix costs many more iterations and Jacobians)
                CHECK(st.difference_quotient_residuals == 0);
                CHECK(st.newton_iterations <= 1.15 * with_dq.newton_iterations + 10);
                CHECK(st.jacobian_evaluations <= 1.15 * with_dq.jacobian_evaluations + 5);
            } else {
                CHECK(st.difference_quotient_residuals > 0);
                with_dq = st;
            }
        }
    }
}

// Bugs caught: the stabilizing μ term dropped or with the wrong sign (positions drift off
// φ = 0, or IDA fails), the velocity rows ψ missing (λ undetermined), the output between
// steps not projected. Checked over 10 s on holonomic (Cartesian pendulum, four-bar, slider-
// crank), nonholonomic (rolling disk) and rheonomic (bead on a turning rod) constraints.
TEST_CASE("IDA keeps the constraints (stabilized index 2) over 10 s, and the energy", "[codegen][ida]") {
    struct Case {
        LagrangianSystem s;
        bool conservative; // the turning rod does work on the bead; the crank is driven and damped
    };
    for (const Case& c : {Case{cartesian_pendulum::system({}), true}, Case{four_bar::system({}), true},
                          Case{slider_crank::system({}), false}, Case{rolling_disk::system({}), true},
                          Case{bead_on_rod::system({}), false}}) {
        const LagrangianSystem& s = c.s;
        INFO(s.coordinate_names[0] << " (" << s.n_constraints << " constraints)");
        World w = make_lagrangian_world(s);
        const double e0 = energy(s, w);
        Ida ida(s, {.rtol = 1e-8, .atol = 1e-10});
        double worst = 0;
        for (int k = 1; k <= 100; ++k) {
            ida.advance(w, 0.1 * k);
            worst = std::max(worst, worst_constraint_violation(s, w.time, w.field(kGQ), w.field(kGV)).scaled);
        }
        CHECK(worst < 1e-10);
        if (c.conservative) CHECK(energy(s, w) == Approx(e0).epsilon(1e-5).margin(1e-9));
    }
}

// Bugs caught: an exception thrown through IDA's C code (undefined behaviour), a NaN state
// returned as if fine, the time reached lost, inconsistent initial values accepted.
TEST_CASE("IDA: errors are the runtime's typed errors, at the time reached", "[codegen][ida]") {
    const LagrangianSystem s = spherical_pendulum::system({});
    World w = make_lagrangian_world(s);
    w.at(kGQ, 0) = 0; // the pole: M = diag(m l^2, m l^2 sin(th)^2) is singular
    Ida ida(s, {});
    CHECK_THROWS_AS(ida.advance(w, 1.0), SingularMassMatrix);
    CHECK(w.time == 0);
    CHECK_THROWS_AS((Ida(s, {.atol = 0})), std::invalid_argument);
    LagrangianSystem no_jacobian = s;
    no_jacobian.canonical_jacobian = nullptr;
    CHECK_THROWS_AS((Ida(no_jacobian, {})), std::invalid_argument);
    CHECK_NOTHROW((Ida(no_jacobian, {.exact_jacobian = false})));
    // too few internal steps allowed: a ConvergenceError naming IDA's flag and the time
    World d = make_lagrangian_world(double_pendulum::system({}));
    Ida tight(double_pendulum::system({}), {.rtol = 1e-12, .atol = 1e-14, .max_steps = 10});
    try {
        tight.advance(d, 5.0);
        FAIL("expected a ConvergenceError");
    } catch (const ConvergenceError& e) {
        CHECK(std::string(e.what()).find("IDA_TOO_MUCH_WORK") != std::string::npos);
        CHECK(d.time > 0);
        CHECK(d.time < 5.0);
    }
    // a constrained start far off the constraints: the projection refuses it, typed
    const LagrangianSystem cp = cartesian_pendulum::system({});
    World off = make_lagrangian_world(cp);
    off.at(kGQ, 0) = 0;
    off.at(kGQ, 1) = 0; // the bob at the pivot: G = 0, no direction to project along
    Ida on_cp(cp, {});
    CHECK_THROWS_AS(on_cp.advance(off, 1.0), SingularConstraints);
}

// Bugs caught: the workflow rule advancing the time twice, a world changed between steps not
// restarting the solver (the old history applied to a new state), a restart from an
// inconsistent state (not projected, or with stale λ).
TEST_CASE("IDA as a workflow: the generated workflow(\"ida\"), restarts on a changed world", "[codegen][ida]") {
    const cartesian_pendulum::Parameters P;
    World a = cartesian_pendulum::make_world(P), b = a;
    Stepper st(cartesian_pendulum::workflow(P, a, "ida"));
    for (int k = 0; k < 10; ++k) st.step(a, 0.1);
    Ida ida(cartesian_pendulum::system(P), {});
    // the targets the rule computes, t + dt with t = (k − 1) dt the Stepper's time; one history
    // throughout (the Stepper's time differs from the solver's by an ulp: no restart)
    for (int k = 1; k <= 10; ++k) ida.advance(b, (k - 1) * 0.1 + 0.1);
    CHECK(std::fabs(a.time - 1.0) < 1e-15);
    CHECK(difference(a, b, 2) == 0); // the same solver, the same calls: bit for bit
    // change the state by hand (off the velocity constraint): the next step starts afresh from
    // it, projected, as a new solver would
    a.at(kGV, 0) += 0.5;
    World c = a;
    st.step(a, 0.1);
    Ida fresh(cartesian_pendulum::system(P), {});
    fresh.advance(c, c.time + 0.1);
    CHECK(difference(a, c, 2) == 0);
    const LagrangianSystem s = cartesian_pendulum::system(P);
    CHECK(worst_constraint_violation(s, a.time, a.field(kGQ), a.field(kGV)).scaled < 1e-10);
}

// Bug caught: a wrong Jacobian on a stiff model (on a non-stiff one Newton converges with
// almost any matrix; on the stiff chain it needs the right one).
TEST_CASE("IDA on the stiff chain: few steps, no Newton failure, = RK4 (dt = 1 ms)", "[codegen][ida]") {
    const LagrangianSystem s = stiff_chain::system({});
    const World ref = rk4_reference(s, 20.0, 1e-3);
    World w = make_lagrangian_world(s);
    Ida ida(s, {.rtol = 1e-8, .atol = 1e-10});
    ida.advance(w, 20.0);
    const auto st = ida.stats();
    INFO(st.steps << " steps, " << st.newton_failures << " Newton failures");
    CHECK(st.steps < 1500);
    CHECK(st.newton_failures == 0);
    CHECK(difference(w, ref, s.dof) < 1e-5);
}
