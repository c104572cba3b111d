// Bounding volumes and broad phases: every broad phase returns exactly the brute-force pair
// set on random scenes; OBB separating axes against a sampling oracle.
#include "phynjo/runtime/runtime.hpp"

#include "property.hpp"

#include <array>
#include <random>
#include <set>

using namespace phynjo::runtime;

namespace {

std::vector<AABB> random_boxes(std::mt19937& rng, int n, double world, double max_size) {
    std::uniform_real_distribution<double> pos(-world, world), size(0, max_size);
    std::vector<AABB> boxes(static_cast<std::size_t>(n));
    for (auto& b : boxes) {
        b.lo = {pos(rng), pos(rng), pos(rng)};
        b.hi = b.lo + Eigen::Vector3d(size(rng), size(rng), size(rng));
    }
    return boxes;
}

} // namespace

TEST_CASE("AABB, sphere and mixed intersection tests", "[collision][volumes]") {
    const AABB a{{0, 0, 0}, {1, 1, 1}}, b{{1, 1, 1}, {2, 2, 2}}, c{{1.0001, 0, 0}, {2, 1, 1}};
    CHECK(intersects(a, b)); // touching at a corner counts
    CHECK_FALSE(intersects(a, c));
    CHECK(aabb_union(a, c).lo == Eigen::Vector3d(0, 0, 0));
    CHECK(aabb_union(a, c).hi == Eigen::Vector3d(2, 1, 1));
    const SphereBB s{{0, 0, 0}, 1}, t{{2, 0, 0}, 1}, u{{2.0001, 0, 0}, 1};
    CHECK(intersects(s, t));
    CHECK_FALSE(intersects(s, u));
    const AABB sb = aabb_from_sphere(SphereBB{{1, 2, 3}, 0.5});
    CHECK(sb.lo == Eigen::Vector3d(0.5, 1.5, 2.5));
    CHECK(sb.hi == Eigen::Vector3d(1.5, 2.5, 3.5));
    // A sphere near a box corner: the corner is √3·0.1 away, farther than 0.15 but within 0.2.
    CHECK_FALSE(intersects(a, SphereBB{{1.1, 1.1, 1.1}, 0.15}));
    CHECK(intersects(a, SphereBB{{1.1, 1.1, 1.1}, 0.2}));
    CHECK(a.contains({0.5, 0.5, 1}));
    CHECK_FALSE(a.contains({0.5, 0.5, 1.01}));
}

