// Manifolds of boxes with planes and spheres, and the point reduction (manifold.hpp); box–box
// is in box_box.cpp.
#include "manifold_detail.hpp"

#include <algorithm>
#include <array>
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
    // Each point midway between its two surfaces, once (m ≤ 8).
    std::array<Eigen::Vector3d, 8> mid;
    for (Eigen::Vector3d& x : mid) x.setZero(); // (GCC cannot see that only the first m are read)
    for (int k = 0; k < m; ++k) mid[static_cast<std::size_t>(k)] = 0.5 * (found[k].on_a + found[k].on_b);
    auto at = [&](int k) -> const Eigen::Vector3d& { return mid[static_cast<std::size_t>(k)]; };
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
    box_plane(a, a.rotation.to_matrix(), plane, margin, out);
}

void box_plane(const OBB& a, const Eigen::Matrix3d& r, const Plane& plane, double margin, Manifold& out) {
    out.count = 0;
    out.normal = plane.normal;
    // The box's lowest point along the normal is at n·c − Σ h_i |n·r_i| from the plane: when
    // that clears the margin by more than the corners' own rounding could (1e-12 relative:
    // thousands of ulps), no corner is within it — most boxes of a pile, against most walls.
    const double centre = plane.normal.dot(a.center) - plane.offset;
    const double reach = a.half.dot((r.transpose() * plane.normal).cwiseAbs());
    if (centre - reach > margin + 1e-12 * (std::abs(centre) + reach + std::abs(plane.offset))) return;
    std::array<ManifoldPoint, 8> found; // each entry written before it is read
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

namespace {

/// The parameter t ∈ [0, 1] of the point of [p0, p1] closest to x.
double closest_on_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& x) {
    const Eigen::Vector3d e = p1 - p0;
    const double l2 = e.squaredNorm();
    return l2 > 0 ? std::clamp((x - p0).dot(e) / l2, 0.0, 1.0) : 0.0;
}

/// Two spheres (a at ca, b at cb) as one manifold point; n fallback when the centres meet.
void two_spheres(const Eigen::Vector3d& ca, double ra, const Eigen::Vector3d& cb, double rb, double margin,
                 std::uint32_t feature, const Eigen::Vector3d& fallback, Manifold& out) {
    const Eigen::Vector3d d = ca - cb;
    const double l = d.norm();
    const double s = l - ra - rb;
    if (s >= margin) return;
    if (out.count == 0) out.normal = l > 0 ? Eigen::Vector3d(d / l) : fallback;
    const Eigen::Vector3d& n = out.normal;
    ManifoldPoint& p = out.points[static_cast<std::size_t>(out.count++)];
    p.on_a = ca - ra * n;
    p.on_b = cb + rb * n;
    p.separation = (p.on_a - p.on_b).dot(n);
    p.feature = feature;
}

/// Closest points of segments [p0, p1] and [q0, q1]: parameters (s, t) (Ericson, Real-Time
/// Collision Detection, §5.1.9).
std::pair<double, double> closest_segments(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                                           const Eigen::Vector3d& q1) {
    const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    if (a <= 1e-30 && e <= 1e-30) return {0, 0};
    if (a <= 1e-30) return {0, std::clamp(f / e, 0.0, 1.0)};
    const double c = d1.dot(r);
    if (e <= 1e-30) return {std::clamp(-c / a, 0.0, 1.0), 0};
    const double b = d1.dot(d2), den = a * e - b * b;
    double s = den > 0 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
    double t = (b * s + f) / e;
    if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
    } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
    }
    return {s, t};
}

/// A unit vector perpendicular to e (any; deterministic).
Eigen::Vector3d perpendicular(const Eigen::Vector3d& e) {
    return e.squaredNorm() > 0 ? Eigen::Vector3d(e.unitOrthogonal()) : Eigen::Vector3d(0, 1, 0);
}

} // namespace

