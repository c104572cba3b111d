#pragma once
// Internals shared by the implicit integrators of generated models (lagrangian_midpoint.cpp,
// lagrangian_rattle.cpp): velocities from momenta, and a small dense solve.
#include "phynjo/runtime/models/lagrangian_system.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace phynjo::runtime::detail {

/// Velocities v with p(t, q, v) = p, from the guess in v: Newton with the mass matrix
/// M = ∂p/∂v as Jacobian, factorized once per call when M does not depend on v (exact after
/// one iteration when L is quadratic in the velocities), at every iteration when it does.
/// `M` and `r` are scratch of sizes n² and n.
inline void velocities_from_momenta(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> p,
                             std::span<double> v, std::vector<double>& M, std::vector<double>& r,
                             std::vector<std::size_t>& perm) {
    const std::size_t n = s.dof;
    perm.resize(n);
    auto factor = [&] { // LU with partial pivoting of M at (t, q, v)
        s.mass_matrix(t, q, v, M);
        for (std::size_t c = 0; c < n; ++c) {
            std::size_t piv = c;
            for (std::size_t k = c + 1; k < n; ++k)
                if (std::fabs(M[k * n + c]) > std::fabs(M[piv * n + c])) piv = k;
            if (!(std::fabs(M[piv * n + c]) > 0)) throw SingularMassMatrix("mass matrix is singular");
            perm[c] = piv;
            if (piv != c)
                for (std::size_t k = 0; k < n; ++k) std::swap(M[c * n + k], M[piv * n + k]);
            for (std::size_t k = c + 1; k < n; ++k) {
                M[k * n + c] /= M[c * n + c];
                for (std::size_t j = c + 1; j < n; ++j) M[k * n + j] -= M[k * n + c] * M[c * n + j];
            }
        }
    };
    factor();
    for (int it = 0; it < 50; ++it) {
        if (it > 0 && s.mass_depends_on_velocities) factor();
        s.momenta(t, q, v, r);
        for (std::size_t i = 0; i < n; ++i) r[i] = p[i] - r[i];
        for (std::size_t c = 0; c < n; ++c) {
            std::swap(r[c], r[perm[c]]);
            for (std::size_t k = c + 1; k < n; ++k) r[k] -= M[k * n + c] * r[c];
        }
        for (std::size_t c = n; c-- > 0;) {
            double x = r[c];
            for (std::size_t j = c + 1; j < n; ++j) x -= M[c * n + j] * r[j];
            r[c] = x / M[c * n + c];
        }
        double change = 0, scale = 0;
        for (std::size_t i = 0; i < n; ++i) {
            v[i] += r[i];
            change = std::max(change, std::fabs(r[i]));
            scale = std::max(scale, std::fabs(v[i]));
        }
        if (change <= 1e-13 * (1 + scale)) return; // the next correction would be round-off
    }
}

/// Solves M x = b in place with the LU factors velocities_from_momenta leaves in `M`, `perm`.
inline void solve_factored(const std::vector<double>& M, const std::vector<std::size_t>& perm, std::span<double> b) {
    const std::size_t n = perm.size();
    for (std::size_t c = 0; c < n; ++c) {
        std::swap(b[c], b[perm[c]]);
        for (std::size_t k = c + 1; k < n; ++k) b[k] -= M[k * n + c] * b[c];
    }
    for (std::size_t c = n; c-- > 0;) {
        double x = b[c];
        for (std::size_t j = c + 1; j < n; ++j) x -= M[c * n + j] * b[j];
        b[c] = x / M[c * n + c];
    }
}

/// Solves A x = b in place (A p×p row-major, overwritten) by LU with partial pivoting;
/// false when A is singular.
inline bool dense_solve(std::vector<double>& A, std::vector<double>& b, std::size_t p) {
    double scale = 0;
    for (double a : A) scale = std::max(scale, std::fabs(a));
    for (std::size_t c = 0; c < p; ++c) {
        std::size_t piv = c;
        for (std::size_t i = c + 1; i < p; ++i)
            if (std::fabs(A[i * p + c]) > std::fabs(A[piv * p + c])) piv = i;
        if (!(std::fabs(A[piv * p + c]) > 1e-14 * scale)) return false;
        if (piv != c) {
            for (std::size_t j = 0; j < p; ++j) std::swap(A[c * p + j], A[piv * p + j]);
            std::swap(b[c], b[piv]);
        }
        for (std::size_t i = c + 1; i < p; ++i) {
            const double f = A[i * p + c] / A[c * p + c];
            for (std::size_t j = c; j < p; ++j) A[i * p + j] -= f * A[c * p + j];
            b[i] -= f * b[c];
        }
    }
    for (std::size_t i = p; i-- > 0;) {
        double x = b[i];
        for (std::size_t j = i + 1; j < p; ++j) x -= A[i * p + j] * b[j];
        b[i] = x / A[i * p + i];
    }
    return true;
}

} // namespace phynjo::runtime::detail
