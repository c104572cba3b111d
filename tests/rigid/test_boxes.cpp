// Boxes and capsules in contact (the solver over manifolds, contact_solver.hpp): a box at
// rest, towers and a pyramid with nothing put to sleep, a heavy box on light ones, friction
// on an incline against Coulomb's law, tipping over an edge at the angle statics gives, a
// capsule rolling down an incline at the acceleration of a rolling body, and head-on
// impacts against the restitution law.
#include "phynjo/runtime/runtime.hpp"

#include "scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <tuple>
#include <vector>

using namespace phynjo::runtime;

namespace {

constexpr double g = 9.81;
const double pi = std::acos(-1.0);

struct Scene {
    World w;
    std::vector<Plane> planes;
};

World boxes(const std::vector<RigidBody>& bodies, const std::vector<RigidInit>& init, int slots = 32) {
    Registry reg;
    for (std::size_t i = 0; i < bodies.size(); ++i) reg.add("b" + std::to_string(i));
    return make_rigid_world(reg, bodies, init, contact_cache_fields(slots));
}

RigidInit at(const Eigen::Vector3d& p, const Quaternion& q = Quaternion::identity()) {
    RigidInit s;
    s.position = p;
    s.orientation = q;
    return s;
}

/// The largest distance of a body from where it started, m, and the largest turn, rad.
std::pair<double, double> moved(const World& w, const std::vector<RigidInit>& init) {
    double far = 0, turn = 0;
    for (Index i = 0; i < w.size(); ++i) {
        far = std::max(far, (position(w, i) - init[i].position).norm());
        const Quaternion d = orientation(w, i) * init[i].orientation.conjugate();
        turn = std::max(turn, 2 * std::acos(std::min(1.0, std::abs(d.w))));
    }
    return {far, turn};
}

/// The deepest overlap of any two bodies or a body and a plane, m, by brute force over every
/// pair with the manifold functions themselves (not the solver's dispatch, nor
/// max_penetration, which shares it).
double deepest_overlap(const World& w, std::span<const Plane> planes) {
    auto obb = [&](Index i) { return OBB{position(w, i), half_extents(w, i), orientation(w, i)}; };
    auto capsule = [&](Index i) {
        const Eigen::Vector3d e = orientation(w, i).rotate(half_extents(w, i));
        return Capsule{position(w, i) - e, position(w, i) + e, w.at(kRadius, i)};
    };
    auto sphere = [&](Index i) { return SphereBB{position(w, i), w.at(kRadius, i)}; };
    double worst = 0;
    Manifold m;
    auto take = [&] {
        for (int k = 0; k < m.count; ++k) worst = std::max(worst, -m.points[static_cast<std::size_t>(k)].separation);
    };
    for (Index i = 0; i < w.size(); ++i) {
        const Shape si = shape_of(w, i);
        for (Index j = 0; j < w.size(); ++j) {
            const Shape sj = shape_of(w, j);
            m.count = 0;
            if (si == Shape::box && sj == Shape::box && i < j) box_box(obb(i), obb(j), 0, m);
            if (si == Shape::sphere && sj == Shape::box) sphere_box(sphere(i), obb(j), 0, m);
            if (si == Shape::capsule && sj == Shape::box) capsule_box(capsule(i), obb(j), 0, m);
            if (si == Shape::capsule && sj == Shape::sphere) capsule_sphere(capsule(i), sphere(j), 0, m);
            if (si == Shape::capsule && sj == Shape::capsule && i < j) capsule_capsule(capsule(i), capsule(j), 0, m);
            if (si == Shape::sphere && sj == Shape::sphere && i < j)
                worst = std::max(worst, w.at(kRadius, i) + w.at(kRadius, j) - (position(w, i) - position(w, j)).norm());
            take();
        }
        for (const Plane& pl : planes) {
            m.count = 0;
            if (si == Shape::box) box_plane(obb(i), pl, 0, m);
            if (si == Shape::capsule) capsule_plane(capsule(i), pl, 0, m);
            if (si == Shape::sphere) worst = std::max(worst, w.at(kRadius, i) + pl.offset - pl.normal.dot(position(w, i)));
            take();
        }
    }
    return worst;
}

/// A step with the boxes' contacts: gravity, contacts, drift.
NumericWorkflow step_of(const World& w, std::vector<Plane> planes, double mu, ContactOptions o = {}, double e = 0) {
    return rigid_contact_step(Force3D::gravity(g), all_bodies(w), std::move(planes),
                              ContactMaterial{restitution_curve(e, 0.05), constant_curve(mu)}, o, w.layout_ptr());
}

} // namespace

