#pragma once
// Internals shared by the implicit integrators of generated models (lagrangian_midpoint.cpp,
// lagrangian_rattle.cpp): velocities from momenta, and solves with their factors.
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

namespace phynjo::runtime::detail {

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
        solve_factored(M, perm, r);
        double change = 0, scale = 0;
        for (std::size_t i = 0; i < n; ++i) {
            v[i] += r[i];
            change = std::max(change, std::fabs(r[i]));
            scale = std::max(scale, std::fabs(v[i]));
        }
        if (change <= 1e-13 * (1 + scale)) return; // the next correction would be round-off
    }
}

} // namespace phynjo::runtime::detail
