#pragma once
// A small dense Cholesky kit for the contact solver's model coupling (internal): M and the
// constraints' Schur complement of a model are a few coordinates wide.
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace phynjo::runtime::contact_detail {

/// L Lᵀ = A in place (row-major n×n; the lower triangle becomes L); false unless A is
/// positive definite (a pivot at or below 1e-14 of the largest diagonal entry).
inline bool cholesky(double* A, std::size_t n) {
    double dmax = 0;
    for (std::size_t i = 0; i < n; ++i) dmax = std::max(dmax, A[i * n + i]);
    for (std::size_t j = 0; j < n; ++j) {
        double d = A[j * n + j];
        for (std::size_t k = 0; k < j; ++k) d -= A[j * n + k] * A[j * n + k];
        if (!(d > 1e-14 * dmax)) return false;
        d = std::sqrt(d);
        A[j * n + j] = d;
        for (std::size_t i = j + 1; i < n; ++i) {
            double v = A[i * n + j];
            for (std::size_t k = 0; k < j; ++k) v -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = v / d;
        }
    }
    return true;
}

/// Solves L Lᵀ x = b in place, b's entries `stride` apart (a column of a row-major matrix).
inline void cholesky_solve(const double* L, std::size_t n, double* b, std::size_t stride) {
    for (std::size_t i = 0; i < n; ++i) {
        double v = b[i * stride];
        for (std::size_t k = 0; k < i; ++k) v -= L[i * n + k] * b[k * stride];
        b[i * stride] = v / L[i * n + i];
    }
    for (std::size_t i = n; i-- > 0;) {
        double v = b[i * stride];
        for (std::size_t k = i + 1; k < n; ++k) v -= L[k * n + i] * b[k * stride];
        b[i * stride] = v / L[i * n + i];
    }
}

} // namespace phynjo::runtime::contact_detail
