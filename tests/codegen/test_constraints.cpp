// Constrained models (docs/language.md, *Constraints*): the generated KKT solve and the
// integrators' projections, against analytic answers and independent references.
#include "atwood.hpp"
#include "bead_on_rod.hpp"
#include "cartesian_double_pendulum.hpp"
#include "cartesian_pendulum.hpp"
#include "four_bar.hpp"
#include "knife_edge.hpp"
#include "pendulum.hpp"
#include "rolling_disk.hpp"
#include "slider_crank.hpp"
#include "unreachable.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace phynjo::runtime;

namespace {

/// The largest scaled residual at position and velocity level.
double worst(const LagrangianSystem& s, const World& w) {
    return worst_constraint_violation(s, w.time, w.field(kGQ), w.field(kGV)).scaled;
}

} // namespace

// Bug caught: a wrong G or γ (a sign, a missing ∂φ/∂t or q'-term in γ), or a wrong
// projection, moves the Cartesian pendulum off the polar one.
TEST_CASE("Cartesian pendulum = polar pendulum over 10 s (1e-9)", "[codegen][constraints]") {
    const cartesian_pendulum::Parameters P;
    const pendulum::Parameters Q;
    World wc = cartesian_pendulum::make_world(P), wp = pendulum::make_world(Q);
    Stepper sc(cartesian_pendulum::workflow(P, wc, "rk4")), sp(pendulum::workflow(Q, wp, "rk4"));
    const double dt = 1e-4;
    double err = 0;
    for (int k = 1; k <= 100000; ++k) {
        sc.step(wc, dt);
        sp.step(wp, dt);
        if (k % 1000) continue;
        const double th = wp.at(kGQ, 0), thd = wp.at(kGV, 0);
        err = std::max({err, std::fabs(wc.at(kGQ, 0) - Q.l * std::sin(th)), std::fabs(wc.at(kGQ, 1) + Q.l * std::cos(th)),
                        std::fabs(wc.at(kGV, 0) - Q.l * std::cos(th) * thd),
                        std::fabs(wc.at(kGV, 1) - Q.l * std::sin(th) * thd)});
    }
    CHECK(err < 1e-9);
    CHECK(worst(cartesian_pendulum::system(P), wc) < 1e-12);
}

// Bug caught: λ with the wrong sign or scale (Gᵀλ against −Gᵀλ, a lost factor 2 of G = 2(x, y)).
TEST_CASE("Cartesian pendulum: lambda = -m (g cos th + l th'^2) / (2 l), the rod tension", "[codegen][constraints]") {
    cartesian_pendulum::Parameters P;
    P.m = 1.7;
    P.l = 0.8;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> angle(-3, 3), rate(-4, 4);
    for (int k = 0; k < 100; ++k) {
        const double th = angle(rng), thd = rate(rng);
        const std::vector<double> q{P.l * std::sin(th), -P.l * std::cos(th)},
            v{P.l * std::cos(th) * thd, P.l * std::sin(th) * thd};
        std::vector<double> a(2), lambda(1);
        cartesian_pendulum::accelerations_and_multipliers(P, 0, q, v, a, lambda);
        const double tension = P.m * (P.g * std::cos(th) + P.l * thd * thd);
        CHECK(lambda[0] == Approx(-tension / (2 * P.l)).epsilon(1e-12).margin(1e-12));
        // and the polar equation θ'' = −(g/l) sin θ, through x'' = l (cos θ θ'' − sin θ θ'^2)
        const double thdd = -P.g / P.l * std::sin(th);
        CHECK(a[0] == Approx(P.l * (std::cos(th) * thdd - std::sin(th) * thd * thd)).margin(1e-11));
    }
}

