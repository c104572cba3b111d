// The generated code of the example models: physics checks on the compiled functions, and
// the runtime integration (workflows, integrators).
#include "cart_pole.hpp"
#include "bateman.hpp"
#include "double_pendulum.hpp"
#include "functions.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "quartic.hpp"
#include "relativistic.hpp"
#include "physical_pendulum.hpp"
#include "spring_pendulum.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace phynjo::runtime;

TEST_CASE("small-angle pendulum: period 2π√(l/g)", "[codegen][generated]") {
    pendulum::Parameters P;
    P.l = 0.8;
    World w = pendulum::make_world(P);
    w.at(kGQ, 0) = 0.01;
    Stepper s(pendulum::workflow(P, w, "rk4"));
    const double dt = 1e-4, T0 = 2 * M_PI * std::sqrt(P.l / P.g);
    std::vector<double> crossings; // downward zero crossings of θ
    double prev = w.at(kGQ, 0), t = 0;
    while (crossings.size() < 4) {
        s.step(w, dt);
        t += dt;
        const double cur = w.at(kGQ, 0);
        if (prev > 0 && cur <= 0) crossings.push_back(t - dt * cur / (cur - prev));
        prev = cur;
    }
    const double T = (crossings[3] - crossings[0]) / 3;
    // finite amplitude lengthens the period by θ0²/16 = 6e-6 (relative)
    CHECK(T == Approx(T0 * (1 + 0.01 * 0.01 / 16)).epsilon(1e-6));
}

TEST_CASE("accelerations solve M q'' = f, M is the Jacobian of the momenta", "[codegen][generated]") {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    nlink_cart_5::Parameters P;
    constexpr std::size_t n = nlink_cart_5::dof;
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<double> q(n), v(n), a(n), f(n), M(n * n), p(n), p2(n);
        for (std::size_t i = 0; i < n; ++i) {
            q[i] = u(rng);
            v[i] = u(rng);
        }
        nlink_cart_5::accelerations(P, 0, q, v, a);
        nlink_cart_5::mass_matrix(P, 0, q, M);
        nlink_cart_5::forcing(P, 0, q, v, f);
        for (std::size_t i = 0; i < n; ++i) { // residual of M a = f
            double r = -f[i];
            for (std::size_t j = 0; j < n; ++j) r += M[i * n + j] * a[j];
            CHECK(std::fabs(r) < 1e-11 * (1 + std::fabs(f[i])));
        }
        // M_ij = ∂p_i/∂q'_j by central differences
        const double h = 1e-6;
        for (std::size_t j = 0; j < n; ++j) {
            std::vector<double> vp = v, vm = v;
            vp[j] += h;
            vm[j] -= h;
            nlink_cart_5::momenta(P, 0, q, vp, p);
            nlink_cart_5::momenta(P, 0, q, vm, p2);
            for (std::size_t i = 0; i < n; ++i) CHECK((p[i] - p2[i]) / (2 * h) == Approx(M[i * n + j]).margin(1e-7));
        }
    }
}

TEST_CASE("generated functions report misuse and singular states", "[codegen][generated]") {
    double_pendulum::Parameters P;
    std::vector<double> q{0.1, 0.2}, v{0, 0}, a(2), bad(3);
    CHECK_THROWS_AS(double_pendulum::accelerations(P, 0, q, v, bad), std::invalid_argument);
    CHECK_THROWS_WITH(double_pendulum::accelerations(P, 0, bad, v, a),
                      "double_pendulum::accelerations: q has 3 entries, expected 2");
    P.m1 = P.m2 = 0; // massless: M = 0
    CHECK_THROWS_AS(double_pendulum::accelerations(P, 0, q, v, a), SingularMassMatrix);
    nlink_cart_5::Parameters Q;
    Q.m0 = Q.m1 = Q.m2 = Q.m3 = Q.m4 = Q.m5 = 0;
    std::vector<double> q6(6, 0.1), v6(6, 0), a6(6);
    CHECK_THROWS_AS(nlink_cart_5::accelerations(Q, 0, q6, v6, a6), SingularMassMatrix);
    double_pendulum::Parameters R;
    R.g = std::nan("");
    CHECK_THROWS_AS(double_pendulum::accelerations(R, 0, q, v, a), NonFiniteResult);
}

