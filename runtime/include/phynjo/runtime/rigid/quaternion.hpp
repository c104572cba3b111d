#pragma once
/// \file
/// Unit quaternions for orientations: Q = (w, x, y, z), ‖Q‖ = 1, rotating body-frame vectors
/// into the world frame, v_W = R(Q) v_B. Conversions to and from rotation matrices (Eigen),
/// the Hamilton product and the two orientation updates of the rigid-body runes.
#include <Eigen/Core>
#include <Eigen/Geometry> // cross products

#include <cmath>

namespace phynjo::runtime {

struct Quaternion {
    double w = 1, x = 0, y = 0, z = 0;

    /// The identity rotation.
    static constexpr Quaternion identity() noexcept { return {1, 0, 0, 0}; }
    /// Rotation by `angle` (rad) about the unit vector `axis` (right-handed):
    /// Q = (cos(θ/2), sin(θ/2) â).
    static Quaternion from_axis_angle(const Eigen::Vector3d& axis, double angle);
    /// The unit quaternion of a proper rotation matrix (Shepperd's method: the largest of
    /// w², x², y², z² is taken from the trace or a diagonal entry, so the result is accurate
    /// for every rotation, including half-turns). The sign is chosen with w ≥ 0.
    static Quaternion from_matrix(const Eigen::Matrix3d& r);

    [[nodiscard]] double norm() const noexcept { return std::sqrt(w * w + x * x + y * y + z * z); }
    [[nodiscard]] Quaternion normalized() const noexcept {
        const double n = norm();
        return {w / n, x / n, y / n, z / n};
    }
    [[nodiscard]] Quaternion conjugate() const noexcept { return {w, -x, -y, -z}; }

    /// The active rotation matrix (body → world):
    ///   R = [[w²+x²−y²−z², 2(xy−wz), 2(xz+wy)],
    ///        [2(xy+wz), w²−x²+y²−z², 2(yz−wx)],
    ///        [2(xz−wy), 2(yz+wx), w²−x²−y²+z²]].
    [[nodiscard]] Eigen::Matrix3d to_matrix() const noexcept {
        const double ww = w * w, xx = x * x, yy = y * y, zz = z * z;
        const double wx = w * x, wy = w * y, wz = w * z, xy = x * y, xz = x * z, yz = y * z;
        Eigen::Matrix3d r;
        r << ww + xx - yy - zz, 2 * (xy - wz), 2 * (xz + wy), //
            2 * (xy + wz), ww - xx + yy - zz, 2 * (yz - wx),   //
            2 * (xz - wy), 2 * (yz + wx), ww - xx - yy + zz;
        return r;
    }
    /// R(Q) v = v + 2w (u × v) + 2 u × (u × v), u = (x, y, z): 15 multiplications, no matrix
    /// (inline: the contact solver rotates every anchor of every pass).
    [[nodiscard]] Eigen::Vector3d rotate(const Eigen::Vector3d& v) const noexcept {
        const Eigen::Vector3d u(x, y, z);
        const Eigen::Vector3d t = 2 * u.cross(v);
        return v + w * t + u.cross(t);
    }
    /// R(Q)ᵀ v (world → body).
    [[nodiscard]] Eigen::Vector3d rotate_inverse(const Eigen::Vector3d& v) const noexcept {
        return conjugate().rotate(v);
    }

    /// Hamilton product: the rotation b followed by a is a ⊗ b.
    friend Quaternion operator*(const Quaternion& a, const Quaternion& b) noexcept {
        return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
    }
    friend bool operator==(const Quaternion&, const Quaternion&) = default;
};

/// One explicit Euler step (`integrateQuat`) of Q̇ = ½ Q ⊗ (0, ω_B) (ω_B: body-frame
/// angular velocity, rad/s) followed by renormalisation. First order; the renormalisation
/// keeps ‖Q‖ = 1 to round-off.
Quaternion integrate_first_order(const Quaternion& q, const Eigen::Vector3d& omega_body, double dt) noexcept;

/// The exact update for an angular velocity that is constant over the step:
/// Q' = exp(½ dt (0, ω_W)) ⊗ Q = (cos(|ω|dt/2), sin(|ω|dt/2) ω̂) ⊗ Q, renormalised (ω_W:
/// world-frame angular velocity, rad/s). Exact for constant ω; the rune's default.
Quaternion integrate_exponential(const Quaternion& q, const Eigen::Vector3d& omega_world, double dt) noexcept;

} // namespace phynjo::runtime