// Catches: a manifold point lost (a box resting on three corners tilts), position correction
// that pushes the points one after another (the box creeps and turns), friction applied
// point by point (a net push from the order of the points).
TEST_CASE("a box at rest on the ground: four points, no drift, no creep", "[contact][boxes]") {
    const std::vector<RigidInit> init{at({0.3, 0.2, -0.1}, Quaternion::from_axis_angle({0, 1, 0}, 0.4))};
    World w = boxes({RigidBody::solid_box(2, {0.4, 0.2, 0.3})}, init);
    Stepper s(step_of(w, {Plane::ground()}, 0.6));
    s.run(w, 1.0 / 60, 600);
    Manifold m;
    box_plane(OBB{position(w, 0), {0.4, 0.2, 0.3}, orientation(w, 0)}, Plane::ground(), 1e-3, m);
    CHECK(m.count == 4);
    const auto [far, turn] = moved(w, init);
    INFO("moved " << far << " m, turned " << turn << " rad in 10 s");
    CHECK(far < 1e-6);
    CHECK(turn < 1e-6);
}

// Catches: the points of a face solved one by one (a tower leans and falls), warm starting
// that loses the points of equal stacked boxes (their feature ids flip), friction at the
// points instead of the face's centre.
TEST_CASE("towers with nothing put to sleep: 20 boxes stand 60 s, 100 boxes 10 s", "[contact][boxes][stacking]") {
    ContactOptions o;
    o.slop = 2e-5; // each of n contacts settles by the slop
    for (const auto& [n, seconds, iterations] : {std::tuple{20, 60.0, 10}, std::tuple{100, 10.0, 20}}) {
        std::vector<RigidInit> init;
        for (int i = 0; i < n; ++i) init.push_back(at({0, 0.5 + i, 0}));
        World w = boxes(std::vector<RigidBody>(static_cast<std::size_t>(n), RigidBody::solid_box(1, {0.5, 0.5, 0.5})), init);
        o.velocity_iterations = iterations;
        o.position_iterations = n > 20 ? 8 : 4;
        Stepper s(step_of(w, {Plane::ground()}, 0.6, o));
        const double dt = 1.0 / 240; // 60 Hz with 4 substeps, as Box2D's towers
        s.run(w, dt, static_cast<long>(std::lround(seconds / dt)));
        double sideways = 0;
        for (int i = 0; i < n; ++i) sideways = std::max(sideways, std::hypot(w.at(kX, i), w.at(kZ, i)));
        const auto [far, turn] = moved(w, init);
        const double deepest = max_penetration(w, all_bodies(w), std::vector<Plane>{Plane::ground()});
        INFO(n << " boxes after " << seconds << " s: moved up to " << far << " m (" << sideways << " m sideways), turned "
               << turn * 180 / pi << " deg, deepest overlap " << deepest << " m");
        CHECK(turn < 0.1 * pi / 180);
        CHECK(sideways < 1e-3);
        if (n == 20) CHECK(far < 1e-3);
        CHECK(deepest < 1e-3);
    }
}

