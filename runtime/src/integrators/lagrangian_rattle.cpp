// RATTLE for generated models (lagrangian_rattle.hpp): the constrained generalized leapfrog.
// Order 2, symmetric; symplectic for conservative models with scleronomic holonomic
// constraints. References: H. C. Andersen, J. Comput. Phys. 52, 24 (1983); L. O. Jay, SIAM J.
// Numer. Anal. 33, 368 (1996); E. Hairer, C. Lubich, G. Wanner, Geometric Numerical
// Integration, 2nd ed., Springer 2006, §VII.1.
#include "phynjo/runtime/integrators/lagrangian_rattle.hpp"

#include "momenta.hpp"

#include <algorithm>
#include <stdexcept>

namespace phynjo::runtime {

namespace {

using detail::dense_solve;
using detail::solve_factored;
using detail::velocities_from_momenta;

struct RattleScratch {
    std::vector<double> q0, p0, ph, vh0, vh1, q1, p1, v1, F, G0, G1, lambda, mu, r, r_old, step, J, A, x, sc, tmp, Ma, Mb,
        col, psi;
    std::vector<std::size_t> pa, pb;
    void size(std::size_t n, std::size_t m) {
        for (auto* v : {&q0, &p0, &ph, &vh0, &vh1, &q1, &p1, &v1, &F, &tmp, &col}) v->assign(n, 0.0);
        for (auto* v : {&lambda, &mu, &r, &r_old, &step, &x, &psi}) v->assign(m, 0.0);
        G0.assign(m * n, 0.0);
        G1.assign(m * n, 0.0);
        J.assign(m * m, 0.0);
        Ma.assign(n * n, 0.0);
        Mb.assign(n * n, 0.0);
    }
};

bool small_change(std::span<const double> a, std::span<const double> b, double tol) {
    double change = 0, scale = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        change = std::max(change, std::fabs(a[i] - b[i]));
        scale = std::max(scale, std::fabs(a[i]));
    }
    return change <= tol * (1 + scale);
}

[[noreturn]] void no_convergence(const char* what, double t0, double dt) {
    throw ConvergenceError(std::string("RATTLE: ") + what + " did not converge at t = " + std::to_string(t0) + " (step " +
                           std::to_string(dt) + " too large?)");
}

void rattle_step(const LagrangianSystem& s, double t0, double h, std::span<double> q, std::span<double> v,
                 const ProjectionOptions& opt, RattleScratch& k) {
    const std::size_t n = s.dof, m = s.n_constraints;
    const double t1 = t0 + h;
    for (std::size_t i = 0; i < n; ++i) {
        k.q0[i] = q[i];
        k.vh0[i] = v[i];
        k.vh1[i] = v[i];
    }
    s.momenta(t0, k.q0, v, k.p0);
    if (m > 0) s.constraint_matrix(t0, k.q0, k.G0);
    k.ph = k.p0;
    for (std::size_t i = 0; i < n; ++i) k.q1[i] = k.q0[i] + h * v[i];
    // ---- p½ and q1 for the multipliers λ, λ by Broyden on φ(q1, t1) = 0
    for (int it = 0;; ++it) {
        // p½ = p0 + h/2 (F(t0, q0, v(q0, p½)) + G0ᵀλ): fixed point in p½
        bool done = false;
        for (int j = 0; j < 100 && !done; ++j) {
            velocities_from_momenta(s, t0, k.q0, k.ph, k.vh0, k.Ma, k.tmp, k.pa);
            s.generalized_forces(t0, k.q0, k.vh0, k.F);
            for (std::size_t c = 0; c < m; ++c)
                for (std::size_t i = 0; i < n; ++i) k.F[i] += k.G0[c * n + i] * k.lambda[c];
            for (std::size_t i = 0; i < n; ++i) k.tmp[i] = k.p0[i] + 0.5 * h * k.F[i];
            done = small_change(k.tmp, k.ph, 4e-16) || (j >= 8 && small_change(k.tmp, k.ph, 1e-13));
            k.ph = k.tmp;
        }
        if (!done) no_convergence("the half-step momenta", t0, h);
        velocities_from_momenta(s, t0, k.q0, k.ph, k.vh0, k.Ma, k.tmp, k.pa);
        // q1 = q0 + h/2 (v(t0, q0, p½) + v(t1, q1, p½)): fixed point in q1
        done = false;
        for (int j = 0; j < 100 && !done; ++j) {
            velocities_from_momenta(s, t1, k.q1, k.ph, k.vh1, k.Mb, k.tmp, k.pb);
            for (std::size_t i = 0; i < n; ++i) k.tmp[i] = k.q0[i] + 0.5 * h * (k.vh0[i] + k.vh1[i]);
            done = small_change(k.tmp, k.q1, 4e-16) || (j >= 8 && small_change(k.tmp, k.q1, 1e-13));
            k.q1 = k.tmp;
        }
        if (!done) no_convergence("the positions", t0, h);
        if (m == 0) break;
        velocities_from_momenta(s, t1, k.q1, k.ph, k.vh1, k.Mb, k.tmp, k.pb); // M(q1) factors for J0
        s.constraint_residuals(t1, k.q1, k.vh1, k.r);
        s.constraint_matrix(t1, k.q1, k.G1);
        detail::constraint_scales(s, t1, k.q1, k.vh1, k.G1, k.sc);
        bool ok = true;
        for (std::size_t c = 0; c < m; ++c) {
            if (!std::isfinite(k.r[c]))
                throw NonFiniteResult("RATTLE: constraint '" + s.constraint_names[c] + "' is not finite at t = " +
                                      std::to_string(t1));
            ok = ok && std::fabs(k.r[c]) <= opt.tolerance * k.sc[c];
        }
        if (ok) break;
        if (it == opt.max_iterations) no_convergence("the position constraints", t0, h);
        if (it == 0) { // J0 = (h²/4) G1 (M0⁻¹ + M1⁻¹) G0ᵀ
            for (std::size_t b = 0; b < m; ++b) {
                for (std::size_t i = 0; i < n; ++i) k.col[i] = k.G0[b * n + i];
                solve_factored(k.Ma, k.pa, k.col);
                for (std::size_t i = 0; i < n; ++i) k.tmp[i] = k.G0[b * n + i];
                solve_factored(k.Mb, k.pb, k.tmp);
                for (std::size_t a = 0; a < m; ++a) {
                    double d = 0;
                    for (std::size_t i = 0; i < n; ++i) d += k.G1[a * n + i] * (k.col[i] + k.tmp[i]);
                    k.J[a * m + b] = 0.25 * h * h * d;
                }
            }
        } else { // Broyden: J += (Δr − J s) sᵀ / sᵀs
            double ss = 0;
            for (std::size_t b = 0; b < m; ++b) ss += k.step[b] * k.step[b];
            if (ss > 0)
                for (std::size_t a = 0; a < m; ++a) {
                    double js = 0;
                    for (std::size_t b = 0; b < m; ++b) js += k.J[a * m + b] * k.step[b];
                    const double u = (k.r[a] - k.r_old[a] - js) / ss;
                    for (std::size_t b = 0; b < m; ++b) k.J[a * m + b] += u * k.step[b];
                }
        }
        k.A = k.J;
        for (std::size_t a = 0; a < m; ++a) k.x[a] = -k.r[a];
        if (!dense_solve(k.A, k.x, m)) {
            std::vector<std::string_view> names(s.constraint_names.begin(), s.constraint_names.end());
            detail::throw_singular_constraints(k.G1.data(), m, n, names, "RATTLE", t1);
        }
        for (std::size_t a = 0; a < m; ++a) {
            k.lambda[a] += k.x[a];
            k.step[a] = k.x[a];
            k.r_old[a] = k.r[a];
        }
    }
    // ---- p1 = p½ + h/2 (F(t1, q1, v(q1, p½)) + G1ᵀμ), μ by Newton on ψ(q1, v(q1, p1)) = 0
    s.generalized_forces(t1, k.q1, k.vh1, k.F);
    for (std::size_t i = 0; i < n; ++i) {
        k.p1[i] = k.ph[i] + 0.5 * h * k.F[i];
        k.v1[i] = k.vh1[i];
    }
    if (m > 0) s.constraint_matrix(t1, k.q1, k.G1);
    for (int it = 0;; ++it) {
        velocities_from_momenta(s, t1, k.q1, k.p1, k.v1, k.Mb, k.tmp, k.pb);
        if (m == 0) break;
        s.constraint_velocity_residuals(t1, k.q1, k.v1, k.psi);
        detail::constraint_scales(s, t1, k.q1, k.v1, k.G1, k.sc);
        bool ok = true;
        for (std::size_t c = 0; c < m; ++c) ok = ok && std::fabs(k.psi[c]) <= opt.tolerance * k.sc[m + c];
        if (ok) break;
        if (it == opt.max_iterations) no_convergence("the velocity constraints", t0, h);
        // (h/2) G1 M1⁻¹ G1ᵀ Δμ = −ψ, and p1 += (h/2) G1ᵀ Δμ
        for (std::size_t b = 0; b < m; ++b) {
            for (std::size_t i = 0; i < n; ++i) k.col[i] = k.G1[b * n + i];
            solve_factored(k.Mb, k.pb, k.col);
            for (std::size_t a = 0; a < m; ++a) {
                double d = 0;
                for (std::size_t i = 0; i < n; ++i) d += k.G1[a * n + i] * k.col[i];
                k.J[a * m + b] = 0.5 * h * d;
            }
            k.x[b] = -k.psi[b];
        }
        k.A = k.J;
        if (!dense_solve(k.A, k.x, m)) {
            std::vector<std::string_view> names(s.constraint_names.begin(), s.constraint_names.end());
            detail::throw_singular_constraints(k.G1.data(), m, n, names, "RATTLE", t1);
        }
        for (std::size_t c = 0; c < m; ++c)
            for (std::size_t i = 0; i < n; ++i) k.p1[i] += 0.5 * h * k.G1[c * n + i] * k.x[c];
    }
    for (std::size_t i = 0; i < n; ++i) {
        q[i] = k.q1[i];
        v[i] = k.v1[i];
    }
}

} // namespace

NumericWorkflow lagrangian_rattle(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                                  const ProjectionOptions& projection) {
    for (std::size_t c = 0; c < s.n_constraints; ++c)
        if (!s.constraint_holonomic[c])
            throw std::invalid_argument("lagrangian_rattle: constraint '" + s.constraint_names[c] +
                                        "' is nonholonomic; RATTLE handles holonomic constraints only (use the implicit "
                                        "midpoint rule, lagrangian_midpoint)");
    const std::size_t n = s.dof;
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(n));
    NumericRule r{"rattle", Domain(kGQ, all) | Domain(kGV, all), {}, nullptr, layout};
    r.step = [s, n, projection](double dt, World& w) {
        thread_local RattleScratch k;
        k.size(n, s.n_constraints);
        rattle_step(s, w.time, dt, w.field(kGQ), w.field(kGV), projection, k);
    };
    return NumericWorkflow::run(r);
}

} // namespace phynjo::runtime
