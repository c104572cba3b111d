// The continuous extension of a step and the Illinois root finder. See simulate/detail/crossing.hpp.
#include "phynjo/runtime/simulate/detail/crossing.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace phynjo::runtime {

HermiteStep::HermiteStep(double t0, double t1, std::span<const double> q0, std::span<const double> v0,
                         std::span<const double> a0, std::span<const double> q1, std::span<const double> v1,
                         std::span<const double> a1)
    : t0_(t0), t1_(t1), q0_(q0), v0_(v0), a0_(a0), q1_(q1), v1_(v1), a1_(a1) {
    const std::size_t n = q0.size();
    if (!(t1 > t0)) throw std::invalid_argument("HermiteStep: the step must have t1 > t0");
    if (v0.size() != n || a0.size() != n || q1.size() != n || v1.size() != n || a1.size() != n)
        throw std::invalid_argument("HermiteStep: q, v and a at both ends must have the same length");
}

void HermiteStep::at(double t, std::span<double> q, std::span<double> v) const {
    if (!(t >= t0_ && t <= t1_))
        throw std::invalid_argument("HermiteStep::at: t = " + std::to_string(t) + " is outside the step [" +
                                    std::to_string(t0_) + ", " + std::to_string(t1_) + "]");
    if (q.size() != q0_.size() || v.size() != q0_.size())
        throw std::invalid_argument("HermiteStep::at: q and v must have length " + std::to_string(q0_.size()));
    const double h = t1_ - t0_, s = (t - t0_) / h, s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    for (std::size_t i = 0; i < q0_.size(); ++i) {
        q[i] = h00 * q0_[i] + h10 * h * v0_[i] + h01 * q1_[i] + h11 * h * v1_[i];
        v[i] = h00 * v0_[i] + h10 * h * a0_[i] + h01 * v1_[i] + h11 * h * a1_[i];
    }
}

Crossing locate_crossing(const std::function<double(double)>& g, double a, double b, double ga, double gb,
                         double tolerance, int max_evaluations) {
    if (!(a < b)) throw std::invalid_argument("locate_crossing: the bracket needs a < b");
    if (!std::isfinite(ga) || !std::isfinite(gb))
        throw std::invalid_argument("locate_crossing: the guard is not finite at an end of the bracket");
    if (ga == 0) return {a, a, a, 0};
    if (gb == 0) return {b, b, b, 0};
    if ((ga > 0) == (gb > 0))
        throw std::invalid_argument("locate_crossing: the guard has the same sign at both ends (" + std::to_string(ga) +
                                    ", " + std::to_string(gb) + "): no crossing bracketed");
    double lo = a, hi = b, glo = ga, ghi = gb;
    int kept = 0;      // +1: lo was kept last time, −1: hi was; for the Illinois halving
    int slow = 0;      // steps in a row that did not halve the bracket
    int evaluations = 0;
    while (hi - lo > tolerance) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break; // lo and hi adjacent doubles
        if (evaluations >= max_evaluations)
            throw ConvergenceError("locate_crossing: the bracket [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                   "] has not closed after " + std::to_string(max_evaluations) + " evaluations");
        const double width = hi - lo;
        double t = slow >= 3 ? mid : (lo * ghi - hi * glo) / (ghi - glo);
        if (!(t > lo && t < hi)) t = mid; // the secant left the bracket (round-off): bisect
        const double gt = g(t);
        ++evaluations;
        if (!std::isfinite(gt))
            throw ConvergenceError("locate_crossing: the guard is not finite at t = " + std::to_string(t));
        if (gt == 0) return {t, t, t, evaluations};
        if ((gt > 0) == (ghi > 0)) { // the crossing is in [lo, t]
            hi = t;
            ghi = gt;
            if (kept == +1) glo *= 0.5; // lo retained twice: Illinois
            kept = +1;
        } else { // in [t, hi]
            lo = t;
            glo = gt;
            if (kept == -1) ghi *= 0.5;
            kept = -1;
        }
        slow = hi - lo > 0.5 * width ? slow + 1 : 0; // a bisection halves it: secants again
    }
    return {hi, lo, hi, evaluations};
}

} // namespace phynjo::runtime