// Bug caught: γ or G of the KKT solve inconsistent with M, f (the residual of either block
// equation), checked at random states off the constraint manifold too (accelerations holds
// for any state: no stabilization inside), with central differences of the velocity
// constraints as the independent reference for G q'' = γ.
TEST_CASE("KKT solution: M q'' = f + G^T lambda and d/dt psi = 0 at random states", "[codegen][constraints]") {
    const cartesian_double_pendulum::Parameters P;
    constexpr std::size_t n = 4, m = 2;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    for (int trial = 0; trial < 50; ++trial) {
        std::vector<double> q(n), v(n), a(n), lambda(m), M(n * n), f(n), G(m * n);
        for (std::size_t i = 0; i < n; ++i) {
            q[i] = u(rng);
            v[i] = u(rng);
        }
        cartesian_double_pendulum::accelerations_and_multipliers(P, 0, q, v, a, lambda);
        std::vector<double> a2(n);
        cartesian_double_pendulum::accelerations(P, 0, q, v, a2);
        CHECK(a2 == a);
        cartesian_double_pendulum::mass_matrix(P, 0, q, M);
        cartesian_double_pendulum::forcing(P, 0, q, v, f);
        cartesian_double_pendulum::constraint_matrix(P, 0, q, G);
        double scale = 1;
        for (std::size_t i = 0; i < n; ++i) scale = std::max({scale, std::fabs(f[i]), std::fabs(a[i])});
        for (std::size_t i = 0; i < n; ++i) {
            double r = -f[i];
            for (std::size_t j = 0; j < n; ++j) r += M[i * n + j] * a[j];
            for (std::size_t k = 0; k < m; ++k) r -= G[k * n + i] * lambda[k];
            CHECK(std::fabs(r) < 1e-12 * scale * 10);
        }
        // ψ(q + h q', q' + h q'') − ψ(q − h q', q' − h q'') over 2h: 0 up to O(h²)
        const double h = 1e-5;
        std::vector<double> qp(n), vp(n), qm(n), vm(n), pp(m), pm(m);
        for (std::size_t i = 0; i < n; ++i) {
            qp[i] = q[i] + h * v[i];
            vp[i] = v[i] + h * a[i];
            qm[i] = q[i] - h * v[i];
            vm[i] = v[i] - h * a[i];
        }
        cartesian_double_pendulum::constraint_velocity_residuals(P, 0, qp, vp, pp);
        cartesian_double_pendulum::constraint_velocity_residuals(P, 0, qm, vm, pm);
        for (std::size_t k = 0; k < m; ++k) CHECK(std::fabs((pp[k] - pm[k]) / (2 * h)) < 1e-7 * scale);
    }
}

// Bug caught: a wrong multiplier sign or an acceleration that ignores the rope.
TEST_CASE("Atwood machine: acceleration (m1-m2)g/(m1+m2) and rope tension 2 m1 m2 g/(m1+m2)", "[codegen][constraints]") {
    const atwood::Parameters P;
    const std::vector<double> q{1.2, 0.8}, v{0.5, -0.5};
    std::vector<double> a(2), lambda(1);
    atwood::accelerations_and_multipliers(P, 0, q, v, a, lambda);
    const double acc = (P.m1 - P.m2) * P.g / (P.m1 + P.m2), tension = 2 * P.m1 * P.m2 * P.g / (P.m1 + P.m2);
    CHECK(a[0] == Approx(acc).epsilon(1e-14));
    CHECK(a[1] == Approx(-acc).epsilon(1e-14));
    CHECK(lambda[0] == Approx(-tension).epsilon(1e-14)); // Gᵀλ = (λ, λ): the rope pulls both up
    // and along a run: x1(t) = x1(0) + a t²/2 (midpoint: exact for constant acceleration)
    World w = atwood::make_world(P);
    Stepper s(atwood::workflow(P, w, "midpoint"));
    for (int k = 0; k < 1000; ++k) s.step(w, 1e-3);
    CHECK(w.at(kGQ, 0) == Approx(1 + acc / 2).epsilon(1e-12));
    CHECK(std::fabs(w.at(kGQ, 0) + w.at(kGQ, 1) - P.L) <= 1e-12 * 2); // the projection tolerance
}

