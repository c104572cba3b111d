// The runtime's own pieces under SUNDIALS (internal: runtime/src/integrators): the reduced
// Newton systems of second-order ODEs (second_order_linear_solver.hpp) against a dense solve
// of the full system, and the serial-vector operations (serial_vector_ops.hpp) against
// SUNDIALS' own.
#include "second_order_linear_solver.hpp"
#include "serial_vector_ops.hpp"
#include "velocity_schur.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using phynjo::runtime::sundials::SecondOrderNewton;

namespace {

struct Context {
    SUNContext ctx = nullptr;
    Context() { SUNContext_Create(nullptr, &ctx); }
    ~Context() { SUNContext_Free(&ctx); }
};

struct Vector {
    N_Vector v;
    Vector(long n, SUNContext ctx) : v(N_VNew_Serial(n, ctx)) {}
    ~Vector() { N_VDestroy(v); }
    double* data() const { return N_VGetArrayPointer(v); }
};

} // namespace

// Bugs caught: the Schur complement without γ² on J_q (or with the wrong sign), the
// right side b₂ + γJ_q b₁ without its γ, x₁ = b₁ + γx₂ left out, J_q read from the wrong
// block or with the wrong stride, b overwritten before it is read when x and b are one vector.
TEST_CASE("SecondOrderNewton: (I − γJ)x = b through the velocities' Schur complement = a dense solve", "[runtime][sundials]") {
    Context c;
    std::mt19937_64 rng(20261201);
    std::uniform_real_distribution<double> u(-1, 1);
    for (const long n : {1L, 2L, 7L, 30L})
        for (const double gamma : {1e-6, 0.01, 0.37, 3.0}) {
            INFO("n = " << n << ", gamma = " << gamma);
            const long N = 2 * n;
            // J = [[0, I], [J_q, J_v]], row-major as rhs_jacobian writes it
            std::vector<double> J(static_cast<std::size_t>(N * N), 0.0);
            for (long i = 0; i < n; ++i) J[static_cast<std::size_t>(i * N + n + i)] = 1.0;
            for (long i = n; i < N; ++i)
                for (long j = 0; j < N; ++j) J[static_cast<std::size_t>(i * N + j)] = 5 * u(rng);
            Eigen::MatrixXd A = Eigen::MatrixXd::Identity(N, N);
            for (long i = 0; i < N; ++i)
                for (long j = 0; j < N; ++j) A(i, j) -= gamma * J[static_cast<std::size_t>(i * N + j)];
            SecondOrderNewton newton(static_cast<std::size_t>(n), c.ctx);
            newton.form(J.data(), gamma);
            REQUIRE(SUNLinSolSetup(newton.solver(), newton.matrix()) == 0);
            Vector b(N, c.ctx), x(N, c.ctx);
            for (long i = 0; i < N; ++i) b.data()[i] = u(rng);
            const Eigen::VectorXd bb = Eigen::Map<const Eigen::VectorXd>(b.data(), N);
            const Eigen::VectorXd ref = A.fullPivLu().solve(bb);
            REQUIRE(SUNLinSolSolve(newton.solver(), newton.matrix(), x.v, b.v, 0.0) == 0);
            const Eigen::VectorXd xx = Eigen::Map<const Eigen::VectorXd>(x.data(), N);
            CHECK((A * xx - bb).norm() <= 1e-12 * (A.norm() * xx.norm() + bb.norm()));
            CHECK((xx - ref).norm() <= 1e-9 * (1 + ref.norm()));
            // x and b one vector
            REQUIRE(SUNLinSolSolve(newton.solver(), newton.matrix(), b.v, b.v, 0.0) == 0);
            CHECK(std::memcmp(b.data(), x.data(), sizeof(double) * static_cast<std::size_t>(N)) == 0);
        }
}

// Bug caught: a singular Schur complement reported as success (CVODE would go on with a
// factorization full of infinities) instead of a recoverable failure.
TEST_CASE("SecondOrderNewton: a singular Schur complement is a recoverable setup failure", "[runtime][sundials]") {
    Context c;
    const long n = 3, N = 6;
    const double gamma = 0.5;
    // J_v = I/γ, J_q = 0: S = I − γJ_v = 0
    std::vector<double> J(N * N, 0.0);
    for (long i = 0; i < n; ++i) {
        J[static_cast<std::size_t>(i * N + n + i)] = 1.0;
        J[static_cast<std::size_t>((n + i) * N + n + i)] = 1.0 / gamma;
    }
    SecondOrderNewton newton(n, c.ctx);
    newton.form(J.data(), gamma);
    CHECK(SUNLinSolSetup(newton.solver(), newton.matrix()) > 0);
}

