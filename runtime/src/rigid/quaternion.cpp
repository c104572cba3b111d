#include "phynjo/runtime/rigid/quaternion.hpp"

#include <Eigen/Geometry>

namespace phynjo::runtime {

Quaternion Quaternion::from_axis_angle(const Eigen::Vector3d& axis, double angle) {
    const Eigen::Vector3d a = axis.normalized();
    const double s = std::sin(0.5 * angle);
    return Quaternion{std::cos(0.5 * angle), s * a.x(), s * a.y(), s * a.z()}.normalized();
}

Quaternion Quaternion::from_matrix(const Eigen::Matrix3d& r) {
    // 4w² = 1 + tr R, 4x² = 1 + R00 − R11 − R22, …; take the largest (|·| ≥ 1/2) and get the
    // other three from the off-diagonal sums and differences, e.g. R21 − R12 = 4wx.
    const double tr = r.trace();
    Quaternion q;
    if (tr >= r(0, 0) && tr >= r(1, 1) && tr >= r(2, 2)) {
        const double s = 2 * std::sqrt(1 + tr); // 4w
        q = {0.25 * s, (r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s};
    } else if (r(0, 0) >= r(1, 1) && r(0, 0) >= r(2, 2)) {
        const double s = 2 * std::sqrt(1 + r(0, 0) - r(1, 1) - r(2, 2)); // 4x
        q = {(r(2, 1) - r(1, 2)) / s, 0.25 * s, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s};
    } else if (r(1, 1) >= r(2, 2)) {
        const double s = 2 * std::sqrt(1 - r(0, 0) + r(1, 1) - r(2, 2)); // 4y
        q = {(r(0, 2) - r(2, 0)) / s, (r(0, 1) + r(1, 0)) / s, 0.25 * s, (r(1, 2) + r(2, 1)) / s};
    } else {
        const double s = 2 * std::sqrt(1 - r(0, 0) - r(1, 1) + r(2, 2)); // 4z
        q = {(r(1, 0) - r(0, 1)) / s, (r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, 0.25 * s};
    }
    if (q.w < 0) q = {-q.w, -q.x, -q.y, -q.z};
    return q.normalized();
}

Quaternion integrate_first_order(const Quaternion& q, const Eigen::Vector3d& om, double dt) noexcept {
    // Q ⊗ (0, ω): its components mw, mx, my, mz.
    const double mw = -q.x * om.x() - q.y * om.y() - q.z * om.z();
    const double mx = q.w * om.x() + q.y * om.z() - q.z * om.y();
    const double my = q.w * om.y() - q.x * om.z() + q.z * om.x();
    const double mz = q.w * om.z() + q.x * om.y() - q.y * om.x();
    const double h = 0.5 * dt;
    return Quaternion{q.w + h * mw, q.x + h * mx, q.y + h * my, q.z + h * mz}.normalized();
}

Quaternion integrate_exponential(const Quaternion& q, const Eigen::Vector3d& om, double dt) noexcept {
    const double n = om.norm();
    const double half = 0.5 * n * dt;
    if (half < 1e-8) {
        // sin(h)/|ω| = dt/2 (1 − h²/6 + …): the series avoids 0/0 and is exact to round-off here.
        const double s = 0.5 * dt * (1 - half * half / 6);
        return (Quaternion{1 - 0.5 * half * half, s * om.x(), s * om.y(), s * om.z()} * q).normalized();
    }
    const double s = std::sin(half) / n;
    return (Quaternion{std::cos(half), s * om.x(), s * om.y(), s * om.z()} * q).normalized();
}

} // namespace phynjo::runtime
