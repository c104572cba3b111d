// Contact manifolds (runtime/include/phynjo/runtime/collision/manifold.hpp): box–box on
// random poses against a brute-force oracle of the separation (every direction sampled,
// then refined), box–plane against all eight vertices, sphere–box against points sampled on
// the box's surface, and the feature ids that warm starting relies on.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

using namespace phynjo::runtime;

namespace {

Quaternion random_rotation(std::mt19937& rng) {
    std::normal_distribution<double> g;
    return Quaternion{g(rng), g(rng), g(rng), g(rng)}.normalized();
}

/// The gap between two boxes along the unit u (from a towards b): (c_b − c_a)·u − r_a(u) −
/// r_b(u), r(u) = h·|Rᵀu| the support radius of a box. In plain doubles: the oracle calls it
/// 10⁹ times, and Eigen's expression templates are slow in the sanitizer build.
struct Gap {
    double ra[3][3], rb[3][3]; // Rᵀ of each box
    double ha[3], hb[3], d[3];
    Gap(const OBB& a, const OBB& b) {
        const Eigen::Matrix3d rat = a.rotation.to_matrix().transpose(), rbt = b.rotation.to_matrix().transpose();
        for (int i = 0; i < 3; ++i) {
            d[i] = b.center[i] - a.center[i];
            ha[i] = a.half[i];
            hb[i] = b.half[i];
            for (int j = 0; j < 3; ++j) ra[i][j] = rat(i, j), rb[i][j] = rbt(i, j);
        }
    }
    /// r_a(u) + r_b(u).
    double support(const double* u) const {
        double s = 0;
        for (int i = 0; i < 3; ++i) {
            s += ha[i] * std::abs(ra[i][0] * u[0] + ra[i][1] * u[1] + ra[i][2] * u[2]);
            s += hb[i] * std::abs(rb[i][0] * u[0] + rb[i][1] * u[1] + rb[i][2] * u[2]);
        }
        return s;
    }
    double along(const double* u) const { return d[0] * u[0] + d[1] * u[1] + d[2] * u[2]; }
    double operator()(const Eigen::Vector3d& u) const { return along(u.data()) - support(u.data()); }
    /// max(gap(u), gap(−u)) = |d·u| − r_a(u) − r_b(u): the support radii are even in u.
    double either_way(const double* u) const { return std::abs(along(u)) - support(u); }
};

double gap(const OBB& a, const OBB& b, const Eigen::Vector3d& u) { return Gap(a, b)(u); }

/// max over unit u of the gap: the distance of separated convex bodies, minus the depth of
/// penetrating ones, by brute force over the 64 differences q_j = (vertex of b) − (vertex of
/// a), in whose terms the gap is min_j q_j·u. Penetrating, the maximum lies along the normal
/// of a face of their hull, a plane through three of them; apart, towards the point of the
/// hull nearest the origin, on a face (again a plane through three), an edge (the segment of
/// two) or at one q_j. Every direction of those is tried: 64 + 2,016 + 41,664 of them. (No
/// separating-axis reasoning: any plane through three differences, not only face normals and
/// edge cross products.)
double oracle_separation(const OBB& a, const OBB& b) {
    const Gap gap_of(a, b);
    const Eigen::Matrix3d ra = a.rotation.to_matrix(), rb = b.rotation.to_matrix();
    auto corner = [](const OBB& x, const Eigen::Matrix3d& r, int v) {
        return Eigen::Vector3d(x.center + r * Eigen::Vector3d(v & 1 ? x.half.x() : -x.half.x(), v & 2 ? x.half.y() : -x.half.y(),
                                                              v & 4 ? x.half.z() : -x.half.z()));
    };
    std::array<Eigen::Vector3d, 64> q;
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 8; ++k) q[static_cast<std::size_t>(8 * i + k)] = corner(b, rb, k) - corner(a, ra, i);
    double top = -INFINITY;
    auto tryu = [&](const Eigen::Vector3d& v) {
        const double l = v.norm();
        if (!(l > 1e-12)) return;
        const Eigen::Vector3d u = v / l;
        top = std::max(top, gap_of.either_way(u.data()));
    };
    for (std::size_t i = 0; i < q.size(); ++i) {
        tryu(q[i]);
        for (std::size_t j = i + 1; j < q.size(); ++j) {
            const Eigen::Vector3d e = q[j] - q[i];
            const double t = std::clamp(-q[i].dot(e) / e.squaredNorm(), 0.0, 1.0);
            tryu(q[i] + t * e);
            for (std::size_t k = j + 1; k < q.size(); ++k) tryu(e.cross(q[k] - q[i]));
        }
    }
    return top;
}