// Bugs caught: U's fill from the interchanges cut off (kl + ku superdiagonals, not ku), a
// pivot search that stops short of row k + kl, the interchanges not replayed in the forward
// substitution or replayed on the multipliers, the bandwidths read off the wrong triangle, a
// fixed-width substitution picked for the wrong (kl, ku) (kl = 0, ku = 3 is not kl = 1,
// ku = 0), the band's rows past n not zero. Oracle: Eigen's full-pivoting dense LU.
TEST_CASE("BandedLu: solves = a dense LU, for every bandwidth, with interchanges", "[runtime][sundials]") {
    using phynjo::runtime::integrators::BandedLu;
    std::mt19937_64 rng(20261202);
    std::uniform_real_distribution<double> u(-1, 1);
    for (const std::size_t n : {1UL, 2UL, 5UL, 12UL, 30UL})
        for (const std::size_t kl : {0UL, 1UL, 2UL, 3UL, 7UL})
            for (const std::size_t ku : {0UL, 1UL, 2UL, 3UL, 11UL})
                for (const double diagonal : {0.0, 4.0}) { // 0: small pivots, the interchanges needed
                    INFO("n = " << n << ", kl = " << kl << ", ku = " << ku << ", diagonal " << diagonal);
                    std::vector<double> A(n * n, 0.0);
                    for (std::size_t i = 0; i < n; ++i)
                        for (std::size_t j = 0; j < n; ++j)
                            if (j + kl >= i && j <= i + ku) A[i * n + j] = u(rng) + (i == j ? diagonal : 0.0);
                    Eigen::MatrixXd M(n, n);
                    for (std::size_t i = 0; i < n; ++i)
                        for (std::size_t j = 0; j < n; ++j) M(i, j) = A[i * n + j];
                    BandedLu lu;
                    REQUIRE(lu.factor(A, n) == 0);
                    CHECK(lu.lower() == std::min(kl, n - 1));
                    CHECK(lu.upper() == std::min(ku, n - 1));
                    Eigen::VectorXd b(n);
                    for (std::size_t i = 0; i < n; ++i) b(i) = u(rng);
                    const Eigen::VectorXd ref = M.fullPivLu().solve(b);
                    Eigen::VectorXd x = b;
                    lu.solve(x.data());
                    CHECK((M * x - b).norm() <= 1e-11 * (M.norm() * x.norm() + b.norm()));
                    CHECK((x - ref).norm() <= 1e-8 * (1 + ref.norm()));
                }
    // an exactly singular band matrix: a zero pivot, reported with its index
    const std::vector<double> S = {1, 2, 0, 2, 4, 0, 0, 0, 3}; // rows 0 and 1 parallel
    BandedLu lu;
    CHECK(lu.factor(S, 3) == 2);
}

// Bugs caught: the band of S read off J_q alone (J_v's couplings dropped), J_q b₁ over a
// range that misses its last column, set_jacobian's ranges kept from an earlier J.
TEST_CASE("VelocitySchur: a banded J (a chain) and then a dense one = a dense solve of (I − cJ)", "[runtime][sundials]") {
    using phynjo::runtime::integrators::VelocitySchur;
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    const std::size_t n = 9, N = 2 * n;
    VelocitySchur schur(n);
    for (const int pass : {0, 1, 2}) { // 0: J_q tridiagonal, J_v two above the diagonal; 1: dense; 2: banded again
        std::vector<double> J(N * N, 0.0);
        for (std::size_t i = 0; i < n; ++i) J[i * N + n + i] = 1.0;
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) {
                const bool q = pass == 1 || (j + 1 >= i && j <= i + 1), v = pass == 1 || j == i + 2;
                if (q) J[(n + i) * N + j] = 1e3 * u(rng);
                if (v) J[(n + i) * N + n + j] = 10 * u(rng);
            }
        for (const double c : {1e-5, 0.02, 0.7}) {
            INFO("pass " << pass << ", c = " << c);
            Eigen::MatrixXd A = Eigen::MatrixXd::Identity(N, N);
            for (std::size_t i = 0; i < N; ++i)
                for (std::size_t j = 0; j < N; ++j) A(i, j) -= c * J[i * N + j];
            schur.set_jacobian(J.data());
            REQUIRE(schur.factor(c) == 0);
            CHECK(schur.lu().lower() == (pass == 1 ? n - 1 : 1));
            CHECK(schur.lu().upper() == (pass == 1 ? n - 1 : 2));
            Eigen::VectorXd b(N);
            for (std::size_t i = 0; i < N; ++i) b(i) = u(rng);
            Eigen::VectorXd x(N);
            schur.solve(b.data(), x.data());
            CHECK((A * x - b).norm() <= 1e-11 * (A.norm() * x.norm() + b.norm()));
            schur.solve(b.data(), b.data()); // in place
            CHECK((b - x).norm() == 0);
        }
    }
}

