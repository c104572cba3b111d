// The generated rhs_jacobian and input_jacobian (docs/generated-code.md) against fourth-order
// central differences of the generated accelerations, at random states near each model's
// initial state, for every example and test model (constrained ones included); and against
// closed forms.
#include "atwood.hpp"
#include "bateman.hpp"
#include "bead_on_rod.hpp"
#include "cart_pole.hpp"
#include "cartesian_double_pendulum.hpp"
#include "cartesian_pendulum.hpp"
#include "collide.hpp"
#include "double_pendulum.hpp"
#include "driven.hpp"
#include "four_bar.hpp"
#include "functions.hpp"
#include "indefinite3.hpp"
#include "knife_edge.hpp"
#include "negative_mass.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "physical_pendulum.hpp"
#include "quartic.hpp"
#include "relativistic.hpp"
#include "rolling_disk.hpp"
#include "slider_crank.hpp"
#include "spherical_pendulum.hpp"
#include "spring_pendulum.hpp"
#include "stiff_chain.hpp"
#include "triple_pendulum.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace {

using Fn = std::function<void(double, std::span<const double>, std::span<const double>, std::span<double>)>;

/// A generated model seen through its functions.
struct Spec {
    std::string name;
    std::size_t n = 0, inputs = 0;
    Fn accelerations, rhs_jacobian, input_jacobian, momenta, generalized_forces;
    std::function<void(double, std::span<const double>, std::span<const double>, std::span<double>, std::span<double>,
                       std::span<double>, std::span<double>)>
        canonical_jacobian;
    std::function<void(std::span<double>, std::span<double>)> initial_state;
    std::function<double&(std::size_t)> input; ///< the k-th input's field of the model's Parameters
};

template <typename Params, typename... Members>
Spec make_spec(std::string name, std::size_t n, std::size_t inputs, auto acc, auto jac, auto ijac, auto init,
               auto mom, auto gf, auto cj, Members... members) {
    auto P = std::make_shared<Params>();
    Spec s;
    s.name = std::move(name);
    s.n = n;
    s.inputs = inputs;
    s.accelerations = [=](double t, auto q, auto v, auto out) { acc(*P, t, q, v, out); };
    s.rhs_jacobian = [=](double t, auto q, auto v, auto out) { jac(*P, t, q, v, out); };
    s.input_jacobian = [=](double t, auto q, auto v, auto out) { ijac(*P, t, q, v, out); };
    s.initial_state = [=](auto q, auto v) { init(*P, q, v); };
    s.momenta = [=](double t, auto q, auto v, auto out) { mom(*P, t, q, v, out); };
    s.generalized_forces = [=](double t, auto q, auto v, auto out) { gf(*P, t, q, v, out); };
    s.canonical_jacobian = [=](double t, auto q, auto v, auto p, auto F, auto dp, auto dF) { cj(*P, t, q, v, p, F, dp, dF); };
    s.input = [=](std::size_t k) -> double& {
        double Params::* const m[] = {members..., nullptr};
        return (*P).*m[k];
    };
    return s;
}

#define PHYNJO_SPEC(ns, ...)                                                                                            \
    make_spec<ns::Parameters>(#ns, ns::dof, ns::n_inputs, ns::accelerations, ns::rhs_jacobian, ns::input_jacobian,     \
                              ns::initial_state, ns::momenta, ns::generalized_forces,                                 \
                              ns::canonical_jacobian __VA_OPT__(, ) __VA_ARGS__)

std::vector<Spec> all_models() {
    return {PHYNJO_SPEC(pendulum),
            PHYNJO_SPEC(double_pendulum),
            PHYNJO_SPEC(spring_pendulum),
            PHYNJO_SPEC(cart_pole),
            PHYNJO_SPEC(nlink_cart_5),
            PHYNJO_SPEC(triple_pendulum),
            PHYNJO_SPEC(spherical_pendulum),
            PHYNJO_SPEC(bateman),
            PHYNJO_SPEC(negative_mass),
            PHYNJO_SPEC(indefinite3),
            PHYNJO_SPEC(physical_pendulum),
            PHYNJO_SPEC(collide),
            PHYNJO_SPEC(relativistic),
            PHYNJO_SPEC(quartic),
            PHYNJO_SPEC(functions),
            PHYNJO_SPEC(stiff_chain),
            PHYNJO_SPEC(driven, &driven::Parameters::u, &driven::Parameters::w),
            PHYNJO_SPEC(cartesian_pendulum),
            PHYNJO_SPEC(atwood),
            PHYNJO_SPEC(bead_on_rod),
            PHYNJO_SPEC(knife_edge),
            PHYNJO_SPEC(rolling_disk),
            PHYNJO_SPEC(cartesian_double_pendulum),
            PHYNJO_SPEC(slider_crank, &slider_crank::Parameters::tau),
            PHYNJO_SPEC(four_bar, &four_bar::Parameters::tau)};
}

