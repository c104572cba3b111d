#include "phynjo/runtime/collision/bounding_volume.hpp"

#include <cmath>

namespace phynjo::runtime {

bool OBB::contains(const Eigen::Vector3d& p) const noexcept {
    const Eigen::Vector3d local = rotation.rotate_inverse(p - center);
    return (local.cwiseAbs().array() <= half.array()).all();
}

bool intersects(const AABB& a, const SphereBB& s) noexcept {
    const Eigen::Vector3d closest = s.center.cwiseMax(a.lo).cwiseMin(a.hi);
    return (closest - s.center).squaredNorm() <= s.radius * s.radius;
}

bool intersects(const OBB& a, const OBB& b) noexcept {
    // Work in a's frame: R = A_ᵀ B expresses b's axes in a's, t = a's-frame centre offset.
    const Eigen::Matrix3d A = a.rotation.to_matrix(), B = b.rotation.to_matrix();
    const Eigen::Matrix3d R = A.transpose() * B;
    const Eigen::Vector3d t = A.transpose() * (b.center - a.center);
    Eigen::Matrix3d absR = R.cwiseAbs();
    absR.array() += 1e-12; // an edge cross product of (nearly) parallel edges is ~0: never a false "separated"
    const Eigen::Vector3d& ha = a.half;
    const Eigen::Vector3d& hb = b.half;
    // Axes A0, A1, A2.
    for (int i = 0; i < 3; ++i)
        if (std::abs(t(i)) > ha(i) + hb.dot(absR.row(i))) return false;
    // Axes B0, B1, B2.
    for (int j = 0; j < 3; ++j)
        if (std::abs(t.dot(R.col(j))) > ha.dot(absR.col(j)) + hb(j)) return false;
    // Axes Ai × Bj: projected radii and distance from the cyclic index identities.
    for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        for (int j = 0; j < 3; ++j) {
            const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            const double ra = ha(i1) * absR(i2, j) + ha(i2) * absR(i1, j);
            const double rb = hb(j1) * absR(i, j2) + hb(j2) * absR(i, j1);
            const double d = std::abs(t(i2) * R(i1, j) - t(i1) * R(i2, j));
            if (d > ra + rb) return false;
        }
    }
    return true;
}

bool intersects(const OBB& a, const SphereBB& s) noexcept {
    const Eigen::Vector3d local = a.rotation.rotate_inverse(s.center - a.center);
    const Eigen::Vector3d closest = local.cwiseMax(-a.half).cwiseMin(a.half);
    return (closest - local).squaredNorm() <= s.radius * s.radius;
}

AABB aabb_from_obb(const OBB& b) noexcept {
    const Eigen::Vector3d e = b.rotation.to_matrix().cwiseAbs() * b.half;
    return {b.center - e, b.center + e};
}

} // namespace phynjo::runtime
