#pragma once
// The Newton systems of the implicit integrators on y = (q, q') (bdf.cpp, CVODE's
// second_order_linear_solver.cpp): (I − cJ) x = b with the exact J = ∂y'/∂y of
// y' = (q', a(q, q')), J = [[0, I], [J_q, J_v]] (rhs_jacobian: row-major, 2n × 2n).
//
// The first block row gives x₁ = b₁ + c x₂, which leaves the n × n Schur complement
//     S = I − c J_v − c² J_q,   S x₂ = b₂ + c J_q b₁.
// S is factored by Gaussian elimination with partial pivoting restricted to its band (kl
// sub- and ku superdiagonals, read off S itself at each factorization: exact for any S, and
// O(n kl (kl + ku)) instead of O(n³) where the model couples neighbours only — a chain's S is
// tridiagonal). J_q b₁ runs over each row's nonzero columns. Internal to the runtime; tested
// against Eigen's dense LU in tests/runtime/test_sundials_kernels.cpp.
#include <cstddef>
#include <span>
#include <vector>

namespace phynjo::runtime::integrators {

/// LU factors with partial pivoting of an n × n band matrix (kl sub-, ku superdiagonals),
/// LAPACK's dgbtf2/dgbtrs: the rows are stored from column i − kl to i + kl + ku (room for
/// the fill the interchanges bring, U having kl + ku superdiagonals); the multipliers stay
/// where they were made, so the interchanges are applied one at a time in the forward
/// substitution.
class BandedLu {
public:
    /// An n × n zero matrix of bandwidths (kl, ku), to be filled through at().
    void reset(std::size_t n, std::size_t kl, std::size_t ku);
    /// Entry (i, j), |j − i| within the band (j − i ∈ [−kl, ku]).
    double& at(std::size_t i, std::size_t j) { return a_[i * width_ + (j + kl_ - i)]; }
    /// Factors the matrix in place. Returns 0, or k + 1 when pivot k is exactly zero (the
    /// matrix is singular; the factors are then unusable).
    std::size_t factor();
    /// The dense row-major n × n A: its bandwidths read off its nonzeros, then factor().
    std::size_t factor(std::span<const double> A, std::size_t n);
    /// b := A⁻¹ b (b: n entries), with the factors of the last successful factor().
    void solve(double* b) const;
    [[nodiscard]] std::size_t lower() const { return kl_; } ///< sub-diagonals
    [[nodiscard]] std::size_t upper() const { return ku_; } ///< super-diagonals

private:
    std::size_t n_ = 0, kl_ = 0, ku_ = 0, width_ = 1; ///< width_ = 2 kl + ku + 1
    std::vector<double> a_;          ///< n + kl rows of width_ (the rows past n zero): L's multipliers, D⁻¹U
    std::vector<double> inv_diag_;   ///< 1 / U_kk
    std::vector<std::size_t> piv_;   ///< the row interchanged with row k at step k
    bool interchanged_ = false;      ///< some piv_[k] ≠ k
    mutable std::vector<double> b_;  ///< solve's b, with kl + ku zeros past n
};

/// (I − cJ) x = b for J of a second-order system, by block elimination and a banded LU of S.
class VelocitySchur {
public:
    explicit VelocitySchur(std::size_t n);
    /// A new J (row-major 2n × 2n, read again by factor and solve: keep it alive, and call
    /// this again when it changes): the nonzero columns of each row of J_q and J_v, so the
    /// band of S.
    void set_jacobian(const double* J);
    /// Forms S = I − c J_v − c² J_q within its band and factors it. Returns 0, or k + 1 for a
    /// zero pivot k.
    std::size_t factor(double c);
    /// x = (I − cJ)⁻¹ b with the J and c of the last factor(); x and b may be one array.
    void solve(const double* b, double* x);
    [[nodiscard]] const BandedLu& lu() const { return lu_; }

private:
    std::size_t n_, kl_ = 0, ku_ = 0;
    const double* J_ = nullptr;
    double c_ = 0;
    std::vector<double> r_;
    std::vector<std::size_t> first_, last_; ///< row i of J_q: nonzero columns within [first_, last_)
    BandedLu lu_;
};

} // namespace phynjo::runtime::integrators
