// Every solve path the emitter writes into `accelerations` — closed-form 1×1 (pendulum),
// closed-form 2×2 (double, spring and spherical pendulum, cart-pole), LDLᵀ at n = 3 (triple
// pendulum) and n = 6 (n-link cart) — against an independent solve of M q'' = f: Eigen's
// full-pivot LU on the generated mass_matrix and forcing, at random states.
// Catches: a sign or index error in an emitted closed form (e.g. qddot[1] of the 2×2), a wrong
// forward/back substitution or pivot in solve_spd, M and f taken from mismatched CSE slots.
#include "cart_pole.hpp"
#include "double_pendulum.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "spherical_pendulum.hpp"
#include "spring_pendulum.hpp"
#include "triple_pendulum.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <random>
#include <string>
#include <vector>

namespace {

struct Checked {
    int states = 0;
    double worst = 0; // largest |q''_gen − q''_ref| / (1 + |q''_ref|)
};

template <std::size_t n, typename Parameters, typename Acc, typename Mass, typename Force>
Checked against_independent_solve(const Parameters& P, Acc accelerations, Mass mass_matrix, Force forcing,
                                  std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> angle(-3.0, 3.0), speed(-2.0, 2.0), time(0.0, 5.0);
    Checked out;
    std::vector<double> q(n), v(n), a(n), M(n * n), f(n);
    for (int trial = 0; trial < 200; ++trial) {
        for (std::size_t i = 0; i < n; ++i) {
            q[i] = angle(rng);
            v[i] = speed(rng);
        }
        const double t = time(rng);
        mass_matrix(P, t, q, M);
        forcing(P, t, q, v, f);
        const Eigen::Matrix<double, n, n, Eigen::RowMajor> Me = Eigen::Map<const Eigen::Matrix<double, n, n, Eigen::RowMajor>>(M.data());
        const Eigen::Matrix<double, n, 1> fe = Eigen::Map<const Eigen::Matrix<double, n, 1>>(f.data());
        const Eigen::FullPivLU<Eigen::Matrix<double, n, n>> lu(Me);
        const double cond = 1 / lu.rcond(); // an estimate, in the 1-norm
        if (!(cond < 1e6)) continue; // near-singular states (e.g. sin θ ≈ 0) say nothing about the solve
        const Eigen::Matrix<double, n, 1> ref = lu.solve(fe);
        accelerations(P, t, q, v, a);
        for (std::size_t i = 0; i < n; ++i)
            out.worst = std::max(out.worst, std::abs(a[i] - ref(static_cast<Eigen::Index>(i))) /
                                                 (1 + std::abs(ref(static_cast<Eigen::Index>(i)))) / cond);
        ++out.states;
    }
    return out;
}

#define PHYNJO_SOLVE_CHECK(NS, SEED)                                                                             \
    do {                                                                                                         \
        const NS::Parameters P;                                                                                  \
        const Checked c = against_independent_solve<NS::dof>(P, &NS::accelerations, &NS::mass_matrix,            \
                                                             &NS::forcing, SEED);                                \
        INFO(#NS << " (" << NS::dof << " dof): " << c.states << " states, worst error / cond " << c.worst);      \
        CHECK(c.states >= 150);                                                                                  \
        CHECK(c.worst < 1e-13);                                                                                  \
    } while (0)

} // namespace

TEST_CASE("emitted 1x1 solve: accelerations agree with an independent solve of M q'' = f", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(pendulum, 1);
}

TEST_CASE("emitted 2x2 closed form: accelerations agree with an independent solve of M q'' = f", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(double_pendulum, 2);
    PHYNJO_SOLVE_CHECK(spring_pendulum, 3);
    PHYNJO_SOLVE_CHECK(spherical_pendulum, 4);
    PHYNJO_SOLVE_CHECK(cart_pole, 5);
}

TEST_CASE("emitted LDLT solve: accelerations agree with an independent solve of M q'' = f", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(triple_pendulum, 6);
    PHYNJO_SOLVE_CHECK(nlink_cart_5, 7);
}