/// ‖Rᵀ(p − c) ⊘ h‖∞: 1 on the box's surface.
double box_norm(const OBB& b, const Eigen::Vector3d& p) {
    return (b.rotation.to_matrix().transpose() * (p - b.center)).cwiseQuotient(b.half).cwiseAbs().maxCoeff();
}

OBB box(const Eigen::Vector3d& c, const Eigen::Vector3d& h, const Quaternion& q = Quaternion::identity()) {
    OBB b;
    b.center = c;
    b.half = h;
    b.rotation = q;
    return b;
}

/// The points' feature ids, sorted (warm starting finds a point by its id, whatever its place).
std::vector<std::uint32_t> features(const Manifold& m) {
    std::vector<std::uint32_t> f;
    for (int k = 0; k < m.count; ++k) f.push_back(m.points[static_cast<std::size_t>(k)].feature);
    std::sort(f.begin(), f.end());
    return f;
}

} // namespace

// Catches: a separating axis missing (an edge cross product, a face of b), the reference face
// on the wrong side, clipped points off the surfaces, a depth measured from the wrong face,
// a normal pointing from a to b, contacts lost between penetrating boxes.
TEST_CASE("box-box manifolds agree with a brute-force separation oracle on 10,000 random poses", "[collision][manifold]") {
    std::mt19937 rng(20261204);
    std::uniform_real_distribution<double> size(0.05, 0.5), offset(-0.8, 0.8);
    const double margin = 0.01;
    int penetrating = 0, exact = 0, separated = 0, faces = 0, edges = 0;
    double worst_excess = 0;
    for (int trial = 0; trial < 10000; ++trial) {
        const OBB a = box({0, 0, 0}, {size(rng), size(rng), size(rng)}, random_rotation(rng));
        const OBB b = box({offset(rng), offset(rng), offset(rng)}, {size(rng), size(rng), size(rng)}, random_rotation(rng));
        const double truth = oracle_separation(a, b);
        Manifold m;
        box_box(a, b, margin, m);
        INFO("trial " << trial << ": oracle separation " << truth << ", " << m.count << " points");
        if (m.count == 0) {
            // No contact only when the boxes are farther apart than the margin.
            CHECK(truth > margin - 1e-9);
            ++separated;
            continue;
        }
        REQUIRE(std::abs(m.normal.norm() - 1) < 1e-12);
        const Eigen::Vector3d u = -m.normal; // from a towards b
        const double along = gap(a, b, u);
        // No direction separates more than the truth; the chosen one within the tolerance that
        // prefers faces: a face is kept unless an edge separates by more than 0.9 of it plus
        // 2e-3 of the smallest half-extent, so its depth is at most |truth|/0.9 plus that/0.9.
        CHECK(along <= truth + 1e-9);
        if (truth < 0) {
            ++penetrating;
            const double allowed =
                (1 / 0.9 - 1) * -truth + 2e-3 / 0.9 * std::min(a.half.minCoeff(), b.half.minCoeff()) + 1e-9;
            CHECK(along >= truth - allowed);
            worst_excess = std::max(worst_excess, (truth - along) / -truth);
            if (along >= truth - 1e-7) ++exact;
        }
        for (int k = 0; k < m.count; ++k) {
            const ManifoldPoint& p = m.points[static_cast<std::size_t>(k)];
            CHECK(std::abs(p.separation - (p.on_a - p.on_b).dot(m.normal)) < 1e-12);
            CHECK(p.separation < margin);
            CHECK(p.separation >= along - 1e-9); // no point deeper than the boxes overlap along n
            CHECK(std::abs(box_norm(a, p.on_a) - 1) < 1e-9);
            CHECK(std::abs(box_norm(b, p.on_b) - 1) < 1e-9);
        }
        std::set<std::uint32_t> ids;
        for (auto f : features(m)) ids.insert(f);
        CHECK(static_cast<int>(ids.size()) == m.count); // every point its own feature
        (m.points[0].feature >> 13 & 1u ? edges : faces) += 1;
    }
    INFO(penetrating << " penetrating poses, " << exact << " with the oracle's depth to 1e-7; " << separated
                     << " apart; " << faces << " face and " << edges << " edge manifolds; worst relative excess "
                     << worst_excess);
    CHECK(penetrating > 3000);
    CHECK(separated > 1000);
    CHECK(edges > 100);
    CHECK(exact > 0.7 * penetrating); // 77 % when measured: the face preference gives up the rest
}

