// Dormand–Prince 5(4) with local error control for generated models: seven stages (FSAL),
// the fifth-order solution advances, the embedded fourth-order one estimates the error.
// Order 5; not symplectic.
// Reference: J. R. Dormand, P. J. Prince, J. Comput. Appl. Math. 6, 19 (1980).
#include "phynjo/runtime/integrators/dormand_prince.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace phynjo::runtime {

DormandPrince45::DormandPrince45(LagrangianSystem system, Options options) : sys_(std::move(system)), opt_(options) {
    const std::size_t m = 2 * sys_.dof;
    y_.assign(m, 0.0);
    tmp_.assign(m, 0.0);
    acc_.assign(sys_.dof, 0.0);
    for (auto& k : k_) k.assign(m, 0.0);
    for (auto& r : rcont_) r.assign(m, 0.0);
}

void DormandPrince45::dense(double t, std::span<double> q, std::span<double> v) const {
    if (dense_h_ <= 0) throw std::logic_error("DormandPrince45::dense: no step taken yet");
    const double th = (t - dense_t0_) / dense_h_;
    if (!(th >= -1e-12 && th <= 1 + 1e-12) || q.size() != sys_.dof || v.size() != sys_.dof)
        throw std::invalid_argument("DormandPrince45::dense: t = " + std::to_string(t) + " outside the last step, or wrong sizes");
    const double th1 = 1 - th;
    const std::size_t n = sys_.dof;
    for (std::size_t i = 0; i < 2 * n; ++i) {
        const double y = rcont_[0][i] + th * (rcont_[1][i] + th1 * (rcont_[2][i] + th * (rcont_[3][i] + th1 * rcont_[4][i])));
        (i < n ? q[i] : v[i - n]) = y;
    }
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
            // the dense output (Hairer's DOPRI5, CONTD5), from y0, y1 = tmp_ and the stages
            static constexpr double d1 = -12715105075.0 / 11282082432, d3 = 87487479700.0 / 32700410799,
                                    d4 = -10690763975.0 / 1880347072, d5 = 701980252875.0 / 199316789632,
                                    d6 = -1453857185.0 / 822651844, d7 = 69997945.0 / 29380423;
            for (std::size_t i = 0; i < m; ++i) {
                const double ydiff = tmp_[i] - y_[i], bspl = dt * k_[0][i] - ydiff;
                rcont_[0][i] = y_[i];
                rcont_[1][i] = ydiff;
                rcont_[2][i] = bspl;
                rcont_[3][i] = ydiff - dt * k_[6][i] - bspl;
                rcont_[4][i] = dt * (d1 * k_[0][i] + d3 * k_[2][i] + d4 * k_[3][i] + d5 * k_[4][i] + d6 * k_[5][i] + d7 * k_[6][i]);
            }
            dense_t0_ = w.time;
            dense_h_ = dt;
            for (Index i = 0; i < n; ++i) {
                w.at(kGQ, i) = tmp_[i];
                w.at(kGV, i) = tmp_[n + i];
            }
            w.time += dt;
            if (sys_.n_constraints > 0) project_onto_constraints(sys_, w.time, w.field(kGQ), w.field(kGV), opt_.projection);
            next_ = std::min(dt * factor, opt_.dt_max);
            return dt;
        }
        ++rejected_;
        dt *= std::isfinite(err) ? factor : 0.2;
    }
}

} // namespace phynjo::runtime
