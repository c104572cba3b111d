// Projections onto the constraint manifold of a generated model, and the check of initial
// values (constraint_projection.hpp). Scratch is thread-local and keeps its size: no
// allocation in a steady step.
#include "phynjo/runtime/system/constraint_projection.hpp"

#include "phynjo/runtime/system/detail/kkt_solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace phynjo::runtime {

namespace {

/// The scratch of solve_gram, thread-local; reserved on entry to every projection (not only
/// when a correction is first needed), so a steady step never allocates.
struct GramScratch {
    std::vector<std::size_t> rows;
    std::vector<double> A;
};
GramScratch& gram_scratch(std::size_t m) {
    thread_local GramScratch k;
    k.rows.reserve(m);
    k.A.reserve(m * m);
    return k;
}

} // namespace

namespace detail {

std::size_t holonomic_count(const LagrangianSystem& s) {
    std::size_t k = 0;
    for (unsigned char h : s.constraint_holonomic) k += h ? 1 : 0;
    return k;
}

void add_constraint_directions(const LagrangianSystem& s, std::span<const double> G, bool holonomic_only,
                               std::span<const double> mu, std::span<double> x) {
    const std::size_t n = s.dof;
    std::size_t r = 0;
    for (std::size_t k = 0; k < s.n_constraints; ++k) {
        if (holonomic_only && !s.constraint_holonomic[k]) continue;
        const double m = mu[r++];
        for (std::size_t j = 0; j < n; ++j) x[j] += G[k * n + j] * m;
    }
}

void solve_gram(const LagrangianSystem& s, std::span<const double> G, bool holonomic_only, std::span<double> r,
                double t) {
    const std::size_t n = s.dof;
    GramScratch& g = gram_scratch(s.n_constraints);
    std::vector<std::size_t>& rows = g.rows;
    std::vector<double>& A = g.A;
    rows.clear();
    for (std::size_t k = 0; k < s.n_constraints; ++k)
        if (!holonomic_only || s.constraint_holonomic[k]) rows.push_back(k);
    const std::size_t m = rows.size();
    A.assign(m * m, 0.0);
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < m; ++b) {
            double v = 0;
            for (std::size_t j = 0; j < n; ++j) v += G[rows[a] * n + j] * G[rows[b] * n + j];
            A[a * m + b] = v;
        }
    if (!dense_solve(A, r, m)) {
        std::vector<double> Gs(m * n);
        std::vector<std::string_view> names;
        for (std::size_t a = 0; a < m; ++a) {
            for (std::size_t j = 0; j < n; ++j) Gs[a * n + j] = G[rows[a] * n + j];
            names.emplace_back(s.constraint_names[rows[a]]);
        }
        throw_singular_constraints(Gs.data(), m, n, names, "constraint projection", t);
    }
}

} // namespace detail

namespace detail {

void constraint_scales(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> qdot,
                       std::span<const double> G, std::vector<double>& scale) {
    const std::size_t m = s.n_constraints, n = s.dof;
    scale.assign(2 * m, 0.0);
    if (s.constraint_scales) s.constraint_scales(t, q, qdot, scale);
    // the floor: 1e-3 Σ_j |G_kj| ‖x‖∞ (x = q, q'), what round-off in the whole state allows
    double qmax = 0, vmax = 0;
    for (std::size_t j = 0; j < n; ++j) {
        qmax = std::max(qmax, std::fabs(q[j]));
        vmax = std::max(vmax, std::fabs(qdot[j]));
    }
    for (std::size_t k = 0; k < m; ++k) {
        double g = 0;
        for (std::size_t j = 0; j < n; ++j) g += std::fabs(G[k * n + j]);
        scale[k] += kScaleFloor * g * qmax;
        scale[m + k] += kScaleFloor * g * vmax;
    }
}

void constraint_scales(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> qdot,
                       std::vector<double>& scale) {
    thread_local std::vector<double> G;
    G.assign(s.n_constraints * s.dof, 0.0);
    s.constraint_matrix(t, q, G);
    constraint_scales(s, t, q, qdot, G, scale);
}

} // namespace detail