// Catches: a clipped point dropped or a side plane clipping the wrong half, the reduction
// keeping three points of a square, feature ids that change while nothing moves or as equal
// stacked boxes jiggle (named after the lines that happen to meet at a point).
TEST_CASE("a box resting on a box: four points at its corners, the same features as it jiggles", "[collision][manifold]") {
    const OBB ground = box({0, -0.5, 0}, {2, 0.5, 2});
    const double depth = 1e-4;
    const OBB crate = box({0.3, 0.25 - depth, -0.2}, {0.4, 0.25, 0.3});
    Manifold m;
    box_box(crate, ground, 0.01, m);
    REQUIRE(m.count == 4);
    CHECK((m.normal - Eigen::Vector3d(0, 1, 0)).norm() < 1e-12);
    std::set<std::pair<double, double>> corners;
    for (int k = 0; k < 4; ++k) {
        const ManifoldPoint& p = m.points[static_cast<std::size_t>(k)];
        CHECK(std::abs(p.separation + depth) < 1e-12);
        corners.insert({std::round(p.on_a.x() * 1e9) / 1e9, std::round(p.on_a.z() * 1e9) / 1e9});
    }
    CHECK(corners == std::set<std::pair<double, double>>{{-0.1, -0.5}, {-0.1, 0.1}, {0.7, -0.5}, {0.7, 0.1}});
    const auto ids = features(m);
    // Nudged by 1e-4 rad and 10 µm: the same features.
    const OBB nudged = box({0.30001, 0.25 - depth, -0.2}, {0.4, 0.25, 0.3},
                           Quaternion::from_axis_angle(Eigen::Vector3d(1, 2, 3).normalized(), 1e-4));
    Manifold n;
    box_box(nudged, ground, 0.01, n);
    INFO("features " << ::Catch::Detail::stringify(ids));
    CHECK(features(n) == ids);
    // Equal boxes stacked edge to edge: every point is at once an incident vertex, a clipped
    // point and a reference corner, and a micrometre decides which; its id must not change.
    const OBB lower = box({0, 0.25, 0}, {0.25, 0.25, 0.25});
    Manifold stacked;
    box_box(box({0, 0.75 - depth, 0}, {0.25, 0.25, 0.25}), lower, 0.01, stacked);
    REQUIRE(stacked.count == 4);
    for (const Eigen::Vector3d& jiggle : {Eigen::Vector3d(1e-6, 0, 0), Eigen::Vector3d(-1e-6, 0, 1e-6),
                                          Eigen::Vector3d(0, 0, -1e-6), Eigen::Vector3d(1e-6, 0, -1e-6)}) {
        Manifold j;
        box_box(box(Eigen::Vector3d(0, 0.75 - depth, 0) + jiggle, {0.25, 0.25, 0.25}), lower, 0.01, j);
        INFO("jiggled by " << jiggle.transpose());
        REQUIRE(j.count == 4);
        CHECK(features(j) == features(stacked));
    }
    // Seen from the ground: the same contact, the normal reversed.
    Manifold g;
    box_box(ground, crate, 0.01, g);
    REQUIRE(g.count == 4);
    CHECK((g.normal + m.normal).norm() < 1e-12);
    // A crate turned 45° on an equal box: the clipped octagon reduced to 4 points spanning at
    // least half its area (a square inscribed in a regular octagon spans 1/√2 of it).
    const OBB base = box({0, -0.25, 0}, {0.25, 0.25, 0.25});
    const OBB turned = box({0, 0.25 - depth, 0}, {0.25, 0.25, 0.25},
                           Quaternion::from_axis_angle(Eigen::Vector3d(0, 1, 0), std::acos(-1.0) / 4));
    Manifold o;
    box_box(turned, base, 0.01, o);
    REQUIRE(o.count == 4);
    std::vector<Eigen::Vector2d> q;
    for (int k = 0; k < 4; ++k) q.emplace_back(o.points[static_cast<std::size_t>(k)].on_a.x(), o.points[static_cast<std::size_t>(k)].on_a.z());
    std::sort(q.begin(), q.end(), [](const auto& x, const auto& y) { return std::atan2(x.y(), x.x()) < std::atan2(y.y(), y.x()); });
    double area = 0;
    for (int k = 0; k < 4; ++k) {
        const auto& p = q[static_cast<std::size_t>(k)];
        const auto& r = q[static_cast<std::size_t>((k + 1) % 4)];
        area += 0.5 * (p.x() * r.y() - r.x() * p.y());
    }
    const double octagon = 8 * 0.25 * 0.25 * std::tan(std::acos(-1.0) / 8); // inradius 0.25
    INFO("quad area " << area << ", octagon " << octagon);
    CHECK(area >= 0.7 * octagon);
}