TEST_CASE("OBB separating axes agree with a sampling oracle", "[collision][volumes]") {
    // Oracles independent of the code under test: sampling each box densely (a grid of its
    // volume) finds intersections of non-negligible volume; a direction on which the corners'
    // projections are disjoint proves separation. Scenes are taken only when clearly separated
    // or clearly overlapping (margin 5% of the sizes). Catches a missing SAT axis (e.g. the
    // edge-edge cross products) or a wrong projection radius.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1), h(0.2, 1.0);
    std::normal_distribution<double> g;
    int overlapping = 0, separated = 0;
    for (int trial = 0; trial < 400; ++trial) {
        OBB a{{0, 0, 0}, {h(rng), h(rng), h(rng)}, Quaternion{g(rng), g(rng), g(rng), g(rng)}.normalized()};
        OBB b{{2 * u(rng), 2 * u(rng), 2 * u(rng)}, {h(rng), h(rng), h(rng)},
              Quaternion{g(rng), g(rng), g(rng), g(rng)}.normalized()};
        // Signed margin: shrink or grow b by 5% and require both to agree, else skip the scene.
        auto sample = [&](const OBB& x, const OBB& y) {
            const int k = 12;
            const Eigen::Matrix3d r = x.rotation.to_matrix();
            for (int i = 0; i <= k; ++i)
                for (int j = 0; j <= k; ++j)
                    for (int l = 0; l <= k; ++l) {
                        const Eigen::Vector3d local(x.half.x() * (2.0 * i / k - 1), x.half.y() * (2.0 * j / k - 1),
                                                    x.half.z() * (2.0 * l / k - 1));
                        if (y.contains(x.center + r * local)) return true;
                    }
            return false;
        };
        // Separation certificate independent of the SAT code: the corners of the two boxes
        // project to disjoint intervals on some direction of a dense set (4,000 directions
        // spread evenly over the sphere: a Fibonacci lattice).
        auto corners = [](const OBB& x) {
            std::array<Eigen::Vector3d, 8> c;
            const Eigen::Matrix3d r = x.rotation.to_matrix();
            for (int k = 0; k < 8; ++k)
                c[static_cast<std::size_t>(k)] =
                    x.center + r * Eigen::Vector3d(k & 1 ? x.half.x() : -x.half.x(), k & 2 ? x.half.y() : -x.half.y(),
                                                   k & 4 ? x.half.z() : -x.half.z());
            return c;
        };
        auto separated_on_some_direction = [&](const OBB& x, const OBB& y) {
            const auto cx = corners(x), cy = corners(y);
            const int m = 4000;
            for (int k = 0; k < m; ++k) {
                const double z = 1 - (2.0 * k + 1) / m, rho = std::sqrt(1 - z * z), phi = k * 2.399963229728653;
                const Eigen::Vector3d d(rho * std::cos(phi), rho * std::sin(phi), z);
                double lox = 1e300, hix = -1e300, loy = 1e300, hiy = -1e300;
                for (const auto& p : cx) lox = std::min(lox, p.dot(d)), hix = std::max(hix, p.dot(d));
                for (const auto& p : cy) loy = std::min(loy, p.dot(d)), hiy = std::max(hiy, p.dot(d));
                if (hix < loy || hiy < lox) return true;
            }
            return false;
        };
        OBB big = b, small = b;
        big.half *= 1.05;
        small.half *= 0.95;
        const bool sep_for_sure = separated_on_some_direction(a, big);
        const bool hit_for_sure = sample(a, small) || sample(small, a);
        if (hit_for_sure) {
            ++overlapping;
            CHECK(intersects(a, b));
            CHECK(intersects(b, a));
        } else if (sep_for_sure) {
            ++separated;
            CHECK_FALSE(intersects(a, b));
        }
        // The tight AABB of an OBB contains its corners.
        const AABB box = aabb_from_obb(b);
        const Eigen::Matrix3d r = b.rotation.to_matrix();
        for (int c = 0; c < 8; ++c) {
            const Eigen::Vector3d corner(c & 1 ? b.half.x() : -b.half.x(), c & 2 ? b.half.y() : -b.half.y(),
                                         c & 4 ? b.half.z() : -b.half.z());
            const Eigen::Vector3d p = b.center + r * corner;
            CHECK(((p.array() >= box.lo.array() - 1e-12).all() && (p.array() <= box.hi.array() + 1e-12).all()));
        }
    }
    INFO(overlapping << " overlapping, " << separated << " separated");
    CHECK(overlapping > 50);
    CHECK(separated > 50);
    // Edge on edge: A turned 45° about z puts an edge along z at x = +√2; B turned 45° about y
    // puts an edge along y at x = −√2 from its centre. Only the axis z × y = x separates them.
    const OBB ea{{0, 0, 0}, {1, 1, 1}, Quaternion::from_axis_angle({0, 0, 1}, M_PI / 4)};
    auto eb = [](double d) { return OBB{{d, 0, 0}, {1, 1, 1}, Quaternion::from_axis_angle({0, 1, 0}, M_PI / 4)}; };
    CHECK_FALSE(intersects(ea, eb(2 * std::sqrt(2.0) + 0.01)));
    CHECK_FALSE(intersects(eb(2 * std::sqrt(2.0) + 0.01), ea));
    CHECK(intersects(ea, eb(2 * std::sqrt(2.0) - 0.01)));
    CHECK(intersects(OBB{{0, 0, 0}, {1, 1, 1}, Quaternion::identity()}, SphereBB{{1.5, 0, 0}, 0.6}));
    CHECK_FALSE(intersects(OBB{{0, 0, 0}, {1, 1, 1}, Quaternion::identity()}, SphereBB{{1.5, 1.5, 0}, 0.6}));
}

