// Every solve path the emitter writes into `accelerations` — closed-form 1×1 (pendulum; a
// negative M), closed-form 2×2 (double, spring and spherical pendulum, cart-pole; Bateman's
// indefinite M), LDLᵀ at n = 3 (triple pendulum) and n = 6 (n-link cart), and the pivoted-LU
// fallback for an indefinite M (indefinite3) — against an independent solve of M q'' = f:
// Eigen's full-pivot LU on the generated mass_matrix and forcing, at random states.
// Catches: a sign or index error in an emitted closed form (e.g. qddot[1] of the 2×2), a wrong
// forward/back substitution or pivot in solve_symmetric, M and f taken from mismatched CSE
// slots, an invertible indefinite M reported as singular.
#include "cart_pole.hpp"
#include "double_pendulum.hpp"
#include "bateman.hpp"
#include "collide.hpp"
#include "indefinite3.hpp"
#include "negative_mass.hpp"
#include "nlink_cart_5.hpp"
#include "pendulum.hpp"
#include "spherical_pendulum.hpp"
#include "spring_pendulum.hpp"
#include "triple_pendulum.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <cmath>
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
    PHYNJO_SOLVE_CHECK(negative_mass, 8);
}

TEST_CASE("emitted 2x2 closed form: accelerations agree with an independent solve of M q'' = f", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(double_pendulum, 2);
    PHYNJO_SOLVE_CHECK(spring_pendulum, 3);
    PHYNJO_SOLVE_CHECK(spherical_pendulum, 4);
    PHYNJO_SOLVE_CHECK(cart_pole, 5);
    PHYNJO_SOLVE_CHECK(bateman, 9);
}

TEST_CASE("emitted LDLT solve: accelerations agree with an independent solve of M q'' = f", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(triple_pendulum, 6);
    PHYNJO_SOLVE_CHECK(nlink_cart_5, 7);
}

TEST_CASE("an indefinite but invertible M is solved by the pivoted fallback, a singular one is reported", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(indefinite3, 10);
    // singular: m = 0 leaves only z' in the kinetic energy
    indefinite3::Parameters P;
    P.m = 0;
    std::vector<double> q{0.1, 0.2, 0.3}, v{0.1, 0.2, 0.3}, a(3);
    CHECK_THROWS_AS(indefinite3::accelerations(P, 0, q, v, a), phynjo::runtime::SingularMassMatrix);
    bateman::Parameters B;
    B.m = 0;
    std::vector<double> q2{0.1, 0.2}, v2{0.3, 0.4}, a2(2);
    CHECK_THROWS_AS(bateman::accelerations(B, 0, q2, v2, a2), phynjo::runtime::SingularMassMatrix);
}

// Catches: generated names colliding with the user's (a coordinate x1 taken for CSE
// temporary x1, a parameter x0 for temporary x0: a redeclared local, or worse, a silently
// wrong value). The model compiles at all only without collisions; here its values.
TEST_CASE("user names like the emitter's own temporaries and locals", "[codegen][generated][solve]") {
    PHYNJO_SOLVE_CHECK(collide, 11);
    const collide::Parameters P;
    std::vector<double> q(4), v(4);
    collide::initial_state(P, q, v);
    CHECK(q[0] == Approx(1.0 / 3));
    CHECK(q[1] == Approx(2.0 / 5));
    CHECK(q[2] == Approx(std::sqrt(2.0)));
    CHECK(q[3] == Approx(1.0 / 3));
    CHECK(v[0] == Approx(3.0 / 4));
    CHECK(v[1] == 0);
    // the mass matrix reads the parameters named P and M, not the function's own P and M
    std::vector<double> M(16);
    collide::mass_matrix(P, 0, q, M);
    CHECK(M[0] == Approx(3));  // P
    CHECK(M[5] == Approx(1));  // M
    CHECK(M[10] == Approx(2)); // inv
    CHECK(M[15] == Approx(1)); // det
    CHECK(M[1] == Approx(0.5 * std::cos(std::sqrt(2.0)))); // f0 cos(x_0)
}