// Catches: edge–edge contacts taken as faces (a point floating off the surface) or a swapped
// edge id.
TEST_CASE("crossed edges meet in one point at the edges' closest points", "[collision][manifold]") {
    const double pi = std::acos(-1.0);
    // A cube on an edge along x, resting across a cube on an edge along z: the edges cross.
    const OBB lower = box({0, 0, 0}, {0.5, 0.5, 0.5}, Quaternion::from_axis_angle({0, 0, 1}, pi / 4));
    const double reach = 0.5 * std::sqrt(2.0);
    const OBB upper = box({0.01, 2 * reach - 1e-3, 0.02}, {0.5, 0.5, 0.5}, Quaternion::from_axis_angle({1, 0, 0}, pi / 4));
    Manifold m;
    box_box(upper, lower, 0.01, m);
    REQUIRE(m.count == 1);
    const ManifoldPoint& p = m.points[0];
    CHECK(p.feature >> 13 == 1u);
    CHECK((m.normal - Eigen::Vector3d(0, 1, 0)).norm() < 1e-9);
    CHECK(std::abs(p.separation + 1e-3) < 1e-9);
    CHECK((p.on_b - Eigen::Vector3d(0, reach, 0.02)).norm() < 1e-9);
    CHECK((p.on_a - Eigen::Vector3d(0, reach - 1e-3, 0.02)).norm() < 1e-9);
}

// Catches: a vertex below the plane missed, one above kept, a vertex's feature id reused; the
// early exit for a box clear of the plane taking the box's extent along the normal in the
// wrong frame (R n for Rᵀ n) or leaving it out — boxes near the plane then lose their corners.
TEST_CASE("box-plane manifolds hold exactly the vertices below the margin", "[collision][manifold]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> size(0.05, 0.5), height(-0.3, 0.8);
    Plane tilted;
    tilted.normal = Eigen::Vector3d(0.1, 1, -0.2).normalized();
    tilted.offset = 0.05;
    int cut = 0, clear = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const OBB a = box({0.2, height(rng), -0.1}, {size(rng), size(rng), size(rng)}, random_rotation(rng));
        Manifold m;
        box_plane(a, tilted, 0.01, m);
        std::vector<std::pair<double, std::uint32_t>> below;
        const Eigen::Matrix3d r = a.rotation.to_matrix();
        for (int sx = -1; sx <= 1; sx += 2)
            for (int sy = -1; sy <= 1; sy += 2)
                for (int sz = -1; sz <= 1; sz += 2) {
                    const Eigen::Vector3d v = a.center + r * Eigen::Vector3d(sx * a.half.x(), sy * a.half.y(), sz * a.half.z());
                    const double s = tilted.normal.dot(v) - tilted.offset;
                    if (s < 0.01) below.emplace_back(s, (sx > 0 ? 1u : 0u) | (sy > 0 ? 2u : 0u) | (sz > 0 ? 4u : 0u));
                }
        INFO("trial " << trial);
        CHECK(m.count == std::min<int>(4, static_cast<int>(below.size())));
        if (below.size() > 4) ++cut;
        if (below.empty()) ++clear;
        std::set<std::uint32_t> seen;
        double deepest = INFINITY;
        for (auto& [s, id] : below) deepest = std::min(deepest, s);
        double kept_deepest = INFINITY;
        for (int k = 0; k < m.count; ++k) {
            const ManifoldPoint& p = m.points[static_cast<std::size_t>(k)];
            const auto it = std::find_if(below.begin(), below.end(), [&](const auto& x) { return x.second == p.feature; });
            REQUIRE(it != below.end());
            CHECK(std::abs(p.separation - it->first) < 1e-12);
            CHECK(std::abs(tilted.normal.dot(p.on_b) - tilted.offset) < 1e-12);
            seen.insert(p.feature);
            kept_deepest = std::min(kept_deepest, p.separation);
        }
        CHECK(static_cast<int>(seen.size()) == m.count);
        if (m.count > 0) CHECK(kept_deepest == deepest);
    }
    CHECK(cut > 10);    // deep poses with 5 or more vertices below, reduced to the deepest and 3 others
    CHECK(clear > 100); // and boxes clear of the plane (the early exit)
}