// Bug caught: a rheonomic constraint whose ∂φ/∂t terms are dropped from γ or from the
// velocity constraint (the bead would not follow the turning rod), or projections made at
// the start instead of the end time of the step.
TEST_CASE("bead on a rotating rod: r(t) = r0 cosh(w t), every integrator", "[codegen][constraints]") {
    const bead_on_rod::Parameters P;
    for (const char* integrator : {"rk4", "midpoint"}) {
        World w = bead_on_rod::make_world(P);
        Stepper s(bead_on_rod::workflow(P, w, integrator));
        const double dt = 1e-4;
        double err = 0;
        for (int k = 1; k <= 15000; ++k) {
            s.step(w, dt);
            const double t = k * dt, r = P.r0 * std::cosh(P.w * t);
            err = std::max({err, std::fabs(w.at(kGQ, 0) - r * std::cos(P.w * t)) / r,
                            std::fabs(w.at(kGQ, 1) - r * std::sin(P.w * t)) / r});
        }
        INFO(integrator);
        CHECK(err < (std::string(integrator) == "rk4" ? 1e-10 : 1e-7));
        CHECK(worst(bead_on_rod::system(P), w) < 1e-11);
    }
    // Dormand–Prince, projecting after each accepted step
    World w = bead_on_rod::make_world(P);
    DormandPrince45 dp(bead_on_rod::system(P), {});
    double h = 1e-3;
    while (w.time < 1.5 - 1e-12) h = dp.step(w, std::min(dp.next_dt() > 0 ? dp.next_dt() : h, 1.5 - w.time), 1.5);
    const double r = P.r0 * std::cosh(P.w * 1.5);
    CHECK(w.at(kGQ, 0) == Approx(r * std::cos(P.w * 1.5)).epsilon(1e-7));
    CHECK(w.at(kGQ, 1) == Approx(r * std::sin(P.w * 1.5)).epsilon(1e-7));
}

// Bug caught: a nonholonomic row handled as holonomic (G = ∂φ/∂q instead of ∂φ/∂q', or
// projected at position level), which the closed-form knife-edge path exposes.
TEST_CASE("knife edge on an incline: the closed-form path", "[codegen][constraints]") {
    const knife_edge::Parameters P;
    const double c = P.g * std::sin(P.alpha) / (2 * P.w * P.w);
    for (const char* integrator : {"rk4", "midpoint"}) {
        World w = knife_edge::make_world(P);
        Stepper s(knife_edge::workflow(P, w, integrator));
        const double dt = 1e-4;
        double err = 0;
        for (int k = 1; k <= 50000; ++k) {
            s.step(w, dt);
            const double t = k * dt, wt = P.w * t;
            err = std::max({err, std::fabs(w.at(kGQ, 0) - c * std::sin(wt) * std::sin(wt)),
                            std::fabs(w.at(kGQ, 1) - c * (wt - 0.5 * std::sin(2 * wt))), std::fabs(w.at(kGQ, 2) - wt)});
        }
        INFO(integrator);
        CHECK(err < (std::string(integrator) == "rk4" ? 1e-10 : 1e-6));
        CHECK(worst(knife_edge::system(P), w) < 1e-11);
    }
}