TEST_CASE("every broad phase returns exactly the brute-force pair set", "[collision][broadphase]") {
    phynjo::test::check_property("grid == sap == brute force", [] {
        const int n = *rc::gen::inRange(0, 300);
        const int seed = *rc::gen::inRange(0, 1 << 30);
        const double world = *rc::gen::element(0.5, 2.0, 10.0, 1e6);
        const double size = *rc::gen::element(0.0, 0.01, 0.3, 1.0, 5.0);
        std::mt19937 rng(static_cast<unsigned>(seed));
        auto boxes = random_boxes(rng, n, world, size);
        if (*rc::gen::arbitrary<bool>() && n > 3) boxes[1] = boxes[0]; // identical boxes
        std::vector<CandidatePair> oracle, sap, grid, grid_small;
        brute_force_pairs(boxes, oracle);
        SweepAndPrune().find_pairs(boxes, sap);
        UniformGrid().find_pairs(boxes, grid);
        UniformGrid(1e-3).find_pairs(boxes, grid_small); // raised to the largest extent
        RC_ASSERT(sap == oracle);
        RC_ASSERT(grid == oracle);
        RC_ASSERT(grid_small == oracle);
    }, {.cases = 300});
}

TEST_CASE("the broad phases follow moving scenes: persistent sweep-and-prune order", "[collision][broadphase]") {
    std::mt19937 rng(5);
    auto boxes = random_boxes(rng, 500, 3.0, 0.3);
    std::normal_distribution<double> jitter(0, 0.05);
    CollisionManager sap(BroadPhase::sweep_and_prune, boxes), grid(BroadPhase::uniform_grid, boxes),
        brute(BroadPhase::brute_force, boxes);
    for (int step = 0; step < 60; ++step) {
        for (auto& b : boxes) {
            const Eigen::Vector3d d(jitter(rng), jitter(rng) + (step == 30 ? 3 : 0), jitter(rng)); // one big jump
            b.lo += d;
            b.hi += d;
        }
        sap.update(boxes);
        grid.update(boxes);
        brute.update(boxes);
        const auto expected = brute.run_broad_phase();
        REQUIRE(sap.run_broad_phase() == expected);
        REQUIRE(grid.run_broad_phase() == expected);
    }
}

TEST_CASE("broad phases reject non-finite and inverted boxes by index", "[collision][guards]") {
    std::vector<AABB> boxes{AABB{{0, 0, 0}, {1, 1, 1}}, AABB{{0, 0, 0}, {1, std::nan(""), 1}}};
    std::vector<CandidatePair> out;
    CHECK_THROWS_WITH(UniformGrid().find_pairs(boxes, out), "broad phase: box 1 is not finite");
    CHECK_THROWS_WITH(SweepAndPrune().find_pairs(boxes, out), "broad phase: box 1 is not finite");
    boxes[1] = AABB{{0, 2, 0}, {1, 1, 1}};
    CHECK_THROWS_WITH(brute_force_pairs(boxes, out), "broad phase: box 1 has lo > hi");
}

TEST_CASE("narrow phase: sphere pairs and planes with signed separations", "[collision][narrowphase]") {
    Registry r;
    for (const char* s : {"a", "b", "c"}) r.add(s);
    std::vector<RigidInit> init(3);
    init[0].position = {0, 0.09, 0};
    init[1].position = {0.19, 0.09, 0};
    init[2].position = {5, 5, 5};
    World w = make_rigid_world(r, std::vector<RigidBody>(3, RigidBody::solid_sphere(1, 0.1)), init);
    CollisionManager m(BroadPhase::uniform_grid);
    std::vector<SphereBB> s;
    for (Index i = 0; i < 3; ++i) s.push_back({position(w, i), 0.1});
    m.update(std::span<const SphereBB>(s));
    const std::vector<Index> ids{0, 1, 2};
    std::vector<Contact> cs;
    sphere_sphere_contacts(w, m.run_broad_phase(), ids, 0, cs);
    REQUIRE(cs.size() == 1);
    CHECK(cs[0].a == 0);
    CHECK(cs[0].b == 1);
    CHECK(cs[0].separation == Approx(-0.01));
    CHECK(cs[0].normal.isApprox(Eigen::Vector3d(-1, 0, 0)));
    cs.clear();
    const std::vector<Plane> planes{Plane::ground(), Plane{{-1, 0, 0}, -10}}; // wall x = 10, facing −x
    sphere_plane_contacts(w, ids, planes, 0, cs);
    REQUIRE(cs.size() == 2); // a and b on the ground; c far from both
    CHECK(cs[0].separation == Approx(-0.01));
    CHECK(max_penetration(w, all_bodies(w), planes) == Approx(0.01));
}
