#include "phynjo/runtime/lagrangian.hpp"

#include "rk4_stages.hpp"

#include <algorithm>

namespace phynjo::runtime {

World make_lagrangian_world(const LagrangianSystem& s) {
    Registry r;
    for (const auto& name : s.coordinate_names) r.add(name);
    World w(std::make_shared<Layout>(r, std::vector<std::string>{"q", "qd", "rk_q0", "rk_v0", "rk_aq", "rk_av"}));
    if (s.initial_state) s.initial_state(w.field(kGQ), w.field(kGV));
    return w;
}

NumericWorkflow lagrangian_rk4(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout) {
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(s.dof));
    // f(t, q, q') = (q', q''(t, q, q')); the stage storage is fields 2…5 of the world.
    auto derivative = [acc = s.accelerations](double t, const World& w, std::span<double> kq, std::span<double> kv) {
        const std::size_t n = w.size();
        acc(t, w.field(kGQ), w.field(kGV), kv.first(n));
        for (Index i = 0; i < n; ++i) kq[i] = w.at(kGV, i);
    };
    return detail::rk4_workflow({kGQ, kGV, 2, 3, 4, 5}, all, {}, derivative, layout);
}

namespace {

/// Velocities v with p(t, q, v) = p: Newton with the mass matrix M = ∂p/∂v as Jacobian,
/// factorized once per call (exact after one iteration when L is quadratic in the
/// velocities; a few iterations otherwise). `M` and `r` are scratch of sizes n² and n.
void velocities_from_momenta(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> p,
                             std::span<double> v, std::vector<double>& M, std::vector<double>& r,
                             std::vector<std::size_t>& perm) {
    const std::size_t n = s.dof;
    s.mass_matrix(t, q, M);
    // LU with partial pivoting of M (small, symmetric positive definite in mechanics)
    perm.resize(n);
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
    for (int it = 0; it < 30; ++it) {
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

// ---- Dormand–Prince 5(4) ------------------------------------------------------------------------

DormandPrince45::DormandPrince45(LagrangianSystem system, Options options) : sys_(std::move(system)), opt_(options) {
    const std::size_t m = 2 * sys_.dof;
    y_.assign(m, 0.0);
    tmp_.assign(m, 0.0);
    acc_.assign(sys_.dof, 0.0);
    for (auto& k : k_) k.assign(m, 0.0);
}

double DormandPrince45::step(World& w, double dt, double t_end) {
    static constexpr double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
    static constexpr double a[7][6] = {
        {},
        {1.0 / 5},
        {3.0 / 40, 9.0 / 40},
        {44.0 / 45, -56.0 / 15, 32.0 / 9},
        {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
        {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
        {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
    static constexpr double b5[7] = {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0};
    static constexpr double b4[7] = {5179.0 / 57600, 0, 7571.0 / 16695, 393.0 / 640, -92097.0 / 339200, 187.0 / 2100, 1.0 / 40};
    const std::size_t n = sys_.dof, m = 2 * n;
    for (Index i = 0; i < n; ++i) {
        y_[i] = w.at(kGQ, i);
        y_[n + i] = w.at(kGV, i);
    }
    auto rhs = [&](double t, const std::vector<double>& y, std::vector<double>& k) {
        sys_.accelerations(t, std::span<const double>(y.data(), n), std::span<const double>(y.data() + n, n), acc_);
        for (std::size_t i = 0; i < n; ++i) {
            k[i] = y[n + i];
            k[n + i] = acc_[i];
        }
    };
    dt = std::min({dt, opt_.dt_max, t_end - w.time});
    for (;;) {
        if (dt < opt_.dt_min) throw ConvergenceError("Dormand-Prince step below dt_min at t = " + std::to_string(w.time));
        rhs(w.time, y_, k_[0]);
        for (int s = 1; s < 7; ++s) {
            for (std::size_t i = 0; i < m; ++i) {
                double v = y_[i];
                for (int j = 0; j < s; ++j) v += dt * a[s][j] * k_[j][i];
                tmp_[i] = v;
            }
            rhs(w.time + c[s] * dt, tmp_, k_[s]);
        }
        double err = 0;
        for (std::size_t i = 0; i < m; ++i) {
            double e5 = 0, e4 = 0;
            for (int s = 0; s < 7; ++s) {
                e5 += b5[s] * k_[s][i];
                e4 += b4[s] * k_[s][i];
            }
            const double y5 = y_[i] + dt * e5;
            const double sc = opt_.atol + opt_.rtol * std::max(std::fabs(y_[i]), std::fabs(y5));
            const double e = dt * (e5 - e4) / sc;
            err += e * e;
            tmp_[i] = y5;
        }
        err = std::sqrt(err / static_cast<double>(m));
        const double factor = std::clamp(0.9 * std::pow(std::max(err, 1e-10), -0.2), 0.2, 5.0);
        if (err <= 1 && std::isfinite(err)) {
            for (Index i = 0; i < n; ++i) {
                w.at(kGQ, i) = tmp_[i];
                w.at(kGV, i) = tmp_[n + i];
            }
            w.time += dt;
            next_ = std::min(dt * factor, opt_.dt_max);
            return dt;
        }
        ++rejected_;
        dt *= std::isfinite(err) ? factor : 0.2;
    }
}

} // namespace phynjo::runtime