// Bug caught: projections that change the energy (a velocity projection along the wrong
// directions) or let the rolling constraints drift; the disk must trace its circle.
TEST_CASE("rolling disk: energy and constraints conserved, the path a circle", "[codegen][constraints]") {
    const rolling_disk::Parameters P;
    const LagrangianSystem sys = rolling_disk::system(P);
    World w = rolling_disk::make_world(P);
    const double e0 = sys.energy(0, w.field(kGQ), w.field(kGV));
    Stepper s(rolling_disk::workflow(P, w, "midpoint"));
    const double radius = P.R * 10 / 1; // R ph' / th'
    double de = 0, dr = 0, dc = 0;
    for (int k = 1; k <= 10000; ++k) {
        s.step(w, 1e-3);
        de = std::max(de, std::fabs(sys.energy(w.time, w.field(kGQ), w.field(kGV)) - e0));
        dc = std::max(dc, worst(sys, w));
        // starts at the origin heading along x, turning left: centre (0, radius)
        dr = std::max(dr, std::fabs(std::hypot(w.at(kGQ, 0), w.at(kGQ, 1) - radius) - radius));
    }
    CHECK(de < 1e-10 * e0);
    CHECK(dc < 1e-11);
    CHECK(dr < 1e-5); // midpoint, dt = 1e-3: O(dt²) phase error of the heading
}

// Bug caught: integration that lets the rod lengths drift (no projection, or a projection
// that stops short of the tolerance) over a long run, or an energy error that grows.
TEST_CASE("Cartesian double pendulum: constraint drift and energy over 10^6 steps, midpoint and RATTLE",
          "[codegen][constraints]") {
    const cartesian_double_pendulum::Parameters P;
    const LagrangianSystem sys = cartesian_double_pendulum::system(P);
    for (const char* integrator : {"midpoint", "rattle"}) {
        World w = cartesian_double_pendulum::make_world(P);
        Stepper s(cartesian_double_pendulum::workflow(P, w, integrator));
        const double e0 = sys.energy(0, w.field(kGQ), w.field(kGV));
        double drift = 0, de_first = 0, de_last = 0;
        for (int k = 1; k <= 1000000; ++k) {
            s.step(w, 1e-3);
            if (k % 100 == 0) {
                drift = std::max(drift, worst(sys, w));
                const double de = std::fabs(sys.energy(w.time, w.field(kGQ), w.field(kGV)) - e0);
                (k <= 100000 ? de_first : de_last) = std::max(k <= 100000 ? de_first : de_last, de);
            }
        }
        INFO(integrator << ": energy error " << de_first << " in the first 100 s, " << de_last << " after");
        CHECK(drift < 1e-10);
        CHECK(de_first < 1e-2);
        // bounded: the other 900 s do not take it beyond twice what the first 100 s saw
        // (RATTLE is symplectic; the midpoint rule with symmetric projection only symmetric)
        CHECK(de_last < 2 * de_first);
    }
}