TEST_CASE("n-link cart: the cart's momentum is conserved (q0 is cyclic), energy too", "[codegen][generated]") {
    nlink_cart_5::Parameters P; // F = 0
    World w = nlink_cart_5::make_world(P);
    w.at(kGV, 0) = 0.3;
    const auto sys = nlink_cart_5::system(P);
    std::vector<double> p(6);
    auto p0 = [&] {
        sys.momenta(w.time, w.field(kGQ), w.field(kGV), p);
        return p[0];
    };
    const double pc0 = p0(), e0 = sys.energy(0, w.field(kGQ), w.field(kGV));
    Stepper s(nlink_cart_5::workflow(P, w, "rk4"));
    s.run(w, 5e-4, 6000);
    CHECK(p0() == Approx(pc0).margin(1e-9));
    CHECK(sys.energy(w.time, w.field(kGQ), w.field(kGV)) == Approx(e0).epsilon(1e-8));
}

TEST_CASE("cart-pole: friction only removes energy, and a push moves the cart", "[codegen][generated]") {
    cart_pole::Parameters P; // b = 0.1, F = 0
    World w = cart_pole::make_world(P);
    w.at(kGV, 0) = 1.0;
    const auto sys = cart_pole::system(P);
    Stepper s(cart_pole::workflow(P, w, "rk4"));
    double e = sys.energy(0, w.field(kGQ), w.field(kGV));
    for (int k = 0; k < 2000; ++k) {
        s.step(w, 1e-3);
        const double e2 = sys.energy(w.time, w.field(kGQ), w.field(kGV));
        REQUIRE(e2 <= e + 1e-12);
        e = e2;
    }
    cart_pole::Parameters pushed;
    pushed.F = 2;
    pushed.b = 0;
    World u = cart_pole::make_world(pushed);
    u.at(kGQ, 1) = 0; // pole upright and at rest: a uniform rod on a pushed cart
    std::vector<double> acc(2);
    cart_pole::accelerations(pushed, 0, u.field(kGQ), u.field(kGV), acc);
    // x'' = F/(mc + mp/4) and θ'' = −3x''/(4 lh) for a uniform rod (moment of inertia
    // about its centre mp(2 lh)²/12)
    CHECK(acc[0] == Approx(2 / (1 + 0.1 / 4)));
    CHECK(acc[1] == Approx(-3 * acc[0] / (4 * 0.5)));
}

TEST_CASE("integrators for generated models agree, and Dormand-Prince meets its tolerance", "[codegen][generated]") {
    spring_pendulum::Parameters P;
    const auto sys = spring_pendulum::system(P);
    World a = spring_pendulum::make_world(P), b = a;
    Stepper(spring_pendulum::workflow(P, a, "rk4")).run(a, 1e-4, 20000); // 2 s, very accurate
    DormandPrince45 dp(sys, {.rtol = 1e-10, .atol = 1e-12});
    double h = 1e-3;
    while (b.time < 2 - 1e-12) h = dp.step(b, dp.next_dt() > 0 ? dp.next_dt() : h, 2.0);
    CHECK(b.time == Approx(2.0));
    for (Index i = 0; i < 2; ++i) {
        CHECK(b.at(kGQ, i) == Approx(a.at(kGQ, i)).margin(1e-7));
        CHECK(b.at(kGV, i) == Approx(a.at(kGV, i)).margin(1e-6));
    }
}