// Catches: effective masses without the bodies' masses (a light box under a heavy one
// crushed), impulses split evenly instead of by the contact's K.
TEST_CASE("five boxes, heavy on light at 10:1, stand 10 s", "[contact][boxes][stacking]") {
    std::vector<RigidInit> init;
    std::vector<RigidBody> bodies;
    for (int i = 0; i < 5; ++i) {
        init.push_back(at({0, 0.5 + i, 0}));
        bodies.push_back(RigidBody::solid_box(i % 2 == 1 ? 10 : 1, {0.5, 0.5, 0.5}));
    }
    World w = boxes(bodies, init);
    ContactOptions o;
    o.slop = 2e-5;
    Stepper s(step_of(w, {Plane::ground()}, 0.6, o));
    s.run(w, 1.0 / 240, 2400);
    const auto [far, turn] = moved(w, init);
    INFO("moved " << far << " m, turned " << turn << " rad");
    CHECK(far < 1e-3);
    CHECK(turn < 0.1 * pi / 180);
}

// Catches: two-point manifolds (a box straddling two) mishandled, side contacts between
// neighbours pushing a row apart.
TEST_CASE("a 20-row pyramid of boxes stands 10 s", "[contact][boxes][stacking]") {
    std::vector<RigidInit> init;
    const int rows = 20;
    for (int r = 0; r < rows; ++r)
        for (int j = 0; j < rows - r; ++j) init.push_back(at({(j - 0.5 * (rows - r - 1)) * 1.02, 0.5 + r, 0}));
    World w = boxes(std::vector<RigidBody>(init.size(), RigidBody::solid_box(1, {0.5, 0.5, 0.5})), init);
    ContactOptions o;
    o.slop = 2e-5;
    o.velocity_iterations = 20; // with 10 the top box creeps sideways after a few seconds
    Stepper s(step_of(w, {Plane::ground()}, 0.6, o));
    s.run(w, 1.0 / 240, 2400);
    const auto [far, turn] = moved(w, init);
    const double deepest = max_penetration(w, all_bodies(w), std::vector<Plane>{Plane::ground()});
    INFO(init.size() << " boxes: moved up to " << far << " m, turned " << turn * 180 / pi << " deg, deepest overlap " << deepest);
    CHECK(far < 1e-2);
    CHECK(turn < 0.1 * pi / 180);
    CHECK(deepest < 1e-3);
}

// Catches: friction limited by the wrong normal impulse, the tangent directions of a
// manifold missing one, a box that creeps down a slope it should stick to.
TEST_CASE("a box on an incline sticks below tan a = mu and slides at g (sin a - mu cos a) above", "[contact][boxes][friction]") {
    const double mu = 0.4;
    for (const double deg : {15.0, 20.0, 25.0, 35.0}) {
        const double a = deg * pi / 180;
        Plane incline;
        incline.normal = Eigen::Vector3d(-std::sin(a), std::cos(a), 0);
        const Eigen::Vector3d down(-std::cos(a), -std::sin(a), 0); // along the slope, downhill
        const Quaternion q = Quaternion::from_axis_angle({0, 0, 1}, a);
        const std::vector<RigidInit> init{at(0.2 * incline.normal, q)};
        World w = boxes({RigidBody::solid_box(3, {0.3, 0.2, 0.25})}, init);
        Stepper s(step_of(w, {incline}, mu));
        const double dt = 1.0 / 240;
        s.run(w, dt, 240); // settle: a second
        const Eigen::Vector3d p0 = position(w, 0);
        const double v0 = velocity(w, 0).dot(down);
        s.run(w, dt, 240);
        const double v1 = velocity(w, 0).dot(down);
        const double slid = (position(w, 0) - p0).dot(down);
        const double expected = std::max(0.0, g * (std::sin(a) - mu * std::cos(a)));
        const double measured = (v1 - v0) / 1.0;
        INFO(deg << " deg: acceleration " << measured << " m/s^2, Coulomb " << expected << "; slid " << slid << " m");
        if (expected == 0) {
            CHECK(std::abs(slid) < 1e-6);
        } else {
            CHECK(std::abs(measured - expected) < 0.01 * expected);
        }
        CHECK(std::abs(orientation(w, 0).w - q.w) < 1e-6); // slides flat, does not tip
    }
}