// Bugs caught: a case of N_VLinearSum_Serial computed another way (a·x + a·y for a·(x + y),
// a·x − y through a·x + (−1)·y contracted into an FMA …): different bits from SUNDIALS, so
// different steps; the in-place cases (z = x, z = y) reading what they already wrote.
TEST_CASE("serial vector ops: linear_sum gives N_VLinearSum_Serial's bits in every case", "[runtime][sundials]") {
    Context c;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-3, 3);
    const double r = 0.7315926535897932, s = -2.1828182845904523;
    const double pairs[][2] = {{1, 1}, {1, -1}, {-1, 1}, {1, r}, {r, 1}, {-1, r}, {r, -1}, {r, r},
                               {r, -r}, {r, s},  {0, s},  {s, 0}, {-1, -1}, {1, 0}, {0, 1}};
    for (const long n : {1L, 4L, 13L, 60L})
        for (const auto& ab : pairs)
            for (int alias = 0; alias < 3; ++alias) { // z separate, z = x, z = y
                INFO("n = " << n << ", a = " << ab[0] << ", b = " << ab[1] << ", alias " << alias);
                Vector x(n, c.ctx), y(n, c.ctx), z(n, c.ctx), x2(n, c.ctx), y2(n, c.ctx), z2(n, c.ctx);
                for (long i = 0; i < n; ++i) {
                    x.data()[i] = x2.data()[i] = u(rng);
                    y.data()[i] = y2.data()[i] = u(rng);
                }
                N_Vector out = alias == 0 ? z.v : alias == 1 ? x.v : y.v;
                N_Vector out2 = alias == 0 ? z2.v : alias == 1 ? x2.v : y2.v;
                phynjo::runtime::sundials::linear_sum(ab[0], x.v, ab[1], y.v, out);
                N_VLinearSum_Serial(ab[0], x2.v, ab[1], y2.v, out2);
                CHECK(std::memcmp(N_VGetArrayPointer(out), N_VGetArrayPointer(out2), sizeof(double) * static_cast<std::size_t>(n)) == 0);
            }
}

// Bugs caught: a partial sum dropped (lengths not a multiple of 4), the mean over the wrong
// length, no square root; and the ops not inherited by the vectors a solver clones.
TEST_CASE("serial vector ops: wrms_norm = N_VWrmsNorm_Serial to round-off, and clones inherit the ops", "[runtime][sundials]") {
    Context c;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-3, 3);
    for (long n = 1; n <= 67; n += 3) {
        Vector x(n, c.ctx), w(n, c.ctx);
        for (long i = 0; i < n; ++i) {
            x.data()[i] = u(rng);
            w.data()[i] = std::fabs(u(rng));
        }
        const double ours = phynjo::runtime::sundials::wrms_norm(x.v, w.v), theirs = N_VWrmsNorm_Serial(x.v, w.v);
        INFO("n = " << n);
        CHECK(std::fabs(ours - theirs) <= 1e-15 * theirs);
    }
    Vector v(5, c.ctx);
    phynjo::runtime::sundials::use_fast_serial_ops(v.v);
    N_Vector clone = N_VClone(v.v);
    CHECK(clone->ops->nvlinearsum == &phynjo::runtime::sundials::linear_sum);
    CHECK(clone->ops->nvwrmsnorm == &phynjo::runtime::sundials::wrms_norm);
    N_VDestroy(clone);
}