/// d/dx of g at x by the fourth-order central difference (error O(h⁴) + O(ε/h)).
template <typename G>
std::vector<double> central_difference(G&& g, double h) {
    const auto p2 = g(2 * h), p1 = g(h), m1 = g(-h), m2 = g(-2 * h);
    std::vector<double> d(p1.size());
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = (m2[i] - p2[i] + 8 * (p1[i] - m1[i])) / (12 * h);
    return d;
}

/// The largest difference between the generated Jacobians and central differences, relative
/// to max(1, the largest entry), over `samples` random states near the initial state.
struct Errors {
    double rhs = 0, input = 0;
    double canonical = 0; ///< dp, dF of canonical_jacobian against differences of momenta and generalized_forces
    double canonical_values = 0; ///< its p and F against momenta and generalized_forces
    int states = 0;
};

Errors compare_with_differences(Spec& s, int samples, std::uint64_t seed) {
    const std::size_t n = s.n, N = 2 * n, K = s.inputs;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> dq(0, 0.3), dv(0, 0.2);
    std::uniform_real_distribution<double> time(0, 2);
    std::vector<double> q0(n), v0(n);
    s.initial_state(q0, v0);
    Errors e;
    for (int trial = 0; trial < samples; ++trial) {
        std::vector<double> y(N);
        for (std::size_t i = 0; i < n; ++i) {
            y[i] = q0[i] + dq(rng);
            y[n + i] = v0[i] + dv(rng);
        }
        const double t = time(rng);
        auto rhs = [&](const std::vector<double>& yy) {
            std::vector<double> out(N);
            std::copy(yy.begin() + n, yy.end(), out.begin());
            s.accelerations(t, std::span(yy).first(n), std::span(yy).subspan(n), std::span(out).subspan(n));
            return out;
        };
        try {
            (void)rhs(y);
        } catch (const std::exception&) {
            continue; // a singular state (or outside the model's domain): draw another
        }
        std::vector<double> J(N * N), B(N * K);
        s.rhs_jacobian(t, std::span(y).first(n), std::span(y).subspan(n), J);
        s.input_jacobian(t, std::span(y).first(n), std::span(y).subspan(n), B);
        double scale = 1;
        for (double v : J) scale = std::max(scale, std::fabs(v));
        for (std::size_t j = 0; j < N; ++j) {
            const double h = 1e-4 * std::max(1.0, std::fabs(y[j]));
            const auto d = central_difference(
                [&](double dx) {
                    auto yy = y;
                    yy[j] += dx;
                    return rhs(yy);
                },
                h);
            for (std::size_t i = 0; i < N; ++i) e.rhs = std::max(e.rhs, std::fabs(J[i * N + j] - d[i]) / scale);
        }
        double bscale = 1;
        for (double v : B) bscale = std::max(bscale, std::fabs(v));
        for (std::size_t k = 0; k < K; ++k) {
            double& u = s.input(k);
            const double u0 = u, h = 1e-4 * std::max(1.0, std::fabs(u0));
            const auto d = central_difference(
                [&](double du) {
                    u = u0 + du;
                    auto out = rhs(y);
                    u = u0;
                    return out;
                },
                h);
            for (std::size_t i = 0; i < N; ++i) e.input = std::max(e.input, std::fabs(B[i * K + k] - d[i]) / bscale);
        }
        // canonical_jacobian: dp = ∂p/∂y, dF = ∂F/∂y (n × 2n each)
        std::vector<double> p(n), F(n), dp(n * N), dF(n * N), p_ref(n), F_ref(n);
        const auto q = std::span(y).first(n), v = std::span(y).subspan(n);
        s.canonical_jacobian(t, q, v, p, F, dp, dF);
        s.momenta(t, q, v, p_ref);
        s.generalized_forces(t, q, v, F_ref);
        double cscale = 1;
        for (double x : dp) cscale = std::max(cscale, std::fabs(x));
        for (double x : dF) cscale = std::max(cscale, std::fabs(x));
        for (std::size_t i = 0; i < n; ++i)
            e.canonical_values = std::max({e.canonical_values, std::fabs(p[i] - p_ref[i]) / std::max(1.0, std::fabs(p_ref[i])),
                                           std::fabs(F[i] - F_ref[i]) / std::max(1.0, std::fabs(F_ref[i]))});
        for (std::size_t j = 0; j < N; ++j) {
            const double h = 1e-4 * std::max(1.0, std::fabs(y[j]));
            auto pf = [&](double dx) {
                auto yy = y;
                yy[j] += dx;
                std::vector<double> out(2 * n);
                s.momenta(t, std::span(yy).first(n), std::span(yy).subspan(n), std::span(out).first(n));
                s.generalized_forces(t, std::span(yy).first(n), std::span(yy).subspan(n), std::span(out).subspan(n));
                return out;
            };
            const auto d = central_difference(pf, h);
            for (std::size_t i = 0; i < n; ++i)
                e.canonical = std::max({e.canonical, std::fabs(dp[i * N + j] - d[i]) / cscale,
                                        std::fabs(dF[i * N + j] - d[n + i]) / cscale});
        }
        ++e.states;
    }
    return e;
}

} // namespace