// Catches: angular terms missing from a point's effective mass or impulse (a box that falls
// back from beyond the edge or tips from within it).
TEST_CASE("a box leaning on an edge tips over exactly when its centre of mass passes the edge", "[contact][boxes]") {
    const double hx = 0.1, hy = 0.3;
    const double critical = std::atan(hx / hy);
    for (const double offset : {-1.0, 1.0}) {
        const double th = critical + offset * pi / 180;
        // Turned by −θ about z: its bottom edge at (+hx, −hy) on the ground under the origin.
        const Quaternion q = Quaternion::from_axis_angle({0, 0, 1}, -th);
        const Eigen::Vector3d edge = q.rotate(Eigen::Vector3d(hx, -hy, 0));
        const std::vector<RigidInit> init{at(-edge, q)};
        World w = boxes({RigidBody::solid_box(1, {hx, hy, 0.2})}, init);
        Stepper s(step_of(w, {Plane::ground()}, 1.0));
        s.run(w, 1.0 / 240, 240 * 4);
        const Eigen::Vector3d up = orientation(w, 0).rotate(Eigen::Vector3d(0, 1, 0));
        INFO("leaning " << th * 180 / pi << " deg (critical " << critical * 180 / pi << "): its axis ends at "
                        << up.transpose());
        if (offset < 0)
            CHECK(up.y() > 0.9999); // back on its base
        else
            CHECK(std::abs(up.y()) < 1e-3); // on its side
    }
}

// Catches: a capsule's contact on one end only (it slews), spin friction that stops rolling,
// the wrong inertia about its axis.
TEST_CASE("a capsule rolls down an incline at g sin a / (1 + I / (m r^2))", "[contact][capsules][friction]") {
    const double r = 0.1, l = 0.3, m = 2, a = 20 * pi / 180;
    const RigidBody cap = RigidBody::solid_capsule(m, r, l);
    Plane incline;
    incline.normal = Eigen::Vector3d(-std::sin(a), std::cos(a), 0);
    const Eigen::Vector3d down(-std::cos(a), -std::sin(a), 0);
    // Its axis (body y) along z, across the slope.
    const Quaternion q = Quaternion::from_axis_angle({0, 0, 1}, a) * Quaternion::from_axis_angle({1, 0, 0}, pi / 2);
    World w = boxes({cap}, {at(r * incline.normal, q)});
    Stepper s(step_of(w, {incline}, 1.0));
    const double dt = 1.0 / 480;
    s.run(w, dt, 240);
    const double v0 = velocity(w, 0).dot(down);
    s.run(w, dt, 480);
    const double measured = velocity(w, 0).dot(down) - v0;
    const double expected = g * std::sin(a) / (1 + cap.inertia(1, 1) / (m * r * r));
    const Eigen::Vector3d axis = orientation(w, 0).rotate(Eigen::Vector3d(0, 1, 0));
    INFO("acceleration " << measured << " m/s^2, rolling " << expected << " (sliding would be " << g * std::sin(a)
                         << "); axis " << axis.transpose());
    CHECK(std::abs(measured - expected) < 0.01 * expected);
    CHECK(std::abs(axis.z()) > 0.9999); // still across the slope
}

// Catches: restitution applied per point without the others (a face impact rebounds too
// fast or too slow), restitution between resting boxes.
TEST_CASE("boxes meeting face to face part at e times the speed they met", "[contact][boxes][restitution]") {
    for (const double e : {0.0, 0.5, 0.9}) {
        const std::vector<RigidInit> init{at({-0.6, 0, 0}), at({0.6, 0, 0})};
        World w = boxes({RigidBody::solid_box(1, {0.5, 0.5, 0.5}), RigidBody::solid_box(3, {0.5, 0.4, 0.5})}, init);
        set_velocity(w, 0, {2, 0, 0});
        set_velocity(w, 1, {-1, 0, 0});
        const auto wf = rigid_contact_step(Force3D::gravity(0), all_bodies(w), {},
                                           ContactMaterial{restitution_curve(e, 0.05), constant_curve(0)}, {}, w.layout_ptr());
        Stepper(wf).run(w, 1e-3, 200);
        const double apart = velocity(w, 1).x() - velocity(w, 0).x();
        INFO("e = " << e << ": parting at " << apart << " m/s after meeting at 3 m/s; spins " << angular_velocity(w, 0).norm()
                    << ", " << angular_velocity(w, 1).norm());
        CHECK(std::abs(apart - 3 * e) < 0.01 * 3);
        CHECK(std::abs(total_linear_momentum(w).x() - (2 - 3)) < 1e-12);
        CHECK(angular_velocity(w, 0).norm() < 1e-9);
    }
}

