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

#include "momenta.hpp"

#include <algorithm>

namespace phynjo::runtime {

namespace {

using detail::dense_solve;
using detail::velocities_from_momenta;

/// Scratch of one midpoint step (thread-local: a workflow may be stepped on several threads).
struct MidpointScratch {
    std::vector<double> q0, p0, qm, pm, vm, F, M, tmp, a, lambda, G, dp, dF, J;
    std::vector<std::size_t> perm;
    /// The last solution (q1, p1, midpoint velocities), and whether the next solve starts from
    /// it (the symmetric projection solves nearby problems in a row).
    std::vector<double> q1_last, p1_last, vm_last, p1;
    bool warm = false;
    void size(std::size_t n, std::size_t m) {
        for (auto* v : {&q0, &p0, &qm, &pm, &vm, &F, &tmp, &a, &q1_last, &p1_last, &vm_last, &p1}) v->assign(n, 0.0);
        warm = false;
        M.assign(n * n, 0.0);
        J.assign(n * n, 0.0);
        dp.assign(2 * n * n, 0.0);
        dF.assign(2 * n * n, 0.0);
        lambda.assign(m, 0.0);
        G.assign(m * n, 0.0);
    }
};

/// F += Gᵀλ with λ of the index-1 system at (t, q, v) (constrained models).
void add_constraint_forces(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> v,
                           MidpointScratch& k) {
    const std::size_t n = s.dof, m = s.n_constraints;
    s.accelerations_and_multipliers(t, q, v, k.a, k.lambda);
    s.constraint_matrix(t, q, k.G);
    for (std::size_t c = 0; c < m; ++c)
        for (std::size_t i = 0; i < n; ++i) k.F[i] += k.G[c * n + i] * k.lambda[c];
}

/// The end point (q1, p1) = (q0 + dt·vm, p0 + dt·F) from the midpoint values of iteration
/// `it` (q1 given, p1 in the scratch); true when it no longer changes: converged at
/// round-off, or stalled there (the iteration rounds differently from one pass to the next:
/// a few ulps of a large coordinate, a wound-up angle).
bool update_end_point(double dt, int it, double& last_change, std::span<double> q1, MidpointScratch& k) {
    double change = 0, scale = 0;
    for (std::size_t i = 0; i < q1.size(); ++i) {
        const double nq = k.q0[i] + dt * k.vm[i], np = k.p0[i] + dt * k.F[i];
        change = std::max({change, std::fabs(nq - q1[i]), std::fabs(np - k.p1[i])});
        scale = std::max({scale, std::fabs(nq), std::fabs(np)});
        q1[i] = nq;
        k.p1[i] = np;
    }
    const bool done = change <= 4e-16 * (1 + scale) || (it >= 8 && change >= last_change && change <= 1e-13 * (1 + scale));
    last_change = change;
    return done;
}

/// After the iteration: remembers the solution (the next solve may start from it) and
/// computes the end velocities from p1 at q1 (Newton from the midpoint velocities).
void finish_step(const LagrangianSystem& s, double t0, double dt, bool converged, std::span<double> q1,
                 std::span<double> v1, MidpointScratch& k) {
    if (!converged) throw ConvergenceError("implicit midpoint did not converge at t = " + std::to_string(t0) +
                                           " (step " + std::to_string(dt) + " too large?)");
    for (std::size_t i = 0; i < q1.size(); ++i) {
        k.q1_last[i] = q1[i];
        k.p1_last[i] = k.p1[i];
        k.vm_last[i] = k.vm[i];
        v1[i] = k.vm[i];
    }
    velocities_from_momenta(s, t0 + dt, q1, k.p1, v1, k.M, k.tmp, k.perm);
}

/// The same step as midpoint_fixed_point, solved by Newton's method with the exact Jacobian
/// (canonical_jacobian). Unknown: the midpoint Q; then V = 2(Q − q0)/dt and
///   R(Q) = p(Q, V) − p0 − dt/2·F(Q, V) = 0,
///   R'(Q) = 2/dt·M + ∂p/∂q − ∂F/∂q' − dt/2·∂F/∂q   (M = ∂p/∂q').
/// Constrained models add Gᵀλ to F but not its derivative to R' (a simplified Newton step:
/// the neglected term is O(dt²) relative to 2/dt·M, so it still converges in a few steps).
/// Stops when (q1, p1) = (q0 + dt·V, p0 + dt·F) no longer change (round-off), as the fixed
/// point does: the same solution, to round-off.
void midpoint_newton(const LagrangianSystem& s, double t0, double dt, std::span<const double> q, std::span<const double> v,
                     std::span<double> q1, std::span<double> v1, MidpointScratch& k) {
    const std::size_t n = s.dof;
    const double tm = t0 + 0.5 * dt, h = 0.5 * dt;
    std::vector<double>& p1 = k.p1;
    for (std::size_t i = 0; i < n; ++i) k.q0[i] = q[i];
    s.momenta(t0, k.q0, v, k.p0);
    for (std::size_t i = 0; i < n; ++i) {
        k.qm[i] = k.warm ? 0.5 * (k.q0[i] + k.q1_last[i]) : k.q0[i] + h * v[i];
        q1[i] = HUGE_VAL;
        p1[i] = HUGE_VAL;
    }
    bool converged = false;
    double last_change = HUGE_VAL;
    for (int it = 0; it < 50 && !converged; ++it) {
        for (std::size_t i = 0; i < n; ++i) k.vm[i] = (k.qm[i] - k.q0[i]) / h;
        s.canonical_jacobian(tm, k.qm, k.vm, k.pm, k.F, k.dp, k.dF);
        if (s.n_constraints > 0) add_constraint_forces(s, tm, k.qm, k.vm, k);
        converged = update_end_point(dt, it, last_change, q1, k);
        if (converged) break;
        for (std::size_t i = 0; i < n; ++i) {
            k.tmp[i] = -(k.pm[i] - k.p0[i] - h * k.F[i]);
            for (std::size_t j = 0; j < n; ++j)
                k.J[i * n + j] = k.dp[i * 2 * n + n + j] / h + k.dp[i * 2 * n + j] - k.dF[i * 2 * n + n + j] -
                                 h * k.dF[i * 2 * n + j];
        }
        if (!dense_solve(k.J, k.tmp, n))
            throw ConvergenceError("implicit midpoint: singular Newton matrix at t = " + std::to_string(t0));
        for (std::size_t i = 0; i < n; ++i) k.qm[i] += k.tmp[i];
    }
    finish_step(s, t0, dt, converged, q1, v1, k);
}

/// One implicit midpoint step by fixed-point iteration (systems without canonical_jacobian).
void midpoint_fixed_point(const LagrangianSystem& s, double t0, double dt, std::span<const double> q, std::span<const double> v,
                   std::span<double> q1, std::span<double> v1, MidpointScratch& k) {
    const std::size_t n = s.dof, m = s.n_constraints;
    const double tm = t0 + 0.5 * dt;
    std::vector<double>& p1 = k.p1;
    for (std::size_t i = 0; i < n; ++i) {
        k.q0[i] = q[i];
        k.vm[i] = v[i];
    }
    s.momenta(t0, k.q0, v, k.p0);
    for (std::size_t i = 0; i < n; ++i) {
        p1[i] = k.warm ? k.p1_last[i] : k.p0[i];
        q1[i] = k.warm ? k.q1_last[i] : k.q0[i] + dt * k.vm[i];
        if (k.warm) k.vm[i] = k.vm_last[i];
    }
    bool converged = false;
    double last_change = HUGE_VAL;
    for (int it = 0; it < 200 && !converged; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            k.qm[i] = 0.5 * (k.q0[i] + q1[i]);
            k.pm[i] = 0.5 * (k.p0[i] + p1[i]);
        }
        velocities_from_momenta(s, tm, k.qm, k.pm, k.vm, k.M, k.tmp, k.perm);
        s.generalized_forces(tm, k.qm, k.vm, k.F);
        if (m > 0) add_constraint_forces(s, tm, k.qm, k.vm, k);
        converged = update_end_point(dt, it, last_change, q1, k);
    }
    finish_step(s, t0, dt, converged, q1, v1, k);
}

/// One implicit midpoint step (q, v) at t0 → (q1, v1) at t0 + dt, in canonical variables.
/// Constrained models: p' = F + Gᵀλ with the multipliers of the index-1 system at the midpoint.
void midpoint_core(const LagrangianSystem& s, double t0, double dt, std::span<const double> q, std::span<const double> v,
                   std::span<double> q1, std::span<double> v1, MidpointScratch& k) {
    if (s.canonical_jacobian) {
        midpoint_newton(s, t0, dt, q, v, q1, v1, k);
        return;
    }
    midpoint_fixed_point(s, t0, dt, q, v, q1, v1, k);
}

/// The symmetric projection of Hairer (BIT 40, 2000) around midpoint_core, onto the
/// manifold g(y) = (φ_h(q, t), ψ(q, q', t)) = 0 with the directions D(y) = diag(G_hᵀ, Gᵀ):
///   ŷ0 = y0 + D(y0) μ,   ỹ1 = Φ_dt(ŷ0),   y1 = ỹ1 + D(y1) μ,   g(y1) = 0.
/// Solved for μ by Broyden's method from the Jacobian estimate 2 g_y D ≈ 2 diag(G_h G_hᵀ,
/// G Gᵀ) (exact for Φ = identity and ψ independent of q): the rank-one updates learn the
/// rest — how the constrained flow moves ỹ1 with ŷ0 — which matters near singular
/// configurations of a mechanism. Symmetric because Φ is and D is the same function at both ends.
void symmetric_projection_step(const LagrangianSystem& s, double t0, double dt, std::span<double> q,
                               std::span<double> v, const ProjectionOptions& opt, MidpointScratch& k) {
    const std::size_t n = s.dof, m = s.n_constraints, mh = detail::holonomic_count(s), p = mh + m;
    thread_local std::vector<double> G0, G1, qh, vh, qt, vt, q1, v1, mu, phi, psi, r, r_old, step, J, A, x, sc;
    G0.assign(m * n, 0.0);
    G1.assign(m * n, 0.0);
    for (auto* z : {&qh, &vh, &qt, &vt, &q1, &v1}) z->assign(n, 0.0);
    for (auto* z : {&mu, &r, &r_old, &step, &x}) z->assign(p, 0.0);
    phi.assign(m, 0.0);
    psi.assign(m, 0.0);
    J.assign(p * p, 0.0);
    A.reserve(p * p);
    const double t1 = t0 + dt;
    s.constraint_matrix(t0, q, G0);
    G1 = G0; // D(y1) starts at D(y0)
    const std::span<const double> mu_q(mu.data(), mh), mu_v(mu.data() + mh, m);
    auto end_point = [&] { // y1 = ỹ1 + D(y1) μ with D at the latest q1
        for (std::size_t i = 0; i < n; ++i) {
            q1[i] = qt[i];
            v1[i] = vt[i];
        }
        detail::add_constraint_directions(s, G1, true, mu_q, q1);
        detail::add_constraint_directions(s, G1, false, mu_v, v1);
    };
    for (int it = 0;; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            qh[i] = q[i];
            vh[i] = v[i];
        }
        detail::add_constraint_directions(s, G0, true, mu_q, qh);
        detail::add_constraint_directions(s, G0, false, mu_v, vh);
        midpoint_core(s, t0, dt, qh, vh, qt, vt, k);
        k.warm = true; // the next solve (a nearby start ŷ0) starts from this solution
        // y1 = ỹ1 + D(y1) μ: a fixed point in q1 (D depends on q1 only; μ is small)
        for (int pass = 0; pass < 2; ++pass) {
            end_point();
            s.constraint_matrix(t1, q1, G1);
        }
        end_point();
        s.constraint_residuals(t1, q1, v1, phi);
        s.constraint_velocity_residuals(t1, q1, v1, psi);
        detail::constraint_scales(s, t1, q1, v1, sc);
        bool ok = true;
        std::size_t h = 0;
        for (std::size_t c = 0; c < m; ++c) {
            if (!std::isfinite(phi[c]) || !std::isfinite(psi[c]))
                throw NonFiniteResult("implicit midpoint: constraint '" + s.constraint_names[c] +
                                      "' is not finite at t = " + std::to_string(t1));
            if (s.constraint_holonomic[c]) {
                ok = ok && std::fabs(phi[c]) <= opt.tolerance * sc[c];
                r[h++] = phi[c];
            }
            ok = ok && std::fabs(psi[c]) <= opt.tolerance * sc[m + c];
            r[mh + c] = psi[c];
        }
        if (ok) break;
        if (it == opt.max_iterations)
            throw ConvergenceError("implicit midpoint: the symmetric projection did not converge at t = " +
                                   std::to_string(t0) + " (step " + std::to_string(dt) + " too large?)");
        if (it == 0) { // J0 = 2 diag(G_h G_hᵀ, G Gᵀ)
            thread_local std::vector<std::size_t> rows; // the holonomic rows
            rows.clear();
            for (std::size_t c = 0; c < m; ++c)
                if (s.constraint_holonomic[c]) rows.push_back(c);
            std::fill(J.begin(), J.end(), 0.0);
            for (std::size_t a = 0; a < p; ++a)
                for (std::size_t b = 0; b < p; ++b) {
                    const bool qa = a < mh, qb = b < mh;
                    if (qa != qb) continue;
                    const std::size_t ra = qa ? rows[a] : a - mh, rb = qb ? rows[b] : b - mh;
                    double d = 0;
                    for (std::size_t j = 0; j < n; ++j) d += G1[ra * n + j] * G1[rb * n + j];
                    J[a * p + b] = 2 * d;
                }
        } else { // Broyden: J += (Δr − J s) sᵀ / sᵀs
            double ss = 0;
            for (std::size_t b = 0; b < p; ++b) ss += step[b] * step[b];
            if (ss > 0)
                for (std::size_t a = 0; a < p; ++a) {
                    double js = 0;
                    for (std::size_t b = 0; b < p; ++b) js += J[a * p + b] * step[b];
                    const double u = (r[a] - r_old[a] - js) / ss;
                    for (std::size_t b = 0; b < p; ++b) J[a * p + b] += u * step[b];
                }
        }
        A = J;
        for (std::size_t a = 0; a < p; ++a) x[a] = -r[a];
        if (!dense_solve(A, x, p)) {
            std::vector<std::string_view> names(s.constraint_names.begin(), s.constraint_names.end());
            detail::throw_singular_constraints(G1.data(), m, n, names, "implicit midpoint (symmetric projection)", t1);
        }
        for (std::size_t a = 0; a < p; ++a) {
            mu[a] += x[a];
            step[a] = x[a];
            r_old[a] = r[a];
        }
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
