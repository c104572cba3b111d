// Collision shapes of rigid bodies: the inertia of solid boxes and capsules against a
// brute-force oracle (the density integrated over a grid of cells), the shape fields of a
// rigid world, and the refusal of shapes no body can have.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <string>

using namespace phynjo::runtime;

namespace {

/// The inertia tensor about the origin of mass `mass` spread evenly over {p : inside(p)} ⊂
/// [−e, e]³, by the midpoints of n³ cells (independent of every formula in rigid_body.cpp).
Eigen::Matrix3d grid_inertia(double mass, const Eigen::Vector3d& e, int n,
                             const std::function<bool(const Eigen::Vector3d&)>& inside) {
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    long count = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const Eigen::Vector3d p(e.x() * (2 * (i + 0.5) / n - 1), e.y() * (2 * (j + 0.5) / n - 1),
                                        e.z() * (2 * (k + 0.5) / n - 1));
                if (!inside(p)) continue;
                ++count;
                sum += p.squaredNorm() * Eigen::Matrix3d::Identity() - p * p.transpose();
            }
    return sum * (mass / static_cast<double>(count));
}

} // namespace

// Catches: a box or capsule inertia formula wrong in any moment (a cap's parallel-axis term
// dropped, the axis of the capsule put along x, the cylinder's L²/3 written as L²/12).
TEST_CASE("solid boxes and capsules have the inertia of their density on a grid", "[rigid][shapes]") {
    const Eigen::Vector3d h(0.3, 0.1, 0.2);
    const RigidBody box = RigidBody::solid_box(2.5, h);
    const Eigen::Matrix3d box_grid =
        grid_inertia(2.5, h, 120, [](const Eigen::Vector3d&) { return true; });
    CHECK((box.inertia - box_grid).cwiseAbs().maxCoeff() < 1e-3 * box.inertia.maxCoeff());
    CHECK(box.shape == Shape::box);
    CHECK(box.half_extents == h);
    CHECK(box.radius == 0);

    for (const auto& [r, l] : {std::pair{0.2, 0.5}, std::pair{0.3, 0.05}, std::pair{0.1, 0.0}}) {
        const RigidBody cap = RigidBody::solid_capsule(3, r, l);
        const Eigen::Matrix3d grid =
            grid_inertia(3, Eigen::Vector3d(r, l + r, r), 160, [r = r, l = l](const Eigen::Vector3d& p) {
                const double y = std::clamp(p.y(), -l, l);
                return p.x() * p.x() + (p.y() - y) * (p.y() - y) + p.z() * p.z() <= r * r;
            });
        INFO("capsule r = " << r << ", L = " << l << "\nformula\n" << cap.inertia << "\ngrid\n" << grid);
        CHECK((cap.inertia - grid).cwiseAbs().maxCoeff() < 5e-3 * cap.inertia.maxCoeff());
        CHECK(cap.shape == Shape::capsule);
        CHECK(cap.half_extents == Eigen::Vector3d(0, l, 0));
        CHECK(cap.radius == r);
    }
    // L = 0 is a sphere: (2/5) m r².
    const RigidBody ball = RigidBody::solid_capsule(3, 0.1, 0);
    CHECK(std::abs(ball.inertia(0, 0) - 0.4 * 3 * 0.01) < 1e-15);
    CHECK(std::abs(ball.inertia(1, 1) - 0.4 * 3 * 0.01) < 1e-15);
}

// Catches: shape fields added to worlds of spheres (their layouts, hashes and archives would
// change), a shape or half-extent stored in the wrong field.
TEST_CASE("a rigid world holds shape fields only when a body is not a sphere", "[rigid][shapes]") {
    Registry r;
    r.add("ball");
    r.add("crate");
    r.add("rod");
    const World spheres = make_rigid_world(r, std::vector<RigidBody>(3, RigidBody::solid_sphere(1, 0.1)));
    CHECK(spheres.field_count() == kRigidFieldCount);
    CHECK(shape_field(spheres.layout()) == -1);
    CHECK(shape_of(spheres, 1) == Shape::sphere);
    CHECK(half_extents(spheres, 1).isZero(0));

    const World w = make_rigid_world(
        r, {RigidBody::solid_sphere(1, 0.1), RigidBody::solid_box(2, {0.1, 0.2, 0.3}), RigidBody::solid_capsule(1, 0.05, 0.4)},
        {}, contact_cache_fields(4));
    CHECK(shape_field(w.layout()) == static_cast<int>(kRigidFieldCount));
    CHECK(w.layout().fields[kRigidFieldCount + 4] == "wc_partner#0");
    CHECK(shape_of(w, 0) == Shape::sphere);
    CHECK(shape_of(w, 1) == Shape::box);
    CHECK(shape_of(w, 2) == Shape::capsule);
    CHECK(half_extents(w, 1) == Eigen::Vector3d(0.1, 0.2, 0.3));
    CHECK(half_extents(w, 2) == Eigen::Vector3d(0, 0.4, 0));
    CHECK(w.at(kRadius, 1) == 0);
    CHECK(w.at(kRadius, 2) == 0.05);
}

// Catches: a box with a zero or negative half-extent, or a capsule without radius, accepted
// (a shape that collides with nothing, or a NaN in the narrow phase).
TEST_CASE("shapes no body can have are refused, naming the body", "[rigid][shapes][guards]") {
    Registry r;
    r.add("crate");
    auto fails = [&](const RigidBody& b, const std::string& what) {
        try {
            (void)make_rigid_world(r, {b});
            FAIL("accepted: " << what);
        } catch (const InvalidBody& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find(what) != std::string::npos);
            CHECK(std::string(e.what()).find("'crate'") != std::string::npos);
        }
    };
    RigidBody b = RigidBody::solid_box(1, {0.1, 0.2, 0.3});
    b.half_extents.y() = 0;
    fails(b, "half-extents of box");
    b.half_extents.y() = std::nan("");
    fails(b, "half-extents of box");
    b = RigidBody::solid_box(1, {0.1, 0.2, 0.3});
    b.radius = 0.1;
    fails(b, "has a radius");
    b = RigidBody::solid_capsule(1, 0.1, 0.2);
    b.radius = 0;
    fails(b, "radius of capsule");
    b = RigidBody::solid_capsule(1, 0.1, 0.2);
    b.half_extents = {0.1, 0.2, 0};
    fails(b, "half-length");
    b = RigidBody::solid_sphere(1, 0.1);
    b.half_extents = {0.1, 0, 0};
    fails(b, "its shape is a sphere");
}