void capsule_plane(const Capsule& a, const Plane& plane, double margin, Manifold& out) {
    out.count = 0;
    out.normal = plane.normal;
    const Eigen::Vector3d* ends[2] = {&a.p0, &a.p1};
    for (std::uint32_t i = 0; i < 2; ++i) {
        const Eigen::Vector3d& x = *ends[i];
        const double h = plane.normal.dot(x) - plane.offset;
        if (h - a.radius >= margin) continue;
        ManifoldPoint& p = out.points[static_cast<std::size_t>(out.count++)];
        p.on_a = x - a.radius * plane.normal;
        p.on_b = x - h * plane.normal;
        p.separation = h - a.radius;
        p.feature = i;
    }
}

void capsule_sphere(const Capsule& a, const SphereBB& b, double margin, Manifold& out) {
    out.count = 0;
    const double t = closest_on_segment(a.p0, a.p1, b.center);
    const Eigen::Vector3d x = a.p0 + t * (a.p1 - a.p0);
    two_spheres(x, a.radius, b.center, b.radius, margin, 0, perpendicular(a.p1 - a.p0), out);
}

void capsule_capsule(const Capsule& a, const Capsule& b, double margin, Manifold& out) {
    out.count = 0;
    const Eigen::Vector3d da = a.p1 - a.p0, db = b.p1 - b.p0;
    const double la = da.norm(), lb = db.norm();
    if (la > 0 && lb > 0 && da.cross(db).norm() < 1e-3 * la * lb) {
        // Parallel: the part of b's segment whose projection falls on a's, both ends of it.
        const Eigen::Vector3d u = da / la;
        double t0 = (b.p0 - a.p0).dot(u), t1 = (b.p1 - a.p0).dot(u);
        if (t0 > t1) std::swap(t0, t1);
        const double lo = std::max(t0, 0.0), hi = std::min(t1, la);
        if (hi - lo > 1e-9 * la) {
            Eigen::Vector3d n_perp = (a.p0 - b.p0) - (a.p0 - b.p0).dot(u) * u; // from b's line to a's
            const double gap = n_perp.norm();
            const Eigen::Vector3d n = gap > 1e-12 * la ? Eigen::Vector3d(n_perp / gap) : perpendicular(u);
            out.normal = n;
            for (std::uint32_t i = 0; i < 2; ++i) {
                const Eigen::Vector3d xa = a.p0 + (i == 0 ? lo : hi) * u;
                const Eigen::Vector3d xb = b.p0 + closest_on_segment(b.p0, b.p1, xa) * db;
                if ((xa - xb).dot(n) - a.radius - b.radius >= margin) continue;
                ManifoldPoint& p = out.points[static_cast<std::size_t>(out.count++)];
                p.on_a = xa - a.radius * n;
                p.on_b = xb + b.radius * n;
                p.separation = (p.on_a - p.on_b).dot(n);
                p.feature = i;
            }
            return;
        }
    }
    const auto [s, t] = closest_segments(a.p0, a.p1, b.p0, b.p1);
    const Eigen::Vector3d xa = a.p0 + s * da, xb = b.p0 + t * db;
    Eigen::Vector3d fallback = da.cross(db);
    fallback = fallback.norm() > 0 ? Eigen::Vector3d(fallback.normalized()) : perpendicular(da);
    two_spheres(xa, a.radius, xb, b.radius, margin, 2, fallback, out);
}