// Bug caught: RATTLE that loses its second order (a half step evaluated at the wrong end, a
// multiplier applied once instead of twice) — error ratio 4 when the step halves.
TEST_CASE("RATTLE: second order on the Cartesian pendulum, against the polar pendulum", "[codegen][constraints]") {
    const cartesian_pendulum::Parameters P;
    const pendulum::Parameters Q;
    World wp = pendulum::make_world(Q);
    Stepper sp(pendulum::workflow(Q, wp, "rk4"));
    for (int k = 0; k < 20000; ++k) sp.step(wp, 1e-4);
    const double th = wp.at(kGQ, 0);
    double err[2];
    for (int j = 0; j < 2; ++j) {
        const double dt = j == 0 ? 0.01 : 0.005;
        World w = cartesian_pendulum::make_world(P);
        Stepper s(cartesian_pendulum::workflow(P, w, "rattle"));
        for (int k = 0; k < (j == 0 ? 200 : 400); ++k) s.step(w, dt);
        err[j] = std::hypot(w.at(kGQ, 0) - std::sin(th), w.at(kGQ, 1) + std::cos(th));
    }
    CHECK(err[0] / err[1] == Approx(4).epsilon(0.05));
    // the four-bar: forces that depend on the angles (gravity on the bars), two loop
    // constraints; the reference is RK4 at a hundredth of the step
    const four_bar::Parameters F;
    World ref = four_bar::make_world(F);
    Stepper sr(four_bar::workflow(F, ref, "rk4"));
    for (int k = 0; k < 100000; ++k) sr.step(ref, 1e-5);
    double e4[2];
    for (int j = 0; j < 2; ++j) {
        World w = four_bar::make_world(F);
        Stepper s(four_bar::workflow(F, w, "rattle"));
        for (int k = 0; k < (j == 0 ? 1000 : 2000); ++k) s.step(w, j == 0 ? 1e-3 : 5e-4);
        e4[j] = 0;
        for (Index i = 0; i < 3; ++i) e4[j] = std::max(e4[j], std::fabs(w.at(kGQ, i) - ref.at(kGQ, i)));
    }
    INFO("four-bar errors " << e4[0] << ", " << e4[1]);
    CHECK(e4[0] / e4[1] == Approx(4).epsilon(0.1));
    // rheonomic constraints: the bead on the turning rod
    const bead_on_rod::Parameters B;
    World w = bead_on_rod::make_world(B);
    Stepper s(bead_on_rod::workflow(B, w, "rattle"));
    for (int k = 0; k < 15000; ++k) s.step(w, 1e-4);
    const double r = B.r0 * std::cosh(B.w * 1.5);
    CHECK(std::hypot(w.at(kGQ, 0) - r * std::cos(B.w * 1.5), w.at(kGQ, 1) - r * std::sin(B.w * 1.5)) < 1e-7 * r);
    CHECK(worst(bead_on_rod::system(B), w) < 1e-11);
    // nonholonomic constraints are refused when the workflow is built
    const knife_edge::Parameters K;
    World wk = knife_edge::make_world(K);
    CHECK_THROWS_WITH(knife_edge::workflow(K, wk, "rattle"), Catch::Contains("constraint 'blade' is nonholonomic"));
}

// Bug caught: singular constraints at a state answered with NaN or a crash instead of the
// documented error naming the constraint.
TEST_CASE("singular constraints at a state: SingularConstraints names them", "[codegen][constraints]") {
    const cartesian_pendulum::Parameters P;
    std::vector<double> q{0, 0}, v{0, 0}, a(2), lambda(1);
    try {
        cartesian_pendulum::accelerations_and_multipliers(P, 0, q, v, a, lambda);
        FAIL("no exception");
    } catch (const SingularConstraints& e) {
        CHECK(e.constraints() == std::vector<std::string>{"rod"});
        CHECK_THAT(e.what(), Catch::Contains("'rod' has a zero row in G"));
    }
    const cartesian_double_pendulum::Parameters Q;
    std::vector<double> q4{0, 0, 1, 0}, v4(4), a4(4), l2(2);
    CHECK_THROWS_AS(cartesian_double_pendulum::accelerations(Q, 0, q4, v4, a4), SingularConstraints);
}

// Bug caught: inconsistent initial values accepted silently, or a projection that does not
// land on the manifold (positions by Gauss–Newton, then velocities).
TEST_CASE("initial values: checked, and projected onto the constraints", "[codegen][constraints]") {
    const cartesian_double_pendulum::Parameters P;
    const LagrangianSystem sys = cartesian_double_pendulum::system(P);
    std::vector<double> q{0.9, -0.1, 1.7, -0.5}, v{0.3, 0.2, -0.1, 0.4};
    try {
        check_constraints(sys, 0, q, v);
        FAIL("no exception");
    } catch (const InconsistentInitialValues& e) {
        // positions first (the velocities are off more): rod1 is off by 0.18 of 1.82 = 0.81 + 0.01 + 1,
        // rod2 by 0.2 of 1.8 = 0.64 + 0.16 + 1 (each scale plus a floor below 1e-2)
        CHECK(e.constraint() == "rod2");
        CHECK(e.residual() == Approx(0.8 * 0.8 + 0.4 * 0.4 - 1));
        CHECK_THAT(e.what(), Catch::Contains("violates constraint 'rod2' at position level: its residual is -0.2 "));
    }
    // positions right, velocities wrong: named at velocity level
    std::vector<double> qc{1, 0, 1.6, -0.8}, vc{0, 1, 0, 0};
    try {
        check_constraints(sys, 0, qc, vc);
        FAIL("no exception");
    } catch (const InconsistentInitialValues& e) {
        CHECK(e.constraint() == "rod2"); // rod2' = 2(0.6)(0 - 0) + 2(-0.8)(0 - 1) = 1.6
        CHECK(e.residual() == Approx(1.6));
        CHECK_THAT(e.what(), Catch::Contains("at velocity level"));
    }
    project_onto_constraints(sys, 0, q, v);
    CHECK_NOTHROW(check_constraints(sys, 0, q, v, 1e-12));
    // a consistent state is left alone
    const std::vector<double> q0 = q, v0 = v;
    project_onto_constraints(sys, 0, q, v);
    CHECK(q == q0);
    CHECK(v == v0);
}

