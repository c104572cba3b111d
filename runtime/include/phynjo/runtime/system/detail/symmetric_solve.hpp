#pragma once
/// \file
/// Solving with a symmetric matrix (a mass matrix M, or G M⁻¹ Gᵀ): LDLᵀ when positive
/// definite, LU with partial pivoting otherwise (factor_core.hpp). Fixed size, no allocation.
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/system/detail/factor_core.hpp"

#include <cstddef>
#include <string>

namespace phynjo::runtime {

namespace detail {
/// The typed exception of a failed factorization of a mass matrix.
[[noreturn]] inline void throw_factor_failure(Factored status, std::size_t pivot, double value) {
    if (status == Factored::non_finite) throw NonFiniteResult("mass matrix has a non-finite entry");
    throw SingularMassMatrix("mass matrix is singular (pivot " + std::to_string(pivot) + " is " + std::to_string(value) + ")");
}
} // namespace detail

/// A factorization of a symmetric N×N matrix, for solving with several right-hand sides
/// (detail::SymmetricCore). Throws SingularMassMatrix only when the matrix is singular (an LU
/// pivot below kSingularTolerance times the largest entry), NonFiniteResult for NaN or
/// infinite input.
template <std::size_t N>
class SymmetricFactor {
public:
    /// Factors the matrix whose lower triangle is `A` (row-major N×N; the upper part is not read).
    explicit SymmetricFactor(const double* A) {
        if (const detail::Factored f = core_.factor(A); f != detail::Factored::ok)
            detail::throw_factor_failure(f, core_.pivot(), core_.pivot_value());
    }
    /// Overwrites b (length N) with x solving A x = b.
    void solve(double* b) const { core_.solve(b); }
    /// True when the LDLᵀ factorization succeeded (the matrix is positive definite).
    [[nodiscard]] bool positive_definite() const noexcept { return core_.positive_definite(); }

private:
    detail::SymmetricCore<N> core_;
};

/// Solves M x = b for a symmetric N×N mass matrix M (row-major; only its lower triangle is
/// read); b is overwritten with x. See SymmetricFactor. Allocates nothing.
template <std::size_t N>
inline void solve_symmetric(double (&M)[N * N], double (&b)[N]) {
    const SymmetricFactor<N> factor(M);
    factor.solve(b);
}

} // namespace phynjo::runtime