// Bugs caught: a term missing from the implicit differentiation — ∂M/∂q contracted with q''
// (every model whose M depends on q), ∂M/∂q' (the relativistic particle), Gᵀλ or ∂G/∂y
// (the constrained models), ∂γ/∂y; a chain rule through a parameter defined from an input
// (driven); the identity block or a transposed block; an entry of the CSE'd body computed
// before the accelerations it reads.
TEST_CASE("rhs_jacobian and input_jacobian = central differences of accelerations, every model", "[codegen][jacobians]") {
    for (Spec& s : all_models()) {
        INFO(s.name);
        const Errors e = compare_with_differences(s, 6, 20261201);
        CHECK(e.states >= 3);
        CHECK(e.rhs < 1e-7);
        CHECK(e.input < 1e-7);
    }
}

// Bugs caught: ∂F/∂q taken as symmetric when the non-conservative forces are not (functions:
// force x depends on y, force y not on x; driven: a dissipation with an input), ∂F/∂q'
// taken as (∂p/∂q)ᵀ without ∂N/∂q', a transposed block of dp or dF, p and F of
// canonical_jacobian not those of momenta and generalized_forces.
TEST_CASE("canonical_jacobian = central differences of momenta and generalized_forces, every model", "[codegen][jacobians]") {
    for (Spec& s : all_models()) {
        INFO(s.name);
        const Errors e = compare_with_differences(s, 6, 20261202);
        CHECK(e.states >= 3);
        CHECK(e.canonical < 1e-7);
        CHECK(e.canonical_values < 1e-13);
    }
}

// Bug caught: a sign or factor in the simplest entries (−g/l cos θ).
TEST_CASE("pendulum: J = [[0, 1], [-g/l cos th, 0]] exactly", "[codegen][jacobians]") {
    pendulum::Parameters P;
    P.g = 9.5;
    P.l = 0.75;
    const double q[] = {0.7}, v[] = {-1.3};
    double J[4];
    pendulum::rhs_jacobian(P, 0, q, v, J);
    CHECK(J[0] == 0);
    CHECK(J[1] == 1);
    CHECK(J[2] == Approx(-P.g / P.l * std::cos(0.7)).epsilon(1e-15));
    CHECK(J[3] == 0);
}

// Bug caught: input_jacobian's rows swapped with the zero block, or a wrong size check.
TEST_CASE("four-bar input_jacobian: a zero top block, a nonzero dq''/dtau, sizes checked", "[codegen][jacobians]") {
    const four_bar::Parameters P;
    std::vector<double> q(3), v(3), B(6);
    four_bar::initial_state(P, q, v);
    four_bar::input_jacobian(P, 0, q, v, B);
    for (int i = 0; i < 3; ++i) CHECK(B[i] == 0);
    CHECK(std::fabs(B[3]) > 1e-3);
    std::vector<double> wrong(5);
    CHECK_THROWS_AS(four_bar::input_jacobian(P, 0, q, v, wrong), std::invalid_argument);
    std::vector<double> J(35);
    CHECK_THROWS_AS(four_bar::rhs_jacobian(P, 0, q, v, J), std::invalid_argument);
}

namespace {

using phynjo::runtime::kGQ;
using phynjo::runtime::kGV;
using phynjo::runtime::LagrangianSystem;
using phynjo::runtime::Stepper;
using phynjo::runtime::World;

/// The largest difference, relative to max(1, |x|), between one implicit midpoint step solved
/// by Newton (canonical_jacobian) and by the fixed-point iteration, from random states near
/// the initial one; and whether two Newton runs agree bit for bit.
double newton_against_fixed_point(const LagrangianSystem& newton, double dt, int samples, bool& bitwise) {
    LagrangianSystem fixed = newton;
    fixed.canonical_jacobian = nullptr;
    std::mt19937_64 rng(99);
    std::normal_distribution<double> d(0, 0.05);
    double worst = 0;
    bitwise = true;
    for (int k = 0; k < samples; ++k) {
        World w0 = phynjo::runtime::make_lagrangian_world(newton);
        for (std::size_t i = 0; i < newton.dof; ++i) {
            w0.at(kGQ, i) += d(rng);
            w0.at(kGV, i) += d(rng);
        }
        World a = w0, b = w0, c = w0;
        Stepper(phynjo::runtime::lagrangian_midpoint(newton, a.layout_ptr())).step(a, dt);
        Stepper(phynjo::runtime::lagrangian_midpoint(newton, c.layout_ptr())).step(c, dt);
        Stepper(phynjo::runtime::lagrangian_midpoint(fixed, b.layout_ptr())).step(b, dt);
        for (auto f : {kGQ, kGV})
            for (std::size_t i = 0; i < newton.dof; ++i) {
                worst = std::max(worst, std::fabs(a.at(f, i) - b.at(f, i)) / std::max(1.0, std::fabs(b.at(f, i))));
                bitwise = bitwise && a.at(f, i) == c.at(f, i);
            }
    }
    return worst;
}

} // namespace