TEST_CASE("implicit midpoint keeps the double pendulum's energy bounded over 10^6 steps", "[codegen][generated][long]") {
    double_pendulum::Parameters P;
    World w = double_pendulum::make_world(P);
    w.at(kGQ, 0) = 1.2; // E(0) ≠ 0
    w.at(kGQ, 1) = -0.4;
    const auto sys = double_pendulum::system(P);
    const double e0 = sys.energy(0, w.field(kGQ), w.field(kGV));
    Stepper s(double_pendulum::workflow(P, w, "midpoint"));
    const std::size_t steps = 1000000;
    double first = 0, last = 0;
    for (std::size_t k = 1; k <= steps; ++k) {
        s.step(w, 1e-3);
        if (k % 100 == 0) {
            const double err = std::fabs((sys.energy(w.time, w.field(kGQ), w.field(kGV)) - e0) / e0);
            if (k <= steps / 10) first = std::max(first, err);
            if (k > steps - steps / 10) last = std::max(last, err);
        }
    }
    INFO("largest relative energy error: first 10% of the run " << first << ", last 10% " << last);
    CHECK(first < 1e-4);
    CHECK(last < 2 * first); // bounded: no drift over 1000 s
}

// Catches: an implicit midpoint whose equations are not solved to round-off (a loose
// iteration tolerance, a missing iteration): the method is then no longer symmetric, which
// the bounded-energy test above cannot see at dt = 1e-3 (an unconverged step still keeps the
// energy bounded there). Symmetric means Φ(−h) ∘ Φ(h) = identity.
TEST_CASE("implicit midpoint is symmetric: a step of h then of -h returns to the start", "[codegen][generated]") {
    double_pendulum::Parameters P;
    World w = double_pendulum::make_world(P);
    w.at(kGQ, 0) = 1.2;
    w.at(kGQ, 1) = -0.4;
    w.at(kGV, 0) = 0.7;
    w.at(kGV, 1) = -1.9;
    Stepper s(double_pendulum::workflow(P, w, "midpoint"));
    for (double h : {1e-3, 1e-2, 5e-2}) {
        World x = w;
        s.step(x, h);
        CHECK(std::abs(x.at(kGQ, 0) - w.at(kGQ, 0)) > 1e-4 * h); // it moved
        s.step(x, -h);
        double worst = 0;
        for (Index i = 0; i < 2; ++i)
            worst = std::max({worst, std::abs(x.at(kGQ, i) - w.at(kGQ, i)), std::abs(x.at(kGV, i) - w.at(kGV, i))});
        INFO("h = " << h << ": |Φ(−h)Φ(h)y − y| = " << worst);
        CHECK(worst < 1e-13);
    }
}

// Catches: an invertible indefinite M refused ("not positive definite") or solved wrongly.
// Bateman's Lagrangian m x'y' + g/2 (x y' − x' y) − k x y gives m x'' + g x' + k x = 0: from
// x(0) = 1, x'(0) = 0, x(t) = e^{−γt}(cos ωt + (γ/ω) sin ωt) with γ = g/2m, ω² = k/m − γ².
TEST_CASE("Bateman's dual oscillator: x is the damped oscillator, y its time-reversed mirror", "[codegen][generated]") {
    bateman::Parameters P; // m = 1, g = 0.3, k = 2
    World w = bateman::make_world(P);
    w.at(kGQ, 1) = 1;
    Stepper s(bateman::workflow(P, w, "rk4"));
    const double gamma = P.g / (2 * P.m), omega = std::sqrt(P.k / P.m - gamma * gamma);
    double worst = 0;
    for (int k = 1; k <= 5000; ++k) {
        s.step(w, 1e-3);
        const double t = k * 1e-3;
        const double x = std::exp(-gamma * t) * (std::cos(omega * t) + gamma / omega * std::sin(omega * t));
        const double y = std::exp(gamma * t) * (std::cos(omega * t) - gamma / omega * std::sin(omega * t));
        worst = std::max({worst, std::abs(w.at(kGQ, 0) - x), std::abs(w.at(kGQ, 1) - y) / std::exp(gamma * t)});
    }
    INFO("largest error over 5 s: " << worst);
    CHECK(worst < 1e-10);
}