// Bug caught: an input that cannot change during a run (the workflow keeps a copy of the
// parameters), or one whose change is ignored by the constrained solve.
TEST_CASE("inputs: a torque changed between steps acts at the next step (live_workflow)", "[codegen][constraints]") {
    STATIC_REQUIRE(slider_crank::n_inputs == 1);
    CHECK(slider_crank::input_names[0] == "tau");
    slider_crank::Parameters P;
    World live = slider_crank::make_world(P), fixed = slider_crank::make_world(P);
    Stepper sl(slider_crank::live_workflow(&P, live, "rk4")), sf(slider_crank::workflow(P, fixed, "rk4"));
    for (int k = 0; k < 2000; ++k) {
        sl.step(live, 1e-4);
        sf.step(fixed, 1e-4);
    }
    CHECK(live.at(kGV, 0) == fixed.at(kGV, 0)); // the same until the input changes
    CHECK(live.at(kGV, 0) > 0);
    P.tau = -0.5; // brake: the live model turns back, the copy keeps accelerating
    const double w0 = live.at(kGV, 0);
    for (int k = 0; k < 2000; ++k) {
        sl.step(live, 1e-4);
        sf.step(fixed, 1e-4);
    }
    CHECK(live.at(kGV, 0) < w0);
    CHECK(fixed.at(kGV, 0) > w0);
    CHECK(worst(slider_crank::system(P), live) < 1e-11);
}

// Bug caught: a constraint that no state satisfies (x² + y² = −l²) reported as a dead point or
// a bifurcation (SingularConstraints) or a bare non-convergence, without its name and residual.
// From (1, 0) Gauss–Newton halves towards the origin, x ← (x² − 1)/(2x) = 0, where G = 0
// and φ = l² = 1.
TEST_CASE("a constraint no state satisfies: UnreachableConstraint names it with its residual", "[codegen][constraints]") {
    const unreachable::Parameters P;
    const LagrangianSystem sys = unreachable::system(P);
    std::vector<double> q{1, 0}, v{0, 0};
    try {
        project_onto_constraints(sys, 0, q, v);
        FAIL("no exception");
    } catch (const UnreachableConstraint& e) {
        CHECK(e.constraint() == "ring");
        CHECK(e.residual() == 1.0);
        CHECK_THAT(e.what(), Catch::Contains("constraint 'ring' cannot be reached: its residual stays at 1 "));
        CHECK_THAT(e.what(), Catch::Contains("at these parameters perhaps none does"));
    }
    // a projection that merely starts far away still lands on a reachable constraint
    const cartesian_pendulum::Parameters C;
    std::vector<double> qc{3, -4}, vc{0, 0};
    project_onto_constraints(cartesian_pendulum::system(C), 0, qc, vc);
    CHECK(qc[0] * qc[0] + qc[1] * qc[1] == Approx(C.l * C.l).epsilon(1e-12));
}
