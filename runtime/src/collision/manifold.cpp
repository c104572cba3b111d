// Manifolds of boxes with planes and spheres, and the point reduction (manifold.hpp); box–box
// is in box_box.cpp.
#include "manifold_detail.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace phynjo::runtime {

void Manifold::flip() {
    normal = -normal;
    for (int k = 0; k < count; ++k) std::swap(points[static_cast<std::size_t>(k)].on_a, points[static_cast<std::size_t>(k)].on_b);
}

namespace manifold_detail {

void keep_four(const ManifoldPoint* found, int m, Manifold& out) {
    if (m <= 4) {
        for (int k = 0; k < m; ++k) out.points[static_cast<std::size_t>(k)] = found[k];
        out.count = m;
        return;
    }
    auto at = [&](int k) -> Eigen::Vector3d { return 0.5 * (found[k].on_a + found[k].on_b); };
    auto area = [&](int i, int j, int k) { return (at(j) - at(i)).cross(at(k) - at(i)).dot(out.normal); };
    int p0 = 0;
    for (int k = 1; k < m; ++k)
        if (found[k].separation < found[p0].separation) p0 = k;
    int p1 = -1;
    double far = -1;
    for (int k = 0; k < m; ++k) {
        const double d = k == p0 ? -1 : (at(k) - at(p0)).squaredNorm();
        if (d > far) far = d, p1 = k;
    }
    int p2 = -1;
    double big = -1;
    for (int k = 0; k < m; ++k) {
        const double s = k == p0 || k == p1 ? -1 : std::abs(area(p0, p1, k));
        if (s > big) big = s, p2 = k;
    }
    // Orient the triangle counter-clockwise about the normal; the fourth point adds the most
    // area outside one of its edges.
    if (area(p0, p1, p2) < 0) std::swap(p1, p2);
    int p3 = -1;
    double more = -1;
    for (int k = 0; k < m; ++k) {
        if (k == p0 || k == p1 || k == p2) continue;
        const double s = std::max({-area(p0, p1, k), -area(p1, p2, k), -area(p2, p0, k)});
        if (s > more) more = s, p3 = k;
    }
    int keep[4] = {p0, p1, p2, p3};
    std::sort(keep, keep + 4); // in the order found: stable across steps
    for (int k = 0; k < 4; ++k) out.points[static_cast<std::size_t>(k)] = found[keep[k]];
    out.count = 4;
}

} // namespace manifold_detail

void box_plane(const OBB& a, const Plane& plane, double margin, Manifold& out) {
    out.count = 0;
    out.normal = plane.normal;
    const Eigen::Matrix3d r = a.rotation.to_matrix();
    std::array<ManifoldPoint, 8> found{};
    int m = 0;
    for (std::uint32_t v = 0; v < 8; ++v) {
        const Eigen::Vector3d local((v & 1u) ? a.half.x() : -a.half.x(), (v & 2u) ? a.half.y() : -a.half.y(),
                                    (v & 4u) ? a.half.z() : -a.half.z());
        const Eigen::Vector3d x = a.center + r * local;
        const double s = plane.normal.dot(x) - plane.offset;
        if (s >= margin) continue;
        ManifoldPoint& p = found[static_cast<std::size_t>(m++)];
        p.on_a = x;
        p.on_b = x - s * plane.normal;
        p.separation = s;
        p.feature = v;
    }
    manifold_detail::keep_four(found.data(), m, out);
}

void sphere_box(const SphereBB& a, const OBB& b, double margin, Manifold& out) {
    out.count = 0;
    const Eigen::Matrix3d r = b.rotation.to_matrix();
    const Eigen::Vector3d c = r.transpose() * (a.center - b.center); // the centre in b's frame
    const Eigen::Vector3d q = c.cwiseMax(-b.half).cwiseMin(b.half);
    Eigen::Vector3d n_local;
    double dist;
    // Region: per axis 0 below, 1 inside, 2 above the slab; 27 regions, the inside one 13.
    std::uint32_t region = 0;
    for (int k = 2; k >= 0; --k) region = 3 * region + (c(k) < -b.half(k) ? 0u : c(k) > b.half(k) ? 2u : 1u);
    Eigen::Vector3d on_box = q;
    if (region != 13) { // outside: the closest point
        const Eigen::Vector3d dv = c - q;
        dist = dv.norm();
        n_local = dv / dist;
    } else { // inside: out through the nearest face
        int k = 0;
        double least = INFINITY;
        for (int i = 0; i < 3; ++i) {
            const double x = b.half(i) - std::abs(c(i));
            if (x < least) least = x, k = i;
        }
        n_local = Eigen::Vector3d::Zero();
        n_local(k) = c(k) >= 0 ? 1 : -1;
        on_box(k) = n_local(k) * b.half(k);
        dist = -least;
        region = 27 + static_cast<std::uint32_t>(2 * k + (c(k) >= 0 ? 1 : 0));
    }
    const double s = dist - a.radius;
    if (s >= margin) return;
    out.normal = r * n_local;
    ManifoldPoint& p = out.points[0];
    p.on_b = b.center + r * on_box;
    p.on_a = a.center - a.radius * out.normal;
    p.separation = s;
    p.feature = region;
    out.count = 1;
}

} // namespace phynjo::runtime