// Catches: a manifold's friction along one tangent only, friction that is not opposite the
// sliding velocity (a box that curves), μ taken from the wrong row.
TEST_CASE("a box sliding on the ground stops in a straight line after v^2 / (2 mu g)", "[contact][boxes][friction]") {
    const double mu = 0.5, v0 = 2;
    for (const double heading : {0.0, 0.7, 1.9, 3.0, 4.4}) {
        const Eigen::Vector3d dir(std::cos(heading), 0, std::sin(heading));
        const std::vector<RigidInit> init{at({0, 0.1, 0}, Quaternion::from_axis_angle({0, 1, 0}, 0.3))};
        World w = boxes({RigidBody::solid_box(1, {0.3, 0.1, 0.3})}, init);
        set_velocity(w, 0, v0 * dir);
        Stepper s(step_of(w, {Plane::ground()}, mu));
        s.run(w, 1.0 / 240, 240);
        const Eigen::Vector3d d = position(w, 0) - init[0].position;
        const double along = d.dot(dir), across = (d - along * dir).norm();
        // Semi-implicit Euler moves by the velocity after each step's friction: the stopping
        // distance falls short of the continuous v²/(2μg) by v dt / 2 (to within a step's a dt²).
        const double dt = 1.0 / 240, continuous = v0 * v0 / (2 * mu * g), expected = continuous - v0 * dt / 2;
        INFO("heading " << heading << ": slid " << along << " m along, " << across << " m across; v^2/(2 mu g) = "
                        << continuous << ", less v dt / 2: " << expected);
        CHECK(velocity(w, 0).norm() < 1e-9);
        CHECK(std::abs(along - expected) < mu * g * dt * dt);
        CHECK(across < 1e-6);
    }
}

// Catches: a pair of shapes left out of the dispatch (bodies fall through each other), a
// capsule's or a box's bounds too small for the broad phase, Jacobi passes without the
// blocks' split masses, a result that depends on anything but the inputs.
TEST_CASE("a pile of boxes, capsules and spheres settles between walls, the same bits every time", "[contact][boxes][capsules]") {
    const World w0 = phynjo::test::shape_grid(5, 6, 5, {0.06, 0.08, 0.06}, 0.11, 0.005, 3);
    const std::vector<Plane> planes = phynjo::test::box_walls(0.55);
    for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
        INFO((scheme == ContactScheme::jacobi ? "Jacobi (mass splitting)" : "Gauss-Seidel"));
        ContactOptions o;
        o.scheme = scheme;
        o.velocity_iterations = 20;
        // Jacobi moves the bodies only at the end of a pass, from corrections computed apart:
        // it needs twice the passes to take out the same depth (4 leave 1 mm here).
        if (scheme == ContactScheme::jacobi) o.position_iterations = 8;
        const ContactMaterial mat{restitution_curve(0.3, 0.2), constant_curve(0.5)};
        World w = w0;
        Stepper s(rigid_contact_step(Force3D::gravity(g), all_bodies(w), planes, mat, o, w.layout_ptr()));
        const RunReport rep = s.run_guarded(w, 1.0 / 240, 240 * 4);
        REQUIRE(rep.completed);
        // Settled: all but a body or two at rest — a pile this size tips, slides or rolls one
        // body now and then (shape_grid seeds 1 to 6: one body at 0.1–0.4 m/s at random moments
        // in 2–6 s, whatever the contact code's rounding), so one body at one instant says
        // nothing about the pile.
        double vmax = 0;
        int moving = 0;
        for (Index i = 0; i < w.size(); ++i) {
            vmax = std::max(vmax, velocity(w, i).norm());
            moving += velocity(w, i).norm() > 0.05 ? 1 : 0;
            const Eigen::Vector3d p = position(w, i);
            CHECK(p.x() > 0);
            CHECK(p.x() < 0.55);
            CHECK(p.z() > 0);
            CHECK(p.z() < 0.55);
            CHECK(p.y() > 0);
        }
        const double pen = deepest_overlap(w, planes);
        INFO("after 4 s: max speed " << vmax << " m/s, " << moving << " bodies faster than 0.05 m/s, deepest overlap " << pen * 1e3 << " mm");
        CHECK(moving <= 2);
        CHECK(pen < 1e-3);
        CHECK(max_penetration(w, all_bodies(w), planes) == Approx(pen).margin(1e-12));
        World again = w0;
        Stepper s2(rigid_contact_step(Force3D::gravity(g), all_bodies(again), planes, mat, o, again.layout_ptr()));
        s2.run(again, 1.0 / 240, 240 * 4);
        CHECK(again.hash() == w.hash());
    }
}