// Catches: a parameter defined from others (I = 1/2 Mp R²) left at its file value when one of
// them changes (stale derived parameters), or overriding a value that was set explicitly.
// th'' = −Mp g d sin th / (I + Mp d²).
TEST_CASE("a parameter defined from others follows them unless it is set", "[codegen][generated]") {
    auto expected = [](double Mp, double R, double d, double I, double th) {
        (void)R;
        return -Mp * 9.81 * d * std::sin(th) / (I + Mp * d * d);
    };
    std::vector<double> q{0.4}, v{0.0}, a(1);
    physical_pendulum::Parameters P;
    CHECK_FALSE(P.I.is_set());
    physical_pendulum::accelerations(P, 0, q, v, a);
    CHECK(a[0] == Approx(expected(2, 0.5, 0.3, 0.5 * 2 * 0.25, 0.4)).epsilon(1e-14));
    P.Mp = 4; // I follows: 1/2 · 4 · 0.25 = 0.5
    physical_pendulum::accelerations(P, 0, q, v, a);
    CHECK(a[0] == Approx(expected(4, 0.5, 0.3, 0.5, 0.4)).epsilon(1e-14));
    P.R = 1; // and again: I = 2
    physical_pendulum::accelerations(P, 0, q, v, a);
    CHECK(a[0] == Approx(expected(4, 1, 0.3, 2, 0.4)).epsilon(1e-14));
    P.I = 0.7; // set: fixed from now on
    P.Mp = 1;
    CHECK(P.I.is_set());
    physical_pendulum::accelerations(P, 0, q, v, a);
    CHECK(a[0] == Approx(expected(1, 1, 0.3, 0.7, 0.4)).epsilon(1e-14));
    const physical_pendulum::Parameters Q{.Mp = 3, .I = 0.9}; // designated initializers set it too
    physical_pendulum::accelerations(Q, 0, q, v, a);
    CHECK(a[0] == Approx(expected(3, 0.5, 0.3, 0.9, 0.4)).epsilon(1e-14));
    P.I = phynjo::runtime::Derived::following(0); // follows again: I = 1/2 · 1 · 1
    physical_pendulum::accelerations(P, 0, q, v, a);
    CHECK(a[0] == Approx(expected(1, 1, 0.3, 0.5, 0.4)).epsilon(1e-14));
    // and the energy uses the same I
    CHECK(physical_pendulum::energy(P, 0, q, std::vector<double>{1.0}) ==
          Approx(0.5 * (0.5 + 1 * 0.09) - 1 * 9.81 * 0.3 * std::cos(0.4)).epsilon(1e-14));
}

// Catches: a Lagrangian that is not quadratic in the velocities refused or miscompiled (M
// then depends on q': mass_matrix takes q', and the midpoint's Newton refactors M).
TEST_CASE("a relativistic particle: M depends on the velocity, and every integrator follows p = F t", "[codegen][generated]") {
    relativistic::Parameters P; // m = 1, c = 1, F = 0.5
    STATIC_REQUIRE(std::is_invocable_v<decltype(&relativistic::mass_matrix), const relativistic::Parameters&, double,
                                       std::span<const double>, std::span<const double>, std::span<double>>);
    std::vector<double> q{0}, v{0.6}, M(1);
    relativistic::mass_matrix(P, 0, q, v, M);
    CHECK(M[0] == Approx(1 / std::pow(1 - 0.36, 1.5)).epsilon(1e-14)); // m γ³
    auto exact_x = [&](double t) { const double u = P.F * t / (P.m * P.c); return P.m * P.c * P.c / P.F * (std::sqrt(1 + u * u) - 1); };
    auto exact_v = [&](double t) { const double u = P.F * t / (P.m * P.c); return P.c * u / std::sqrt(1 + u * u); };
    for (const char* integrator : {"rk4", "midpoint"}) {
        World w = relativistic::make_world(P);
        Stepper s(relativistic::workflow(P, w, integrator));
        s.run(w, 1e-3, 4000); // to t = 4: v = 0.894 c
        INFO(integrator << ": x = " << w.at(kGQ, 0) << " (exact " << exact_x(4) << "), v = " << w.at(kGV, 0));
        const double tol = std::string(integrator) == "rk4" ? 1e-10 : 1e-6; // order 4 and order 2 at dt = 1 ms
        CHECK(std::abs(w.at(kGQ, 0) - exact_x(4)) < tol);
        CHECK(std::abs(w.at(kGV, 0) - exact_v(4)) < tol);
    }
}

