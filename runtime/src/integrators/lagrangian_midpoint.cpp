// The implicit midpoint rule on the canonical variables (q, p) of a generated model:
//   q1 = q0 + dt·v(q_m, p_m),  p1 = p0 + dt·F(q_m, v_m),  q_m = (q0+q1)/2, p_m = (p0+p1)/2,
// solved by fixed-point iteration to round-off. Order 2; symplectic and symmetric, so the
// energy error of a conservative autonomous model stays bounded (it is not conserved exactly).
// Reference: E. Hairer, C. Lubich, G. Wanner, Geometric Numerical Integration, 2nd ed.,
// Springer 2006, §VI.3.
// Constrained models: the same rule with p' = F + Gᵀλ (λ of the index-1 system at the
// midpoint), wrapped in Hairer's symmetric projection (E. Hairer, Symmetric projection
// methods for differential equations on manifolds, BIT 40, 726 (2000); GNI §V.4.1), so the
// step stays symmetric and the constraints hold to the projection tolerance.
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

/// Scratch of one midpoint step (thread-local: a workflow may be stepped on several threads).
struct MidpointScratch {
    std::vector<double> q0, p0, qm, pm, vm, F, M, tmp, a, lambda, G;
    std::vector<std::size_t> perm;
    void size(std::size_t n, std::size_t m) {
        for (auto* v : {&q0, &p0, &qm, &pm, &vm, &F, &tmp, &a}) v->assign(n, 0.0);
        M.assign(n * n, 0.0);
        lambda.assign(m, 0.0);
        G.assign(m * n, 0.0);
    }
};

/// One implicit midpoint step (q, v) at t0 → (q1, v1) at t0 + dt, in canonical variables.
/// Constrained models: p' = F + Gᵀλ with the multipliers of the index-1 system at the midpoint.
void midpoint_core(const LagrangianSystem& s, double t0, double dt, std::span<const double> q, std::span<const double> v,
                   std::span<double> q1, std::span<double> v1, MidpointScratch& k) {
    const std::size_t n = s.dof, m = s.n_constraints;
    const double tm = t0 + 0.5 * dt;
    thread_local std::vector<double> p1;
    p1.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        k.q0[i] = q[i];
        k.vm[i] = v[i];
    }
    s.momenta(t0, k.q0, v, k.p0);
    for (std::size_t i = 0; i < n; ++i) {
        p1[i] = k.p0[i];
        q1[i] = k.q0[i] + dt * k.vm[i];
    }
    bool converged = false;
    for (int it = 0; it < 200 && !converged; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            k.qm[i] = 0.5 * (k.q0[i] + q1[i]);
            k.pm[i] = 0.5 * (k.p0[i] + p1[i]);
        }
        velocities_from_momenta(s, tm, k.qm, k.pm, k.vm, k.M, k.tmp, k.perm);
        s.generalized_forces(tm, k.qm, k.vm, k.F);
        if (m > 0) {
            s.accelerations_and_multipliers(tm, k.qm, k.vm, k.a, k.lambda);
            s.constraint_matrix(tm, k.qm, k.G);
            for (std::size_t c = 0; c < m; ++c)
                for (std::size_t i = 0; i < n; ++i) k.F[i] += k.G[c * n + i] * k.lambda[c];
        }
        double change = 0, scale = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double nq = k.q0[i] + dt * k.vm[i], np = k.p0[i] + dt * k.F[i];
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
    for (std::size_t i = 0; i < n; ++i) v1[i] = k.vm[i];
    velocities_from_momenta(s, t0 + dt, q1, p1, v1, k.M, k.tmp, k.perm);
}