void capsule_box(const Capsule& a, const OBB& b, double margin, Manifold& out) {
    out.count = 0;
    const Eigen::Matrix3d r = b.rotation.to_matrix();
    // In the box's frame.
    const Eigen::Vector3d p0 = r.transpose() * (a.p0 - b.center), p1 = r.transpose() * (a.p1 - b.center);
    const Eigen::Vector3d& h = b.half;
    auto distance2 = [&](double t) {
        const Eigen::Vector3d x = p0 + t * (p1 - p0);
        return (x - x.cwiseMax(-h).cwiseMin(h)).squaredNorm();
    };
    // Golden-section search for the t of least distance (convex in t; flat where inside).
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    double lo = 0, hi = 1;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = distance2(x1), f2 = distance2(x2);
    for (int it = 0; it < 80; ++it) {
        if (f1 <= f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - g * (hi - lo), f1 = distance2(x1);
        } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + g * (hi - lo), f2 = distance2(x2);
        }
    }
    double t = 0.5 * (lo + hi);
    for (double end : {0.0, 1.0})
        if (distance2(end) < distance2(t)) t = end;
    const Eigen::Vector3d e = p1 - p0;
    Eigen::Vector3d n_local; // from the box towards the capsule
    double core;             // the segment's signed distance from the box
    const Eigen::Vector3d xs = p0 + t * e;
    const Eigen::Vector3d xb = xs.cwiseMax(-h).cwiseMin(h);
    const double d = (xs - xb).norm();
    if (d > 1e-12 * h.maxCoeff()) {
        n_local = (xs - xb) / d;
        core = d;
    } else {
        // The segment enters the box: the axis of least overlap among the box's faces and the
        // cross products of the segment with the box's edges.
        const Eigen::Vector3d c = 0.5 * (p0 + p1), half_e = 0.5 * e;
        core = -INFINITY;
        n_local = Eigen::Vector3d(0, 1, 0);
        for (int k = 0; k < 6; ++k) {
            Eigen::Vector3d l = Eigen::Vector3d::Zero();
            if (k < 3) {
                l(k) = 1;
            } else {
                l = half_e.cross(Eigen::Vector3d::Unit(k - 3));
                if (l.norm() < 1e-9 * half_e.norm()) continue;
                l.normalize();
            }
            const double s = std::abs(c.dot(l)) - h.dot(l.cwiseAbs()) - std::abs(half_e.dot(l));
            if (s > core + 1e-12) core = s, n_local = c.dot(l) >= 0 ? l : Eigen::Vector3d(-l);
        }
    }
    if (core - a.radius >= margin) return;
    // Lying along a face: the segment clipped against the face's sides, two points.
    int face = 0;
    for (int k = 1; k < 3; ++k)
        if (std::abs(n_local(k)) > std::abs(n_local(face))) face = k;
    const double sign = n_local(face) >= 0 ? 1 : -1;
    const double el = e.norm();
    if (std::abs(n_local(face)) > 1 - 1e-6 && el > 0 && std::abs(e(face)) < 1e-3 * el) {
        double t0 = 0, t1 = 1;
        for (int k = 0; k < 3 && t0 <= t1; ++k) {
            if (k == face) continue;
            // −h_k ≤ p0_k + t e_k ≤ h_k
            if (std::abs(e(k)) < 1e-15) {
                if (std::abs(p0(k)) > h(k)) t1 = -1;
                continue;
            }
            double ta = (-h(k) - p0(k)) / e(k), tb = (h(k) - p0(k)) / e(k);
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        }
        if (t0 <= t1) {
            Eigen::Vector3d nl = Eigen::Vector3d::Zero();
            nl(face) = sign;
            out.normal = r * nl;
            for (std::uint32_t i = 0; i < 2; ++i) {
                const Eigen::Vector3d x = p0 + (i == 0 ? t0 : t1) * e;
                const double above = sign * x(face) - h(face);
                if (above - a.radius >= margin) continue;
                Eigen::Vector3d on_face = x;
                on_face(face) = sign * h(face);
                ManifoldPoint& p = out.points[static_cast<std::size_t>(out.count++)];
                p.on_a = b.center + r * (x - a.radius * nl);
                p.on_b = b.center + r * on_face;
                p.separation = above - a.radius;
                p.feature = 8 + 2 * static_cast<std::uint32_t>(face) + i;
            }
            if (out.count > 0) return;
        }
    }
    out.normal = r * n_local;
    ManifoldPoint& p = out.points[0];
    p.on_a = b.center + r * (xs - a.radius * n_local);
    p.on_b = b.center + r * (d > 1e-12 * h.maxCoeff() ? xb : Eigen::Vector3d(xs - core * n_local));
    p.separation = core - a.radius;
    p.feature = 0;
    out.count = 1;
}

} // namespace phynjo::runtime