TEST_CASE("a velocity-quartic Lagrangian: energy conserved, the midpoint rule symmetric", "[codegen][generated]") {
    quartic::Parameters P;
    World w = quartic::make_world(P);
    const auto sys = quartic::system(P);
    CHECK(sys.mass_depends_on_velocities);
    const double e0 = sys.energy(0, w.field(kGQ), w.field(kGV));
    World a = w;
    Stepper rk(quartic::workflow(P, a, "rk4"));
    rk.run(a, 1e-3, 10000);
    CHECK(sys.energy(a.time, a.field(kGQ), a.field(kGV)) == Approx(e0).epsilon(1e-10));
    World b = w;
    Stepper mid(quartic::workflow(P, b, "midpoint"));
    mid.step(b, 0.05);
    mid.step(b, -0.05);
    for (Index i = 0; i < 2; ++i) {
        CHECK(std::abs(b.at(kGQ, i) - w.at(kGQ, i)) < 1e-13);
        CHECK(std::abs(b.at(kGV, i) - w.at(kGV, i)) < 1e-13);
    }
}

// Bug caught: a function of the language printed wrongly into C++ (sign as a plain call, abs as integer
// std::abs, asin for acos, atan2's arguments swapped), or derived wrongly inside the
// equations of motion.
TEST_CASE("generated code with every function of the language: accelerations against the hand-written equations", "[codegen][generated]") {
    const functions::Parameters P;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    for (int k = 0; k < 50; ++k) {
        const double t = u(rng), x = u(rng), y = u(rng), xd = u(rng), yd = u(rng);
        std::vector<double> q{x, y}, v{xd, yd}, a(2);
        functions::accelerations(P, t, q, v, a);
        // L = (x'^2 + y'^2)/2 - cosh x - log cosh y:  x'' = -sinh x + Q_x,  y'' = -tanh y + Q_y
        const double ax = -std::sinh(x) - P.c * std::atan(xd) + std::asin(std::sin(t) / 2) + std::acos(1 / (1 + y * y)) +
                          P.mu * std::atan2(yd, x);
        const double ay = -std::tanh(y) - P.mu * (yd > 0 ? 1 : yd < 0 ? -1 : 0) - P.k * std::fabs(y) * std::sinh(y);
        CHECK(a[0] == Approx(ax).epsilon(1e-13).margin(1e-14));
        CHECK(a[1] == Approx(ay).epsilon(1e-13).margin(1e-14));
    }
}

// Bugs caught: a model without the declarations made for every model — events
// and shapes (docs/generated-code.md: "declared for every model …, then the counts are 0 and the
// functions still exist"; a user's code naming them would not compile) —, or their size
// checks missing (a caller's wrong span accepted silently).
TEST_CASE("every model declares events and shapes (none yet), sizes checked", "[codegen][generated]") {
    static_assert(pendulum::n_events == 0 && pendulum::event_names.empty());
    static_assert(spring_pendulum::n_shapes == 0 && spring_pendulum::shape_names.empty());
    const spring_pendulum::Parameters P;
    std::vector<double> q(spring_pendulum::dof, 0.1), v(spring_pendulum::dof, 0.2), none, one(1);
    CHECK_NOTHROW(spring_pendulum::event_guards(P, 0, q, v, none));
    CHECK_NOTHROW(spring_pendulum::shape_positions(P, 0, q, none));
    CHECK_NOTHROW(spring_pendulum::sphere_jacobians(P, 0, q, none));
    CHECK_THROWS_AS(spring_pendulum::event_guards(P, 0, q, v, one), std::invalid_argument);
    CHECK_THROWS_AS(spring_pendulum::event_guards(P, 0, one, v, none), std::invalid_argument);
    CHECK_THROWS_AS(spring_pendulum::shape_positions(P, 0, q, one), std::invalid_argument);
    CHECK_THROWS_AS(spring_pendulum::sphere_jacobians(P, 0, one, none), std::invalid_argument);
}