/// The symmetric projection of Hairer (BIT 40, 2000) around midpoint_core, onto the
/// manifold g(y) = (φ_h(q, t), ψ(q, q', t)) = 0 with the directions D(y) = diag(G_hᵀ, Gᵀ):
///   ŷ0 = y0 + D(y0) μ,   ỹ1 = Φ_dt(ŷ0),   y1 = ỹ1 + D(y1) μ,   g(y1) = 0,
/// solved for μ by simplified Newton (∂g(y1)/∂μ ≈ 2 g_y D, the off-diagonal block dropped).
/// Symmetric because Φ is and D is the same function at both ends.
void symmetric_projection_step(const LagrangianSystem& s, double t0, double dt, std::span<double> q,
                               std::span<double> v, const ProjectionOptions& opt, MidpointScratch& k) {
    const std::size_t n = s.dof, m = s.n_constraints, mh = detail::holonomic_count(s);
    thread_local std::vector<double> G0, G1, qh, vh, qt, vt, q1, v1, mu_q, mu_v, phi, psi, rq, rv, sc;
    G0.assign(m * n, 0.0);
    G1.assign(m * n, 0.0);
    for (auto* x : {&qh, &vh, &qt, &vt, &q1, &v1}) x->assign(n, 0.0);
    mu_q.assign(mh, 0.0);
    mu_v.assign(m, 0.0);
    phi.assign(m, 0.0);
    psi.assign(m, 0.0);
    rq.assign(mh, 0.0);
    rv.assign(m, 0.0);
    const double t1 = t0 + dt;
    s.constraint_matrix(t0, q, G0);
    for (std::size_t i = 0; i < n; ++i) {
        q1[i] = q[i];
        v1[i] = v[i];
    }
    G1 = G0; // D(y1) starts at D(y0)
    for (int it = 0;; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            qh[i] = q[i];
            vh[i] = v[i];
        }
        detail::add_constraint_directions(s, G0, true, mu_q, qh);
        detail::add_constraint_directions(s, G0, false, mu_v, vh);
        midpoint_core(s, t0, dt, qh, vh, qt, vt, k);
        // y1 = ỹ1 + D(y1) μ: a fixed point in q1 (D depends on q1 only), two passes suffice
        for (int pass = 0; pass < 2; ++pass) {
            for (std::size_t i = 0; i < n; ++i) {
                q1[i] = qt[i];
                v1[i] = vt[i];
            }
            detail::add_constraint_directions(s, G1, true, mu_q, q1);
            detail::add_constraint_directions(s, G1, false, mu_v, v1);
            s.constraint_matrix(t1, q1, G1);
        }
        for (std::size_t i = 0; i < n; ++i) {
            q1[i] = qt[i];
            v1[i] = vt[i];
        }
        detail::add_constraint_directions(s, G1, true, mu_q, q1);
        detail::add_constraint_directions(s, G1, false, mu_v, v1);
        s.constraint_residuals(t1, q1, v1, phi);
        s.constraint_velocity_residuals(t1, q1, v1, psi);
        detail::constraint_scales(s, t1, q1, v1, sc);
        bool ok = true;
        std::size_t h = 0;
        for (std::size_t c = 0; c < m; ++c) {
            if (s.constraint_holonomic[c]) {
                ok = ok && std::fabs(phi[c]) <= opt.tolerance * sc[c];
                rq[h++] = -0.5 * phi[c];
            }
            ok = ok && std::fabs(psi[c]) <= opt.tolerance * sc[m + c];
            rv[c] = -0.5 * psi[c];
            if (!std::isfinite(phi[c]) || !std::isfinite(psi[c]))
                throw NonFiniteResult("implicit midpoint: constraint '" + s.constraint_names[c] +
                                      "' is not finite at t = " + std::to_string(t1));
        }
        if (ok) break;
        if (it == opt.max_iterations)
            throw ConvergenceError("implicit midpoint: the symmetric projection did not converge at t = " +
                                   std::to_string(t0) + " (step " + std::to_string(dt) + " too large?)");
        if (mh > 0) detail::solve_gram(s, G1, true, rq, t1);
        detail::solve_gram(s, G1, false, rv, t1);
        for (std::size_t c = 0; c < mh; ++c) mu_q[c] += rq[c];
        for (std::size_t c = 0; c < m; ++c) mu_v[c] += rv[c];
    }
    for (std::size_t i = 0; i < n; ++i) {
        q[i] = q1[i];
        v[i] = v1[i];
    }
}

} // namespace

NumericWorkflow lagrangian_midpoint(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                                   const ProjectionOptions& projection) {
    const std::size_t n = s.dof;
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    NumericRule r{"implicit_midpoint", Domain(kGQ, all) | Domain(kGV, all), {}, nullptr, layout};
    r.step = [s, n, projection](double dt, World& w) {
        thread_local MidpointScratch k;
        thread_local std::vector<double> q1, v1;
        k.size(n, s.n_constraints);
        if (s.n_constraints > 0) {
            symmetric_projection_step(s, w.time, dt, w.field(kGQ), w.field(kGV), projection, k);
            return;
        }
        q1.assign(n, 0.0);
        v1.assign(n, 0.0);
        midpoint_core(s, w.time, dt, w.field(kGQ), w.field(kGV), q1, v1, k);
        for (Index i = 0; i < n; ++i) {
            w.at(kGQ, i) = q1[i];
            w.at(kGV, i) = v1[i];
        }
    };
    return NumericWorkflow::run(r);
}

} // namespace phynjo::runtime
