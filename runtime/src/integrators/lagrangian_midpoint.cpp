// The implicit midpoint rule on the canonical variables (q, p) of a generated model:
//   q1 = q0 + dt·v(q_m, p_m),  p1 = p0 + dt·F(q_m, v_m),  q_m = (q0+q1)/2, p_m = (p0+p1)/2,
// solved by fixed-point iteration to round-off. Order 2; symplectic and symmetric, so the
// energy error of a conservative autonomous model stays bounded (it is not conserved exactly).
// Reference: E. Hairer, C. Lubich, G. Wanner, Geometric Numerical Integration, 2nd ed.,
// Springer 2006, §VI.3.
#include "phynjo/runtime/integrators/lagrangian_midpoint.hpp"

#include <algorithm>

namespace phynjo::runtime {

namespace {

/// Velocities v with p(t, q, v) = p, from the guess in v: Newton with the mass matrix
/// M = ∂p/∂v as Jacobian, factorized once per call when M does not depend on v (exact after
/// one iteration when L is quadratic in the velocities), at every iteration when it does.
/// `M` and `r` are scratch of sizes n² and n.
void velocities_from_momenta(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> p,
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

} // namespace

NumericWorkflow lagrangian_midpoint(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout) {
    const std::size_t n = s.dof;
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    NumericRule r{"implicit_midpoint", Domain(kGQ, all) | Domain(kGV, all), {}, nullptr, layout};
    r.step = [s, n](double dt, World& w) {
        thread_local std::vector<double> q0, p0, q1, p1, qm, pm, vm, F, M, tmp;
        thread_local std::vector<std::size_t> perm;
        for (auto* v : {&q0, &p0, &q1, &p1, &qm, &pm, &vm, &F, &tmp}) v->assign(n, 0.0);
        M.assign(n * n, 0.0);
        const double t0 = w.time, tm = t0 + 0.5 * dt;
        for (Index i = 0; i < n; ++i) {
            q0[i] = w.at(kGQ, i);
            vm[i] = w.at(kGV, i);
        }
        s.momenta(t0, q0, w.field(kGV), p0);
        q1 = q0;
        p1 = p0;
        for (Index i = 0; i < n; ++i) q1[i] = q0[i] + dt * vm[i];
        bool converged = false;
        for (int it = 0; it < 200 && !converged; ++it) {
            for (std::size_t i = 0; i < n; ++i) {
                qm[i] = 0.5 * (q0[i] + q1[i]);
                pm[i] = 0.5 * (p0[i] + p1[i]);
            }
            velocities_from_momenta(s, tm, qm, pm, vm, M, tmp, perm);
            s.generalized_forces(tm, qm, vm, F);
            double change = 0, scale = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const double nq = q0[i] + dt * vm[i], np = p0[i] + dt * F[i];
                change = std::max({change, std::fabs(nq - q1[i]), std::fabs(np - p1[i])});
                scale = std::max({scale, std::fabs(nq), std::fabs(np)});
                q1[i] = nq;
                p1[i] = np;
            }
            converged = change <= 4e-16 * (1 + scale);
        }
        if (!converged) throw ConvergenceError("implicit midpoint did not converge at t = " + std::to_string(t0) +
                                               " (step " + std::to_string(dt) + " too large?)");
        // the velocities at the end: from p1 at q1 (start Newton from the midpoint velocities)
        velocities_from_momenta(s, t0 + dt, q1, p1, vm, M, tmp, perm);
        for (Index i = 0; i < n; ++i) {
            w.at(kGQ, i) = q1[i];
            w.at(kGV, i) = vm[i];
        }
    };
    return NumericWorkflow::run(r);
}

} // namespace phynjo::runtime
