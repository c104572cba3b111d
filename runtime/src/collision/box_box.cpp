// Box–box manifolds: separating axes, then the incident face clipped against the reference
// face (manifold.hpp). The point reduction is shared with box_plane (manifold_detail.hpp).
#include "manifold_detail.hpp"

#include <algorithm>
#include <cmath>

namespace phynjo::runtime {

namespace {

using manifold_detail::keep_four;

/// Clipping lines: the incident face's edges 0..3 and the reference face's sides 4..7; every
/// point of the clipped polygon lies where two of them meet, and that pair names it.
std::uint32_t line_pair(int l1, int l2) {
    const int lo = std::min(l1, l2), hi = std::max(l1, l2);
    return static_cast<std::uint32_t>(lo * 8 + hi);
}

struct ClipVertex {
    Eigen::Vector3d p;
    int out_line;      // the line the edge from this vertex to the next lies on
    std::uint32_t id;  // line_pair of the two lines meeting here
};

/// Sutherland–Hodgman against one side plane {p : u·(p − c) ≤ h}, named `line`.
int clip(const ClipVertex* in, int n, ClipVertex* out, const Eigen::Vector3d& u, const Eigen::Vector3d& c, double h,
         int line) {
    // Each vertex's distance once (it is the start of one edge and the end of another).
    double dist[8];
    for (int k = 0; k < n; ++k) dist[k] = u.dot(in[k].p - c) - h;
    int m = 0;
    for (int k = 0; k < n; ++k) {
        const int k1 = k + 1 == n ? 0 : k + 1;
        const ClipVertex& p = in[k];
        const ClipVertex& q = in[k1];
        const double dp = dist[k], dq = dist[k1];
        const bool pin = dp <= 0, qin = dq <= 0;
        if (pin) out[m++] = p;
        if (pin != qin) {
            const double t = dp / (dp - dq);
            const Eigen::Vector3d x = p.p + t * (q.p - p.p);
            // Leaving: the new edge runs along the side plane; entering: along p's edge.
            out[m++] = ClipVertex{x, pin ? line : p.out_line, line_pair(p.out_line, line)};
        }
    }
    return m;
}

struct Axis {
    double sep = -INFINITY;
    int index = -1;
};

} // namespace

void box_box(const OBB& a, const OBB& b, double margin, Manifold& out) {
    box_box(a, a.rotation.to_matrix(), b, b.rotation.to_matrix(), margin, out);
}

void box_box(const OBB& a, const Eigen::Matrix3d& ra, const OBB& b, const Eigen::Matrix3d& rb, double margin, Manifold& out) {
    out.count = 0;
    const Eigen::Vector3d& ha = a.half;
    const Eigen::Vector3d& hb = b.half;
    const Eigen::Vector3d d = b.center - a.center; // from a to b
    // c(i, j) = a_i · b_j, tₐ = Rₐᵀ d (d's coordinates along a's axes), each sum in index order.
    double c[3][3], ac[3][3], ta[3];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            c[i][j] = ra(0, i) * rb(0, j) + ra(1, i) * rb(1, j) + ra(2, i) * rb(2, j);
            ac[i][j] = std::abs(c[i][j]);
        }
        ta[i] = d(0) * ra(0, i) + d(1) * ra(1, i) + d(2) * ra(2, i);
    }

    // Face axes of a, then of b: separation |d·u| − r_a(u) − r_b(u).
    Axis fa, fb, edge;
    for (int i = 0; i < 3; ++i) {
        const double s = std::abs(ta[i]) - ha(i) - (hb(0) * ac[i][0] + hb(1) * ac[i][1] + hb(2) * ac[i][2]);
        if (s > fa.sep) fa = {s, i};
    }
    if (fa.sep > margin) return;
    for (int j = 0; j < 3; ++j) {
        const double s = std::abs(d(0) * rb(0, j) + d(1) * rb(1, j) + d(2) * rb(2, j)) - hb(j) -
                         (ha(0) * ac[0][j] + ha(1) * ac[1][j] + ha(2) * ac[2][j]);
        if (s > fb.sep) fb = {s, j};
    }
    if (fb.sep > margin) return;
    // Edge axes l = a_i × b_j, in a's frame through c and tₐ (Gottschalk, Lin & Manocha,
    // "OBBTree", 1996): |l| = √(1 − c_ij²), l·a_{i+1} = −c_{i+2,j}, l·a_{i+2} = c_{i+1,j},
    // l·b_{j+1} = c_{i,j+2}, l·b_{j+2} = −c_{i,j+1}, d·l = tₐ_{i+2} c_{i+1,j} − tₐ_{i+1} c_{i+2,j}.
    // The nine separations num/|l| at once (their roots and divisions independent of each
    // other: one chain, not nine), then the best in axis order — the same choice as dividing
    // only where num can win. A pair of parallel edges (|l| ≈ 0; 1 − c² may round below 0,
    // hence the floor under the root) is left out: the face axes cover it.
    static constexpr int kNext[3] = {1, 2, 0}, kAfter[3] = {2, 0, 1}; // (k + 1) % 3, (k + 2) % 3
    double num[9], len2[9], sep[9];
    for (int i = 0; i < 3; ++i) {
        const int i1 = kNext[i], i2 = kAfter[i];
        for (int j = 0; j < 3; ++j) {
            const int j1 = kNext[j], j2 = kAfter[j];
            len2[3 * i + j] = 1 - c[i][j] * c[i][j];
            const double r = ha(i1) * ac[i2][j] + ha(i2) * ac[i1][j] + hb(j1) * ac[i][j2] + hb(j2) * ac[i][j1];
            num[3 * i + j] = std::abs(ta[i2] * c[i1][j] - ta[i1] * c[i2][j]) - r;
        }
    }
    for (int k = 0; k < 9; ++k) sep[k] = num[k] / std::sqrt(std::max(len2[k], 1e-12));
    for (int k = 0; k < 9; ++k)
        if (!(len2[k] < 1e-12) && sep[k] > edge.sep) edge = {sep[k], k};
    if (edge.sep > margin) return;
    const Eigen::Vector3d edge_axis =
        edge.index >= 0 ? Eigen::Vector3d(ra.col(edge.index / 3).cross(rb.col(edge.index % 3)).normalized()) : Eigen::Vector3d::Zero();

    // Prefer a's faces to b's and faces to edges unless the other separates clearly more
    // (Gregorius 2015): resting boxes keep one reference face from step to step.
    const double tolerance = 2e-3 * std::min(ha.minCoeff(), hb.minCoeff());
    const bool ref_b = fb.sep > 0.98 * fa.sep + tolerance;
    const double face_sep = ref_b ? fb.sep : fa.sep;
    if (edge.index >= 0 && edge.sep > 0.9 * face_sep + tolerance) {
        // Edge–edge: the supporting edge of a along l (oriented from a to b) and of b along −l.
        const int i = edge.index / 3, j = edge.index % 3;
        const Eigen::Vector3d l = d.dot(edge_axis) < 0 ? Eigen::Vector3d(-edge_axis) : edge_axis;
        Eigen::Vector3d pa = a.center, pb = b.center;
        std::uint32_t ea = static_cast<std::uint32_t>(i), eb = static_cast<std::uint32_t>(j);
        for (int k = 0, bit = 2; k < 3; ++k) {
            if (k == i) continue;
            const bool plus = l.dot(ra.col(k)) > 0;
            pa += (plus ? ha(k) : -ha(k)) * ra.col(k);
            ea |= (plus ? 1u : 0u) << bit++;
        }
        for (int k = 0, bit = 2; k < 3; ++k) {
            if (k == j) continue;
            const bool plus = l.dot(rb.col(k)) < 0;
            pb += (plus ? hb(k) : -hb(k)) * rb.col(k);
            eb |= (plus ? 1u : 0u) << bit++;
        }
        // Closest points of the segments pa + s u, |s| ≤ ha_i, and pb + t v, |t| ≤ hb_j (unit u, v).
        const Eigen::Vector3d u = ra.col(i), v = rb.col(j), r = pa - pb;
        const double uv = u.dot(v), ur = u.dot(r), vr = v.dot(r);
        const double den = 1 - uv * uv;
        double s = den > 1e-12 ? std::clamp((uv * vr - ur) / den, -ha(i), ha(i)) : 0.0;
        double t = std::clamp(uv * s + vr, -hb(j), hb(j));
        s = std::clamp(uv * t - ur, -ha(i), ha(i));
        ManifoldPoint& p = out.points[0];
        p.on_a = pa + s * u;
        p.on_b = pb + t * v;
        out.normal = -l;
        p.separation = (p.on_a - p.on_b).dot(out.normal);
        p.feature = (1u << 13) | (eb << 4) | ea;
        out.count = 1;
        return;
    }

    // Face contact: the reference box R, its face `axis` facing the incident box I.
    const OBB& R = ref_b ? b : a;
    const OBB& I = ref_b ? a : b;
    const Eigen::Matrix3d& rr = ref_b ? rb : ra;
    const Eigen::Matrix3d& ri = ref_b ? ra : rb;
    const int axis = ref_b ? fb.index : fa.index;
    const Eigen::Vector3d towards = ref_b ? Eigen::Vector3d(-d) : d; // from R to I
    const bool ref_plus = towards.dot(rr.col(axis)) >= 0;
    const Eigen::Vector3d nref = ref_plus ? rr.col(axis) : Eigen::Vector3d(-rr.col(axis));
    // The incident face: the face of I whose outward normal is most anti-parallel to nref.
    int inc = 0;
    double best = -1;
    for (int k = 0; k < 3; ++k) {
        const double x = std::abs(nref.dot(ri.col(k)));
        if (x > best) best = x, inc = k;
    }
    const bool inc_plus = nref.dot(ri.col(inc)) < 0;
    const int iu = (inc + 1) % 3, iv = (inc + 2) % 3;
    const Eigen::Vector3d fc = I.center + (inc_plus ? I.half(inc) : -I.half(inc)) * ri.col(inc);
    const Eigen::Vector3d eu = I.half(iu) * ri.col(iu), ev = I.half(iv) * ri.col(iv);
    // Two buffers, clipped from one into the other (pointers swapped, not the 8 vertices);
    // left uninitialised, as `found` and `lines` below: each entry is written before it is
    // read, and zeroing them cost more than the clipping.
    std::array<ClipVertex, 8> buffer_a, buffer_b;
    ClipVertex* poly = buffer_a.data();
    ClipVertex* next = buffer_b.data();
    const Eigen::Vector3d corners[4] = {fc + eu + ev, fc - eu + ev, fc - eu - ev, fc + eu - ev};
    for (int k = 0; k < 4; ++k) poly[k] = {corners[k], k, line_pair((k + 3) % 4, k)};
    int n = 4;
    // The four side planes of the reference face.
    const int su = (axis + 1) % 3, sv = (axis + 2) % 3;
    const int sides[4] = {su, su, sv, sv};
    for (int k = 0; k < 4 && n > 0; ++k) {
        const Eigen::Vector3d u = (k % 2 == 0 ? 1.0 : -1.0) * rr.col(sides[k]);
        n = clip(poly, n, next, u, R.center, R.half(sides[k]), 4 + k);
        std::swap(poly, next);
    }
    const Eigen::Vector3d face_centre = R.center + R.half(axis) * nref;
    const std::uint32_t faces = (ref_b ? 1u << 12 : 0u) | static_cast<std::uint32_t>(2 * axis + (ref_plus ? 1 : 0)) << 9 |
                                static_cast<std::uint32_t>(2 * inc + (inc_plus ? 1 : 0)) << 6;
    // A point's id: the corner of the reference face and the vertex of the incident face
    // nearest to it (the quadrants it lies in), as Box2D pairs the vertices of its clipped
    // edges. It does not change when a point that was an incident vertex becomes a clipped
    // one or a reference corner: equal boxes stacked edge to edge flip between the three at
    // every jiggle, and their warm start must not. Two points in one pair of quadrants (rare:
    // a turned face) add the lines that meet there.
    std::array<ManifoldPoint, 8> found;
    std::array<std::uint32_t, 8> lines;
    int m = 0;
    for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d& x = poly[k].p;
        const double s = nref.dot(x - face_centre);
        if (s >= margin) continue;
        ManifoldPoint& p = found[static_cast<std::size_t>(m)];
        const Eigen::Vector3d on_ref = x - s * nref;
        p.on_a = ref_b ? x : on_ref;
        p.on_b = ref_b ? on_ref : x;
        p.separation = s;
        const std::uint32_t qr = (rr.col(su).dot(x - R.center) >= 0 ? 1u : 0u) | (rr.col(sv).dot(x - R.center) >= 0 ? 2u : 0u);
        const std::uint32_t qi = (ri.col(iu).dot(x - fc) >= 0 ? 1u : 0u) | (ri.col(iv).dot(x - fc) >= 0 ? 2u : 0u);
        p.feature = faces | qr << 2 | qi;
        lines[static_cast<std::size_t>(m)] = poly[k].id;
        ++m;
    }
    for (int k = 0; k < m; ++k)
        for (int j = 0; j < k; ++j)
            if ((found[static_cast<std::size_t>(j)].feature & 0x1fffu) == (found[static_cast<std::size_t>(k)].feature & 0x1fffu)) {
                found[static_cast<std::size_t>(k)].feature |= 1u << 20 | lines[static_cast<std::size_t>(k)] << 14;
                break;
            }
    out.normal = ref_b ? nref : Eigen::Vector3d(-nref);
    keep_four(found.data(), m, out);
}

} // namespace phynjo::runtime