/// A pile for the lanes tests: boxes on a 4 × layers × 4 lattice 0.12 m apart, jittered and
/// turned at random (seed), `body(n)` the n-th box.
struct LanePile {
    World w0;
    std::vector<Plane> planes = phynjo::test::box_walls(0.6);
    LanePile(unsigned seed, int layers, const std::function<RigidBody(std::size_t)>& body) : w0(make(seed, layers, body)) {}
    static World make(unsigned seed, int layers, const std::function<RigidBody(std::size_t)>& body) {
        Registry reg;
        std::vector<RigidBody> bodies;
        std::vector<RigidInit> init;
        std::mt19937 rng(seed);
        std::uniform_real_distribution<double> u(-1, 1);
        std::normal_distribution<double> gauss;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < layers; ++j)
                for (int k = 0; k < 4; ++k) {
                    reg.add("b" + std::to_string(init.size()));
                    bodies.push_back(body(init.size()));
                    init.push_back(at({0.1 + 0.12 * i + 0.01 * u(rng), 0.06 + 0.12 * j, 0.1 + 0.12 * k + 0.01 * u(rng)},
                                      Quaternion{gauss(rng), gauss(rng), gauss(rng), gauss(rng)}.normalized()));
                }
        return make_rigid_world(reg, bodies, init, contact_cache_fields(32));
    }
    /// The pile dropped for `checkpoints` × `steps` steps, in `lanes` lanes (4 or 8) or one at
    /// a time (0): the world's hash and the boxes faster than 0.05 m/s at each checkpoint, and
    /// the end.
    std::tuple<std::vector<std::uint64_t>, World, std::vector<int>> run(int lanes, int checkpoints, int steps) const {
        ContactOptions o;
        o.velocity_iterations = 20;
        o.wide = lanes != 0;
        o.lanes = lanes;
        World w = w0;
        const ContactMaterial mat{restitution_curve(0.2, 0.2), constant_curve(0.5)};
        Stepper s(rigid_contact_step(Force3D::gravity(g), all_bodies(w), planes, mat, o, w.layout_ptr()));
        std::vector<std::uint64_t> hashes;
        std::vector<int> moving;
        for (int k = 0; k < checkpoints; ++k) {
            s.run(w, 1.0 / 240, steps);
            hashes.push_back(w.hash());
            int m = 0;
            for (Index i = 0; i < w.size(); ++i) m += velocity(w, i).norm() > 0.05 ? 1 : 0;
            moving.push_back(m);
        }
        return {hashes, w, moving};
    }
};