namespace {

/// The worst scaled residual at one level: position (holonomic rows) or velocity (all rows).
ConstraintViolation worst_at_level(const LagrangianSystem& s, double t, std::span<const double> q,
                                   std::span<const double> qdot, bool velocity) {
    ConstraintViolation worst;
    const std::size_t m = s.n_constraints;
    thread_local std::vector<double> sc, r;
    r.assign(m, 0.0);
    detail::constraint_scales(s, t, q, qdot, sc);
    if (velocity) s.constraint_velocity_residuals(t, q, qdot, r);
    else s.constraint_residuals(t, q, qdot, r);
    bool first = true;
    for (std::size_t k = 0; k < m; ++k) {
        if (!velocity && !s.constraint_holonomic[k]) continue;
        const double scaled = detail::scaled_residual(r[k], sc[velocity ? m + k : k]);
        if (first || scaled > worst.scaled) worst = {k, velocity, r[k], scaled};
        first = false;
    }
    return worst;
}

} // namespace

ConstraintViolation worst_constraint_violation(const LagrangianSystem& s, double t, std::span<const double> q,
                                               std::span<const double> qdot) {
    if (s.n_constraints == 0) return {};
    const ConstraintViolation p = worst_at_level(s, t, q, qdot, false), v = worst_at_level(s, t, q, qdot, true);
    return v.scaled > p.scaled ? v : p;
}

void check_constraints(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> qdot,
                       double tolerance) {
    if (s.n_constraints == 0) return;
    // positions first: velocity constraints of a state off the position manifold mean little
    ConstraintViolation v = worst_at_level(s, t, q, qdot, false);
    if (!(v.scaled > tolerance)) v = worst_at_level(s, t, q, qdot, true);
    if (!(v.scaled > tolerance)) return;
    const std::string& name = s.constraint_names[v.constraint];
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", v.residual);
    const bool nonholonomic = !s.constraint_holonomic[v.constraint];
    char tol[32];
    std::snprintf(tol, sizeof tol, "%g", tolerance);
    char when[32];
    std::snprintf(when, sizeof when, "%g", t);
    throw InconsistentInitialValues(
        std::string("the state at t = ") + when + " violates constraint '" + name + "' " +
            (nonholonomic        ? "(nonholonomic): its residual is "
             : v.velocity_level ? "at velocity level: its time derivative is "
                                : "at position level: its residual is ") +
            buf + " (relative tolerance " + tol +
            "; give consistent initial values, or project them: --project-initial)",
        name, v.residual);
}