// Bugs caught: a wrong term in the Newton matrix (∂p/∂q, ∂F/∂q', the 2/dt·M scaling) — it
// converges slowly or to nothing (ConvergenceError) —, a stopping rule that leaves the
// Newton solution short of the fixed point's, the end velocities from the wrong momenta.
TEST_CASE("implicit midpoint: Newton with the exact Jacobian = the fixed-point iteration (1e-13)", "[codegen][jacobians]") {
    bool bitwise = false;
    const std::pair<const char*, LagrangianSystem> systems[] = {
        {"double_pendulum", double_pendulum::system({})},
        {"cart_pole", cart_pole::system({})},
        {"triple_pendulum", triple_pendulum::system({})},
        {"relativistic", relativistic::system({})},
        {"bateman", bateman::system({})},
        {"driven", driven::system({})},
        {"spring_pendulum", spring_pendulum::system({})},
        {"nlink_cart_5", nlink_cart_5::system({})},
        {"four_bar", four_bar::system({})},
        {"cartesian_pendulum", cartesian_pendulum::system({})}};
    for (const auto& [name, sys] : systems) {
        INFO(name);
        CHECK(newton_against_fixed_point(sys, 1e-2, 20, bitwise) < 1e-13);
        CHECK(bitwise);
    }
}

// Bug caught: a wrong or missing term in the Newton matrix (∂p/∂q, ∂F/∂q', ∂F/∂q, the
// 2/dt·M scaling): the iteration then still converges, but linearly — more evaluations per
// step. With the exact matrix Newton converges quadratically: from the explicit guess, at
// most 5 evaluations of canonical_jacobian per step over 200 steps of dt = 10 ms (measured:
// 5 on all three models; with ∂F/∂q' left out 9 and 11, with ∂F/∂q left out 7 and 6, on the
// double pendulum and the driven model, whose forces depend on q and q').
TEST_CASE("implicit midpoint: Newton converges quadratically (at most 5 Jacobian evaluations a step)", "[codegen][jacobians]") {
    for (const LagrangianSystem& base : {double_pendulum::system({}), driven::system({}), relativistic::system({})}) {
        auto calls = std::make_shared<int>(0);
        LagrangianSystem s = base;
        s.canonical_jacobian = [calls, f = base.canonical_jacobian](double t, auto q, auto v, auto p, auto F, auto dp,
                                                                    auto dF) {
            ++*calls;
            f(t, q, v, p, F, dp, dF);
        };
        World w = phynjo::runtime::make_lagrangian_world(s);
        Stepper st(phynjo::runtime::lagrangian_midpoint(s, w.layout_ptr()));
        int worst = 0;
        for (int k = 0; k < 200; ++k) {
            *calls = 0;
            st.step(w, 1e-2);
            worst = std::max(worst, *calls);
        }
        INFO(s.coordinate_names[0]);
        CHECK(worst <= 5);
    }
}

// Bugs caught: the diagonal-M path of the generated accelerations dividing by the wrong
// entry, or rounding differently from the LDLᵀ path it replaces; a zero mass not reported.
TEST_CASE("diagonal mass matrix: accelerations f_i/M_ii, the same bits as the LDLT solve", "[codegen][jacobians]") {
    stiff_chain::Parameters P;
    P.m = 1.7;
    std::mt19937_64 rng(5);
    std::normal_distribution<double> d(0, 1);
    for (int k = 0; k < 50; ++k) {
        double q[3], v[3], a[3], M[9], f[3];
        for (int i = 0; i < 3; ++i) {
            q[i] = d(rng);
            v[i] = d(rng);
        }
        stiff_chain::accelerations(P, 0, q, v, a);
        stiff_chain::mass_matrix(P, 0, q, M);
        stiff_chain::forcing(P, 0, q, v, f);
        phynjo::runtime::solve_symmetric<3>(M, f);
        for (int i = 0; i < 3; ++i) CHECK(a[i] == f[i]);
    }
    P.m = 0;
    double q[3] = {0, 0, 0}, v[3] = {0, 0, 0}, a[3];
    CHECK_THROWS_AS(stiff_chain::accelerations(P, 0, q, v, a), phynjo::runtime::SingularMassMatrix);
}
