#pragma once
/// \file
/// Solving with a symmetric matrix (a mass matrix M, or G M⁻¹ Gᵀ): LDLᵀ when positive
/// definite, LU with partial pivoting otherwise. Fixed size, no allocation.
#include "phynjo/runtime/core/errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>

namespace phynjo::runtime {

/// The relative size below which a pivot (or a 2×2 determinant) counts as zero: the mass
/// matrix is then singular at that state.
inline constexpr double kSingularTolerance = 1e-13;

/// A factorization of a symmetric N×N matrix, for solving with several right-hand sides.
/// LDLᵀ without pivoting first (every positive definite matrix: the usual kinetic energy);
/// when a pivot is not positive — an indefinite but invertible matrix, e.g. the mass matrix
/// of Bateman's dual oscillator — LU with partial pivoting of the same matrix. Throws
/// SingularMassMatrix only when the matrix is singular (an LU pivot below
/// kSingularTolerance times the largest entry), NonFiniteResult for NaN or infinite input.
template <std::size_t N>
class SymmetricFactor {
public:
    /// Factors the matrix whose lower triangle is `A` (row-major N×N; the upper part is not read).
    explicit SymmetricFactor(const double* A) {
        double top = 0; // the largest entry of the lower triangle
        for (std::size_t i = 0; i < N; ++i)
            for (std::size_t j = 0; j <= i; ++j) top = std::max(top, std::fabs(A[i * N + j]));
        for (std::size_t i = 0; i < N * N; ++i) F_[i] = A[i];
        // LDLᵀ: L below the diagonal, D on it; a pivot not above kSingularTolerance·max|A|
        // hands over to pivoted LU (which then decides whether A is singular).
        for (std::size_t j = 0; j < N; ++j) {
            double d = F_[j * N + j];
            for (std::size_t k = 0; k < j; ++k) d -= F_[j * N + k] * F_[j * N + k] * F_[k * N + k];
            if (!std::isfinite(d)) throw NonFiniteResult("mass matrix has a non-finite entry");
            if (!(d > kSingularTolerance * top)) {
                ldlt_ = false;
                break;
            }
            F_[j * N + j] = d;
            for (std::size_t i = j + 1; i < N; ++i) {
                double s = F_[i * N + j];
                for (std::size_t k = 0; k < j; ++k) s -= F_[i * N + k] * F_[j * N + k] * F_[k * N + k];
                F_[i * N + j] = s / d;
            }
        }
        if (ldlt_) return;
        // LU with partial pivoting on the full matrix rebuilt from the lower triangle. The
        // multiplier of row position r at step c is kept in F_[r][c] (rows are swapped from
        // column c on only), so solve() replays the elimination step by step.
        double scale = 0;
        for (std::size_t i = 0; i < N; ++i)
            for (std::size_t j = 0; j < N; ++j) {
                F_[i * N + j] = i >= j ? A[i * N + j] : A[j * N + i];
                scale = std::max(scale, std::fabs(F_[i * N + j]));
            }
        for (std::size_t c = 0; c < N; ++c) {
            std::size_t piv = c;
            for (std::size_t r = c + 1; r < N; ++r)
                if (std::fabs(F_[r * N + c]) > std::fabs(F_[piv * N + c])) piv = r;
            if (!(std::fabs(F_[piv * N + c]) > kSingularTolerance * scale))
                throw SingularMassMatrix("mass matrix is singular (pivot " + std::to_string(c) + " is " +
                                         std::to_string(F_[piv * N + c]) + ")");
            perm_[c] = piv;
            if (piv != c)
                for (std::size_t j = c; j < N; ++j) std::swap(F_[c * N + j], F_[piv * N + j]);
            for (std::size_t r = c + 1; r < N; ++r) {
                const double f = F_[r * N + c] / F_[c * N + c];
                for (std::size_t j = c + 1; j < N; ++j) F_[r * N + j] -= f * F_[c * N + j];
                F_[r * N + c] = f;
            }
        }
    }

    /// Overwrites b (length N) with x solving A x = b.
    void solve(double* b) const {
        if (ldlt_) {
            for (std::size_t i = 0; i < N; ++i)
                for (std::size_t k = 0; k < i; ++k) b[i] -= F_[i * N + k] * b[k];
            for (std::size_t i = 0; i < N; ++i) b[i] /= F_[i * N + i];
            for (std::size_t i = N; i-- > 0;)
                for (std::size_t k = i + 1; k < N; ++k) b[i] -= F_[k * N + i] * b[k];
            return;
        }
        for (std::size_t c = 0; c < N; ++c) {
            if (perm_[c] != c) std::swap(b[c], b[perm_[c]]);
            for (std::size_t r = c + 1; r < N; ++r) b[r] -= F_[r * N + c] * b[c];
        }
        for (std::size_t i = N; i-- > 0;) {
            double x = b[i];
            for (std::size_t j = i + 1; j < N; ++j) x -= F_[i * N + j] * b[j];
            b[i] = x / F_[i * N + i];
        }
    }

    /// True when the LDLᵀ factorization succeeded (the matrix is positive definite).
    [[nodiscard]] bool positive_definite() const noexcept { return ldlt_; }

private:
    double F_[N * N];
    std::size_t perm_[N]{};
    bool ldlt_ = true;
};

/// Solves M x = b for a symmetric N×N mass matrix M (row-major; only its lower triangle is
/// read); b is overwritten with x. See SymmetricFactor. Allocates nothing.
template <std::size_t N>
inline void solve_symmetric(double (&M)[N * N], double (&b)[N]) {
    const SymmetricFactor<N> factor(M);
    factor.solve(b);
}

} // namespace phynjo::runtime
