#pragma once
/// \file
/// Bounding volumes: axis-aligned boxes, spheres and
/// oriented boxes, their containment and intersection tests (closed sets: touching counts
/// as intersecting), aabb_union and the conservative AABB of a sphere or an OBB.
#include "phynjo/runtime/rigid/quaternion.hpp"

#include <Eigen/Core>

namespace phynjo::runtime {

/// Axis-aligned box [lo, hi] (m). Valid when lo ≤ hi componentwise.
struct AABB {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    [[nodiscard]] bool contains(const Eigen::Vector3d& p) const noexcept {
        return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
    }
    [[nodiscard]] Eigen::Vector3d extent() const noexcept { return hi - lo; }
};

/// Sphere: centre (m) and radius (m).
struct SphereBB {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    double radius = 0;
    [[nodiscard]] bool contains(const Eigen::Vector3d& p) const noexcept {
        return (p - center).squaredNorm() <= radius * radius;
    }
};

/// Oriented box: centre (m), half-sizes along its local axes (m), and the rotation that
/// takes local axes to world axes.
struct OBB {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    Quaternion rotation = Quaternion::identity();
    [[nodiscard]] bool contains(const Eigen::Vector3d& p) const noexcept;
};

/// Two boxes intersect iff their intervals overlap on all three axes.
[[nodiscard]] inline bool intersects(const AABB& a, const AABB& b) noexcept {
    return a.hi.x() >= b.lo.x() && b.hi.x() >= a.lo.x() && a.hi.y() >= b.lo.y() && b.hi.y() >= a.lo.y() &&
           a.hi.z() >= b.lo.z() && b.hi.z() >= a.lo.z();
}
/// |c₁ − c₂|² ≤ (r₁ + r₂)².
[[nodiscard]] inline bool intersects(const SphereBB& a, const SphereBB& b) noexcept {
    const double r = a.radius + b.radius;
    return (a.center - b.center).squaredNorm() <= r * r;
}
/// The closest point of the box to the centre is within the radius.
[[nodiscard]] bool intersects(const AABB& a, const SphereBB& s) noexcept;
[[nodiscard]] inline bool intersects(const SphereBB& s, const AABB& a) noexcept { return intersects(a, s); }
/// Separating-axis test over the 15 candidate axes (3 face normals of each box and the 9
/// cross products of their edges); near-parallel edges are handled by padding the rotation
/// terms with ε = 1e-12 (Gottschalk, Lin & Manocha, "OBBTree", SIGGRAPH 1996; Ericson,
/// Real-Time Collision Detection, §4.4.1).
[[nodiscard]] bool intersects(const OBB& a, const OBB& b) noexcept;
[[nodiscard]] bool intersects(const OBB& a, const SphereBB& s) noexcept;

/// The smallest AABB containing both (componentwise min and max).
[[nodiscard]] inline AABB aabb_union(const AABB& a, const AABB& b) noexcept {
    return {a.lo.cwiseMin(b.lo), a.hi.cwiseMax(b.hi)};
}
/// [c − r, c + r] on each axis.
[[nodiscard]] inline AABB aabb_from_sphere(const SphereBB& s) noexcept {
    const Eigen::Vector3d r = Eigen::Vector3d::Constant(s.radius);
    return {s.center - r, s.center + r};
}
/// The tight AABB of an OBB: half-extent_i = Σ_j |R_ij| h_j.
[[nodiscard]] AABB aabb_from_obb(const OBB& b) noexcept;

} // namespace phynjo::runtime