void project_positions(const LagrangianSystem& s, double t, std::span<double> q, std::span<const double> qdot,
                       const ProjectionOptions& options) {
    const std::size_t m = s.n_constraints, n = s.dof, mh = detail::holonomic_count(s);
    if (mh == 0) return;
    (void)gram_scratch(m);
    thread_local std::vector<double> G, phi, r, sc;
    G.assign(m * n, 0.0);
    phi.assign(m, 0.0);
    r.assign(mh, 0.0);
    // the constraint furthest from holding when the iterates stall: when it is far (more
    // than 1e-6 of its scale, or of 1), the projection cannot reach it — say so, with φ
    auto stalled = [&](const std::string& why) {
        std::size_t worst = m;
        double worst_scaled = 0;
        for (std::size_t k = 0; k < m; ++k) {
            if (!s.constraint_holonomic[k]) continue;
            const double scaled = std::fabs(phi[k]) / std::max(sc[k], 1.0);
            if (worst == m || scaled > worst_scaled) worst = k, worst_scaled = scaled;
        }
        if (worst == m || !(worst_scaled > 1e-6)) return;
        char buf[200];
        std::snprintf(buf, sizeof buf, "%.6g", phi[worst]);
        throw UnreachableConstraint("constraint projection at t = " + std::to_string(t) + ": constraint '" +
                                        s.constraint_names[worst] + "' cannot be reached: its residual stays at " + buf +
                                        " (" + why +
                                        "); no state near this one satisfies it, and at these parameters perhaps "
                                        "none does",
                                    s.constraint_names[worst], phi[worst]);
    };
    for (int it = 0; it <= options.max_iterations; ++it) {
        s.constraint_matrix(t, q, G);
        s.constraint_residuals(t, q, qdot, phi);
        detail::constraint_scales(s, t, q, qdot, G, sc);
        bool ok = true;
        std::size_t i = 0;
        for (std::size_t k = 0; k < m; ++k) {
            if (!s.constraint_holonomic[k]) continue;
            if (!std::isfinite(phi[k]))
                throw NonFiniteResult("constraint projection: constraint '" + s.constraint_names[k] +
                                      "' is not finite at t = " + std::to_string(t));
            ok = ok && std::fabs(phi[k]) <= options.tolerance * sc[k];
            r[i++] = -phi[k];
        }
        if (ok) return;
        if (it == options.max_iterations) break;
        try {
            detail::solve_gram(s, G, true, r, t);
        } catch (const SingularConstraints&) {
            // singular where the projection started: the state given is a singular point (the
            // bob at the pivot), as solve_gram says; reached by the iterates: they were drawn
            // to a minimum of the residual away from zero
            if (it > 0) stalled("Gauss-Newton reached a point where the constraints' gradients are dependent or vanish");
            throw;
        }
        detail::add_constraint_directions(s, G, true, r, q);
    }
    stalled("Gauss-Newton did not converge in " + std::to_string(options.max_iterations) + " iterations");
    throw ConvergenceError("constraint projection did not converge at t = " + std::to_string(t) + " in " +
                           std::to_string(options.max_iterations) + " Gauss-Newton iterations");
}

void project_velocities(const LagrangianSystem& s, double t, std::span<const double> q, std::span<double> qdot,
                        const ProjectionOptions& options) {
    const std::size_t m = s.n_constraints, n = s.dof;
    if (m == 0) return;
    (void)gram_scratch(m);
    thread_local std::vector<double> G, psi, sc;
    G.assign(m * n, 0.0);
    psi.assign(m, 0.0);
    s.constraint_matrix(t, q, G);
    s.constraint_velocity_residuals(t, q, qdot, psi);
    detail::constraint_scales(s, t, q, qdot, G, sc);
    bool ok = true;
    for (std::size_t k = 0; k < m; ++k) {
        if (!std::isfinite(psi[k]))
            throw NonFiniteResult("constraint projection: the velocity constraint of '" + s.constraint_names[k] +
                                  "' is not finite at t = " + std::to_string(t));
        ok = ok && std::fabs(psi[k]) <= options.tolerance * sc[m + k];
    }
    if (ok) return; // already on the manifold: left exactly as it is
    for (double& v : psi) v = -v;
    detail::solve_gram(s, G, false, psi, t);
    detail::add_constraint_directions(s, G, false, psi, qdot);
}

void project_onto_constraints(const LagrangianSystem& s, double t, std::span<double> q, std::span<double> qdot,
                              const ProjectionOptions& options) {
    project_positions(s, t, q, qdot, options);
    project_velocities(s, t, q, qdot, options);
}

NumericRule constraint_projection_rule(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                                       const ProjectionOptions& options) {
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(s.dof));
    NumericRule r{"project_constraints", Domain(kGQ, all) | Domain(kGV, all), {}, nullptr, layout};
    r.step = [s, options](double dt, World& w) {
        project_onto_constraints(s, w.time + dt, w.field(kGQ), w.field(kGV), options);
    };
    return r;
}

} // namespace phynjo::runtime