// Catches: the sphere's centre inside the box pushed out through the wrong face, an edge or
// corner region's normal not along the closest point, the sign of the separation.
TEST_CASE("sphere-box separations agree with points sampled on the box's surface", "[collision][manifold]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> size(0.1, 0.5), pos(-0.7, 0.7), rad(0.02, 0.3);
    const int n = 40; // samples per face edge
    for (int trial = 0; trial < 500; ++trial) {
        const OBB b = box({0.1, -0.2, 0.3}, {size(rng), size(rng), size(rng)}, random_rotation(rng));
        const SphereBB s{b.center + Eigen::Vector3d(pos(rng), pos(rng), pos(rng)), rad(rng)};
        Manifold m;
        sphere_box(s, b, 1.0, m);
        REQUIRE(m.count == 1);
        const Eigen::Matrix3d r = b.rotation.to_matrix();
        double nearest = INFINITY;
        Eigen::Vector3d at = Eigen::Vector3d::Zero();
        for (int axis = 0; axis < 3; ++axis)
            for (int side = -1; side <= 1; side += 2)
                for (int i = 0; i <= n; ++i)
                    for (int j = 0; j <= n; ++j) {
                        Eigen::Vector3d l;
                        l(axis) = side * b.half(axis);
                        l((axis + 1) % 3) = b.half((axis + 1) % 3) * (2.0 * i / n - 1);
                        l((axis + 2) % 3) = b.half((axis + 2) % 3) * (2.0 * j / n - 1);
                        const Eigen::Vector3d x = b.center + r * l;
                        const double d = (x - s.center).norm();
                        if (d < nearest) nearest = d, at = x;
                    }
        const bool inside = box_norm(b, s.center) < 1;
        const double expected = (inside ? -nearest : nearest) - s.radius;
        const double cell = 2 * b.half.maxCoeff() / n;
        const ManifoldPoint& p = m.points[0];
        INFO("trial " << trial << ": separation " << p.separation << ", sampled " << expected);
        // The sampled points lie on the surface, and come within a cell of the closest point:
        // outside, no farther than the nearest sample, inside, no nearer to the surface.
        if (inside) {
            CHECK(p.separation >= expected - 1e-12);
            CHECK(p.separation <= expected + cell);
        } else {
            CHECK(p.separation <= expected + 1e-12);
            CHECK(p.separation >= expected - cell);
        }
        CHECK(std::abs(box_norm(b, p.on_b) - 1) < 1e-9);
        CHECK(std::abs((p.on_a - s.center).norm() - s.radius) < 1e-12);
        CHECK(std::abs(p.separation - (p.on_a - p.on_b).dot(m.normal)) < 1e-12);
        if (!inside && nearest > 5 * cell) CHECK(m.normal.dot((s.center - at).normalized()) > 0.99);
    }
}