// Catches: a lane that reads one side's inverse mass or inertia for the other's (every box of
// the scene below weighs 1 kg, so there it cannot show), or mixes up the lanes' bodies.
TEST_CASE("manifolds at once in SIMD lanes give the bits of one at a time, bodies of unequal masses", "[contact][boxes][wide]") {
    const int lanes = GENERATE(4, 8);
    INFO(lanes << " lanes");
    // 48 boxes of 0.25 to 4 kg and three shapes, turned at random, dropped into a walled box.
    const double masses[4] = {0.25, 1, 4, 2}, heights[3] = {0.05, 0.02, 0.035};
    const LanePile pile(2026, 3, [&](std::size_t n) { return RigidBody::solid_box(masses[n % 4], {0.05, heights[n % 3], 0.04}); });
    const auto [wide, end, moving] = pile.run(lanes, 6, 40);
    const auto [one, end_one, moving_one] = pile.run(0, 6, 40);
    for (std::size_t k = 0; k < wide.size(); ++k) {
        INFO("after " << static_cast<double>(k + 1) / 6 << " s");
        CHECK(wide[k] == one[k]);
    }
    // the pile came down (the top layer from 0.30 m) and lies without a millimetre of overlap
    double top = 0;
    for (Index i = 0; i < end.size(); ++i) top = std::max(top, position(end, i).y());
    CHECK(top < 0.28);
    CHECK(max_penetration(end, all_bodies(end), pile.planes) < 1e-3);
}

// Catches: a lane of the wide solver (wide_solver.cpp) that computes anything its block would
// not one at a time — a friction clamp, a twist limit, the normal impulses of the full or the
// last set or of a set its own search finds (the lanes' inverse of K_SS, the order of the
// sets, the set found not kept as the block's last), an impulse applied to the wrong body or
// not stored back — and a colouring that lets two items of a colour share a moving body
// (their order would then change the bits). Four lanes and eight: the eight's lanes 4 to 7
// come from the second half of every transpose.
TEST_CASE("manifolds at once in SIMD lanes give the bits of one at a time", "[contact][boxes][wide]") {
    const int lanes = GENERATE(4, 8);
    INFO(lanes << " lanes");
    // 96 cubes and flat boxes turned at random, dropped into a walled box: blocks of 2, 3 and
    // 4 points, full sets, last sets and enumerations, impacts and resting piles.
    const LanePile pile(37, 6, [](std::size_t n) { return RigidBody::solid_box(1, {0.05, n % 4 == 0 ? 0.02 : 0.05, 0.05}); });
    const auto [wide, end, moving] = pile.run(lanes, 8, 60);
    static const auto one_at_a_time = pile.run(0, 8, 60); // the same for both widths: once
    const std::vector<std::uint64_t>& one = std::get<0>(one_at_a_time);
    for (std::size_t k = 0; k < wide.size(); ++k) {
        INFO("after " << 0.25 * static_cast<double>(k + 1) << " s");
        CHECK(wide[k] == one[k]);
    }
    // The pile has come down (six layers closed up from 0.12 m apart to 0.1 or less) and
    // rests, its overlaps below a millimetre: the lanes solved a real pile, not a free fall.
    // "Rests" counts boxes over the last second: a pile this size tips or slides a box or
    // three now and then (seeds 1 to 7 and 37 of this scene, counted every 0.5 s for 8 s: up to
    // 3 boxes at a time at random moments, whatever the order of the block solver's search or
    // the position passes), so neither one box's speed nor the count at one instant says
    // anything about the pile; a pile that does not come to rest moves at every checkpoint.
    double top = 0, vmax = 0;
    for (Index i = 0; i < end.size(); ++i) {
        top = std::max(top, position(end, i).y());
        vmax = std::max(vmax, velocity(end, i).norm());
    }
    int resting = 0, most = 0; // of the checkpoints at 1.25, 1.5, 1.75 and 2 s
    for (std::size_t k = 4; k < 8; ++k) {
        resting += moving[k] <= 2 ? 1 : 0;
        most = std::max(most, moving[k]);
    }
    const double deepest = max_penetration(end, all_bodies(end), pile.planes);
    INFO("top " << top << " m, max speed " << vmax << " m/s at the end; boxes faster than 0.05 m/s at 1.25, 1.5, 1.75, 2 s: "
                << moving[4] << ", " << moving[5] << ", " << moving[6] << ", " << moving[7] << "; deepest overlap " << deepest << " m");
    CHECK(top < 0.6);
    CHECK(resting >= 3); // at most 2 boxes moving at three of the four checkpoints
    CHECK(most <= 4);
    CHECK(deepest < 1e-3);
}