// Catches: the closest points of two segments wrong at their ends (a capsule's cap missed),
// parallel capsules resting on one point (they rock), a normal from a to b.
TEST_CASE("capsule manifolds agree with sampled distances between their segments and shapes", "[collision][manifold][capsules]") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> pos(-0.6, 0.6), rad(0.02, 0.2), len(0.0, 0.5);
    auto random_capsule = [&](const Eigen::Vector3d& c) {
        const Eigen::Vector3d e = random_rotation(rng).rotate(Eigen::Vector3d(0, len(rng), 0));
        return Capsule{c - e, c + e, rad(rng)};
    };
    const int n = 400; // samples along a segment
    auto point = [](const Capsule& c, int i, int k) { return Eigen::Vector3d(c.p0 + (c.p1 - c.p0) * (static_cast<double>(i) / k)); };
    for (int trial = 0; trial < 300; ++trial) {
        INFO("trial " << trial);
        // capsule–capsule
        const Capsule a = random_capsule({0, 0, 0}), b = random_capsule({pos(rng), pos(rng), pos(rng)});
        double nearest = INFINITY;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n; j += 1) nearest = std::min(nearest, (point(a, i, n) - point(b, j, n)).norm());
        const double cell = ((a.p1 - a.p0).norm() + (b.p1 - b.p0).norm()) / n;
        Manifold m;
        capsule_capsule(a, b, 10.0, m);
        REQUIRE(m.count >= 1);
        const double s = m.points[0].separation;
        const double expected = nearest - a.radius - b.radius;
        CHECK(s <= expected + 1e-12);
        CHECK(s >= expected - cell);
        for (int k = 0; k < m.count; ++k) {
            const ManifoldPoint& p = m.points[static_cast<std::size_t>(k)];
            CHECK(std::abs(p.separation - (p.on_a - p.on_b).dot(m.normal)) < 1e-12);
        }
        // capsule–box: the distance of the segment's points from the box, each by clamping
        const OBB box_b = box({pos(rng), pos(rng), pos(rng)}, {0.1 + 0.3 * std::abs(pos(rng)), 0.1 + 0.3 * std::abs(pos(rng)), 0.1 + 0.3 * std::abs(pos(rng))},
                              random_rotation(rng));
        double to_box = INFINITY;
        const Eigen::Matrix3d r = box_b.rotation.to_matrix();
        for (int i = 0; i <= n; ++i) {
            const Eigen::Vector3d l = r.transpose() * (point(a, i, n) - box_b.center);
            to_box = std::min(to_box, (l - l.cwiseMax(-box_b.half).cwiseMin(box_b.half)).norm());
        }
        Manifold mb;
        capsule_box(a, box_b, 10.0, mb);
        REQUIRE(mb.count >= 1);
        if (to_box > 0) { // apart at the core: the distance, within a sample's spacing
            double least = INFINITY;
            for (int k = 0; k < mb.count; ++k) least = std::min(least, mb.points[static_cast<std::size_t>(k)].separation);
            CHECK(least <= to_box - a.radius + 1e-9);
            CHECK(least >= to_box - a.radius - (a.p1 - a.p0).norm() / n);
        } else { // the segment enters the box: deeper than the radius
            CHECK(mb.points[0].separation < -a.radius + 1e-9);
        }
        for (int k = 0; k < mb.count; ++k) {
            const ManifoldPoint& p = mb.points[static_cast<std::size_t>(k)];
            CHECK(std::abs(p.separation - (p.on_a - p.on_b).dot(mb.normal)) < 1e-12);
        }
    }
    // Parallel capsules side by side rest on a line: two points, at the ends of the overlap.
    Manifold par;
    capsule_capsule(Capsule{{-0.5, 0.1, 0}, {0.5, 0.1, 0}, 0.05}, Capsule{{-0.2, 0, 0}, {0.9, 0, 0}, 0.05}, 0.01, par);
    REQUIRE(par.count == 2);
    CHECK((par.normal - Eigen::Vector3d(0, 1, 0)).norm() < 1e-12);
    CHECK(std::abs(par.points[0].on_a.x() + 0.2) < 1e-12);
    CHECK(std::abs(par.points[1].on_a.x() - 0.5) < 1e-12);
    // A capsule lying on a box's face: two points, its ends clipped to the face.
    Manifold lying;
    capsule_box(Capsule{{-0.8, 0.55, 0.1}, {0.3, 0.55, 0.1}, 0.05}, box({0, 0, 0}, {0.5, 0.5, 0.5}), 0.01, lying);
    REQUIRE(lying.count == 2);
    CHECK((lying.normal - Eigen::Vector3d(0, 1, 0)).norm() < 1e-12);
    CHECK(std::abs(lying.points[0].separation) < 1e-12);
    CHECK(std::abs(lying.points[0].on_b.x() + 0.5) < 1e-12);
    CHECK(std::abs(lying.points[1].on_b.x() - 0.3) < 1e-12);
}
