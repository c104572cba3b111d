// Contacts: bounce heights (e²), sliding to rolling at the time theory predicts, Newton's
// cradle, simultaneous impacts (Gauss–Seidel vs Jacobi), a settling pile, guards.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace phynjo::runtime;

namespace {

constexpr double g = 9.81;

World one_ball(const Eigen::Vector3d& p, const Eigen::Vector3d& v, double r = 0.05) {
    Registry reg;
    reg.add("ball");
    RigidInit s;
    s.position = p;
    s.velocity = v;
    return make_rigid_world(reg, {RigidBody::solid_sphere(1, r)}, {s}, contact_cache_fields());
}

/// A row of n touching balls along x (radius r), the first `gap` away from the second.
World row(int n, double r, double gap, double v0) {
    Registry reg;
    std::vector<RigidInit> init(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        reg.add("ball" + std::to_string(i));
        init[static_cast<std::size_t>(i)].position = {2 * r * i + (i == 0 ? -gap : 0.0), 0, 0};
    }
    init[0].velocity = {v0, 0, 0};
    return make_rigid_world(reg, std::vector<RigidBody>(static_cast<std::size_t>(n), RigidBody::solid_sphere(1, r)),
                            init, contact_cache_fields());
}

} // namespace

TEST_CASE("a bouncing ball loses height by e squared per bounce", "[contact][physics]") {
    const double e = 0.5, r = 0.05, h0 = 1.0;
    World w = one_ball({0, h0 + r, 0}, {0, 0, 0}, r);
    ContactMaterial mat{restitution_curve(e, 0.05), constant_curve(0)};
    Stepper s(rigid_contact_step(Force3D::gravity(g), all_bodies(w), {Plane::ground()}, mat, {}, w.layout_ptr()));
    const double dt = 1e-4;
    std::vector<double> apex{h0};
    double prev_vy = 0;
    for (int n = 0; n < 25000 && apex.size() < 4; ++n) {
        s.step(w, dt);
        const double vy = w.at(kVY, 0);
        if (prev_vy > 0 && vy <= 0) apex.push_back(w.at(kY, 0) - r); // top of a bounce
        prev_vy = vy;
    }
    REQUIRE(apex.size() == 4);
    for (std::size_t k = 1; k < apex.size(); ++k) {
        INFO("bounce " << k << ": " << apex[k - 1] << " -> " << apex[k] << " m, ratio " << apex[k] / apex[k - 1]);
        // The collision is taken at the step that would reach the ground, within v·dt of it:
        // the apex is off by at most that (≤ 0.5 mm here) relative to the bounce height.
        CHECK(std::abs(apex[k] / apex[k - 1] - e * e) < 3e-3);
    }
    CHECK(max_penetration(w, all_bodies(w), std::vector<Plane>{Plane::ground()}) < 1e-9);
}

TEST_CASE("a sliding sphere starts rolling without slipping when theory says", "[contact][physics]") {
    // Solid sphere, v0 along x, no spin, friction μ: the slip speed v − ωr falls at (7/2) μ g, so
    // rolling (v = ωr) starts at t* = 2 v0 / (7 μ g) with v = (5/7) v0, and then stays.
    const double r = 0.1, v0 = 2.0, mu = 0.3, dt = 1e-4;
    World w = one_ball({0, r, 0}, {v0, 0, 0}, r);
    ContactMaterial mat{constant_curve(0), constant_curve(mu)};
    Stepper s(rigid_contact_step(Force3D::gravity(g), all_bodies(w), {Plane::ground()}, mat, {}, w.layout_ptr()));
    const double t_star = 2 * v0 / (7 * mu * g);
    double t_roll = -1;
    for (int n = 1; n <= 5000; ++n) {
        s.step(w, dt);
        // contact point velocity: v + ω × (0, −r, 0) → x component v_x + ω_z r
        const double slip = w.at(kVX, 0) + w.at(kWZ, 0) * r;
        if (t_roll < 0 && std::abs(slip) < 1e-9) t_roll = n * dt;
    }
    INFO("rolling from t = " << t_roll << " s; theory " << t_star << " s");
    CHECK(std::abs(t_roll - t_star) <= 1.5 * dt);
    CHECK(w.at(kVX, 0) == Approx(5.0 / 7.0 * v0).epsilon(1e-9));
    CHECK(std::abs(w.at(kVX, 0) + w.at(kWZ, 0) * r) < 1e-9);
    CHECK(std::abs(w.at(kY, 0) - r) < 1e-9); // stays on the ground, neither sinking nor hopping
}

TEST_CASE("Newton's cradle passes the momentum to the last ball", "[contact][physics]") {
    const int n = 5;
    World w = row(n, 0.05, 0.02, 1.0);
    ContactMaterial mat{constant_curve(1.0), constant_curve(0)};
    const auto layout = w.layout_ptr();
    Stepper s(rigid_contact_step(Force3D{}, all_bodies(w), {}, mat, {}, layout));
    s.run(w, 1e-3, 200);
    for (int i = 0; i + 1 < n; ++i) CHECK(std::abs(w.at(kVX, static_cast<Index>(i))) < 1e-12);
    CHECK(w.at(kVX, n - 1) == Approx(1.0).epsilon(1e-12));
    CHECK(total_linear_momentum(w).x() == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("simultaneous impacts: Gauss-Seidel conserves energy, Jacobi passes do not", "[contact][physics]") {
    // Two balls hit a resting middle ball from both sides at once, e = 1. Energy and momentum
    // conservation with the symmetry give the outer balls reversed and the middle at rest.
    auto run = [](ContactScheme scheme) {
        Registry reg;
        for (const char* s : {"left", "middle", "right"}) reg.add(s);
        std::vector<RigidInit> init(3);
        init[0].position = {-0.1005, 0, 0};
        init[0].velocity = {1, 0, 0};
        init[2].position = {0.1005, 0, 0};
        init[2].velocity = {-1, 0, 0};
        World w = make_rigid_world(reg, std::vector<RigidBody>(3, RigidBody::solid_sphere(1, 0.05)), init);
        ContactOptions o;
        o.scheme = scheme;
        Stepper s(rigid_contact_step(Force3D{}, all_bodies(w), {}, ContactMaterial{constant_curve(1), constant_curve(0)},
                                     o, w.layout_ptr()));
        s.run(w, 1e-3, 10);
        return w;
    };
    const World gs = run(ContactScheme::gauss_seidel);
    CHECK(gs.at(kVX, 0) == Approx(-1).epsilon(1e-12));
    CHECK(std::abs(gs.at(kVX, 1)) < 1e-12);
    CHECK(gs.at(kVX, 2) == Approx(1).epsilon(1e-12));
    const World jc = run(ContactScheme::jacobi);
    CHECK(std::abs(total_linear_momentum(jc).x()) < 1e-12);  // momentum is kept…
    CHECK(rigid_kinetic_energy(jc) < 0.5 * rigid_kinetic_energy(gs)); // …energy is not
}

TEST_CASE("a pile of spheres settles between walls: at rest, no visible overlap, deterministic", "[contact][physics]") {
    for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
        INFO((scheme == ContactScheme::jacobi ? "Jacobi (mass splitting)" : "Gauss-Seidel"));
        const int side = 5;
        const double r = 0.05, spacing = 0.13;
        Registry reg;
        std::vector<RigidInit> init;
        std::mt19937 rng(42);
        std::uniform_real_distribution<double> jitter(-0.01, 0.01);
        for (int i = 0; i < side; ++i)
            for (int j = 0; j < side; ++j)
                for (int k = 0; k < side; ++k) {
                    reg.add("s" + std::to_string(init.size()));
                    RigidInit s;
                    s.position = {(i + 0.5) * spacing + jitter(rng), r + 0.05 + j * spacing + jitter(rng), (k + 0.5) * spacing + jitter(rng)};
                    init.push_back(s);
                }
        const double L = side * spacing;
        std::vector<Plane> planes{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -L}, Plane{{0, 0, 1}, 0},
                                  Plane{{0, 0, -1}, -L}};
        World w0 = make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_sphere(1, r)), init,
                                    contact_cache_fields());
        ContactMaterial mat{restitution_curve(0.5, 0.2), constant_curve(0.5)};
        ContactOptions o;
        o.scheme = scheme;
        o.velocity_iterations = 20;
        World w = w0;
        Stepper s(rigid_contact_step(Force3D::gravity(g), all_bodies(w), planes, mat, o, w.layout_ptr()));
        const RunReport rep = s.run_guarded(w, 1.0 / 240, 720);
        REQUIRE(rep.completed);
        double vmax = 0, top = 0;
        for (Index i = 0; i < w.size(); ++i) {
            vmax = std::max(vmax, velocity(w, i).norm());
            top = std::max(top, w.at(kY, i));
            CHECK(w.at(kX, i) > r - 1e-3);
            CHECK(w.at(kX, i) < L - r + 1e-3);
        }
        const double pen = max_penetration(w, all_bodies(w), planes);
        INFO("after 3 s: max speed " << vmax << " m/s, max penetration " << pen * 1e3 << " mm, top " << top << " m");
        CHECK(vmax < 0.05);
        CHECK(pen < 5e-4);
        // Same inputs, same bits.
        World again = w0;
        Stepper s2(rigid_contact_step(Force3D::gravity(g), all_bodies(again), planes, mat, o, again.layout_ptr()));
        s2.run(again, 1.0 / 240, 720);
        CHECK(again.hash() == w.hash());
    }
}

TEST_CASE("contact misuse is refused with a message naming what is wrong", "[contact][guards]") {
    World w = one_ball({0, 1, 0}, {0, 0, 0});
    const auto layout = w.layout_ptr();
    ContactOptions bad;
    bad.baumgarte = 2;
    CHECK_THROWS_WITH(contact_ground(all_bodies(w), {}, bad, layout),
                      "contact_rule: the Baumgarte factor must be in [0, 1]");
    ContactOptions odd;
    odd.lanes = 6; // SIMD lanes come in fours and eights only
    CHECK_THROWS_WITH(contact_ground(all_bodies(w), {}, odd, layout), "contact_rule: lanes must be 0 (the machine's), 4 or 8");
    CHECK_THROWS_WITH(contact_rule(all_bodies(w), {Plane{{0, 2, 0}, 0}}, {}, {}, layout),
                      "plane: the normal is not a unit vector");
    // A restitution curve out of range: the guarded run stops and says why.
    World v = one_ball({0, 0.06, 0}, {0, -1, 0});
    Stepper s(NumericWorkflow::run(
        contact_ground(all_bodies(v), ContactMaterial{constant_curve(1.5), constant_curve(0)}, {}, v.layout_ptr())));
    const RunReport rep = s.run_guarded(v, 0.01, 10);
    CHECK_FALSE(rep.completed);
    CHECK(rep.reason.find("restitution curve returned 1.5") != std::string::npos);
    // A non-finite state reaching the contacts: the guarded run names the body.
    World nan = one_ball({0, 1, 0}, {0, 0, 0}); // (make_rigid_world itself refuses a NaN)
    nan.at(kY, 0) = std::nan("");
    Stepper sn(NumericWorkflow::run(contact_ground(all_bodies(nan), {}, {}, nan.layout_ptr())));
    const RunReport rn = sn.run_guarded(nan, 0.01, 1);
    CHECK_FALSE(rn.completed);
    CHECK(rn.reason == "a rule failed: contact: the position or velocity of 'ball' is not finite");
    // Contacts write what a kick of the same body writes: they cannot run in parallel.
    CHECK_THROWS_AS(NumericWorkflow::par(NumericWorkflow::run(contact_ground(all_bodies(w), {}, {}, layout)),
                                         NumericWorkflow::run(kick_force3d(Force3D::gravity(g), all_bodies(w), 1, layout))),
                    DomainOverlapError);
}

TEST_CASE("contact rules over disjoint bodies run in par, bit-identical to seq on any thread count", "[contact][workflow]") {
    Registry reg;
    std::vector<RigidInit> init(6);
    for (int i = 0; i < 6; ++i) {
        reg.add("ball" + std::to_string(i));
        init[static_cast<std::size_t>(i)].position = {0.3 * i, 0.3 + 0.1 * i, 0};
        init[static_cast<std::size_t>(i)].velocity = {0.5, 0, 0.2 * i};
    }
    const World w0 = make_rigid_world(reg, std::vector<RigidBody>(6, RigidBody::solid_sphere(1, 0.05)), init,
                                      contact_cache_fields());
    const auto layout = w0.layout_ptr();
    using W = NumericWorkflow;
    std::vector<W> grounds;
    for (Index i = 0; i < 6; i += 2)
        grounds.push_back(W::run(contact_ground(ComponentSet{i, i + 1},
                                                ContactMaterial{restitution_curve(0.3 + 0.1 * i, 0.05), constant_curve(0.4)},
                                                {}, layout)));
    const ComponentSet all = all_bodies(w0);
    auto wf = [&](bool parallel) {
        return W::seq(W::run(kick_force3d(Force3D::gravity(g), all, 1, layout)), parallel ? W::par(grounds) : W::seq(grounds),
                      W::run(drift_trans(all, 1, layout)), W::run(drift_rot(all, 1, layout)));
    };
    World a = w0, b = w0, c = w0;
    Executor two(2), four(4);
    Stepper(wf(false)).run(a, 1e-3, 2000);
    Stepper(wf(true), &two).run(b, 1e-3, 2000);
    Stepper(wf(true), &four).run(c, 1e-3, 2000);
    CHECK(a.hash() == b.hash());
    CHECK(a.hash() == c.hash());
    CHECK(a.at(kY, 0) < 0.3); // something happened: the balls fell and bounced
}

TEST_CASE("a contact rule over every other body writes no field of the bodies between them", "[contact][workflow]") {
    // Bug caught: the warm-start cache cleared as one run of components from the rule's first
    // body to its last, wiping the cache (or anything) of bodies that are not the rule's.
    Registry reg;
    std::vector<RigidInit> init(5);
    for (int i = 0; i < 5; ++i) {
        reg.add("ball" + std::to_string(i));
        init[static_cast<std::size_t>(i)].position = {0.3 * i, 0.05, 0}; // resting on the ground
    }
    World w = make_rigid_world(reg, std::vector<RigidBody>(5, RigidBody::solid_sphere(1, 0.05)), init, contact_cache_fields());
    const Layout& layout = w.layout();
    // The bodies between the rule's hold cache entries of their own (another rule's, say).
    for (Index i : {Index{1}, Index{3}})
        for (std::size_t f = 0; f < layout.fields.size(); ++f)
            if (layout.fields[f].rfind("wc_", 0) == 0) w.at(static_cast<FieldId>(f), i) = 100.0 + static_cast<double>(f);
    const World before = w;
    Stepper st(rigid_contact_step(Force3D::gravity(g), ComponentSet{0, 2, 4}, {Plane::ground()}, {}, {}, w.layout_ptr()));
    st.run(w, 1e-3, 10);
    for (Index i : {Index{1}, Index{3}})
        for (std::size_t f = 0; f < layout.fields.size(); ++f) {
            INFO(layout.describe(static_cast<FieldId>(f), i));
            CHECK(w.at(static_cast<FieldId>(f), i) == before.at(static_cast<FieldId>(f), i));
        }
    // The rule's own bodies rest on the ground and keep their contact in the cache.
    for (Index i : {Index{0}, Index{2}, Index{4}}) CHECK(w.at(layout.field("wc_partner#0"), i) != 0);
}

TEST_CASE("impacts of bodies with anisotropic inertia conserve angular momentum about the contact point", "[contact][physics]") {
    // An impulse acts at the contact point, so across a contact step (no other force) the
    // angular momentum about that point, L_c = I_W ω + m (p − c) × v, is unchanged, whatever
    // the inertia tensor and orientation: a check of the effective masses with world inertia
    // tensors and of every lever arm. Friction clips (sliding) and sticks (rolling) here.
    RigidBody b = RigidBody::solid_sphere(2, 0.1);
    b.inertia << 0.010, 0.002, -0.001, 0.002, 0.006, 0.0005, -0.001, 0.0005, 0.012;
    for (double mu : {0.1, 2.0}) {
        Registry reg;
        reg.add("ball");
        RigidInit s;
        s.position = {0, 0.1, 0}; // touching the ground
        s.orientation = Quaternion::from_axis_angle({1, 2, 3}, 0.8);
        s.velocity = {1.5, -2.0, 0.7};
        s.angular_velocity = {3, -1, 4};
        World w = make_rigid_world(reg, {b}, {s});
        const Eigen::Vector3d c(0, 0, 0); // the contact point
        auto Lc = [&](const World& x) {
            return Eigen::Vector3d(world_inertia(x, 0) * angular_velocity(x, 0) +
                                   2.0 * (position(x, 0) - c).cross(velocity(x, 0)));
        };
        const Eigen::Vector3d before = Lc(w);
        Stepper st(NumericWorkflow::run(contact_ground(all_bodies(w), ContactMaterial{constant_curve(0.6), constant_curve(mu)},
                                                       {}, w.layout_ptr())));
        st.step(w, 1e-3);
        INFO("mu = " << mu << ": v_y after " << w.at(kVY, 0));
        CHECK(w.at(kVY, 0) > 0); // it bounced
        CHECK((Lc(w) - before).norm() < 1e-12 * before.norm());
        // and the bounce obeys Newton's law at the contact point when friction does not stick
        if (mu < 1) {
            const Eigen::Vector3d vc = velocity(w, 0) + angular_velocity(w, 0).cross(Eigen::Vector3d(0, -0.1, 0));
            CHECK(vc.y() == Approx(0.6 * 2.0).epsilon(1e-12));
        }
    }
}

TEST_CASE("sphere-sphere impacts with anisotropic inertia conserve momentum and angular momentum", "[contact][physics]") {
    RigidBody a = RigidBody::solid_sphere(1, 0.1), b = RigidBody::solid_sphere(3, 0.2);
    a.inertia << 0.004, 0.001, 0, 0.001, 0.005, 0.0002, 0, 0.0002, 0.006;
    b.inertia << 0.05, -0.01, 0.004, -0.01, 0.04, 0, 0.004, 0, 0.06;
    Registry reg;
    reg.add("a");
    reg.add("b");
    std::vector<RigidInit> s(2);
    const Eigen::Vector3d n = Eigen::Vector3d(1, 0.4, -0.3).normalized();
    s[0].position = Eigen::Vector3d(0.2, 0.1, 0) + 0.3 * n; // touching: |p_a − p_b| = r_a + r_b
    s[1].position = {0.2, 0.1, 0};
    s[0].orientation = Quaternion::from_axis_angle({0, 1, 1}, 1.1);
    s[1].orientation = Quaternion::from_axis_angle({1, 0, 1}, -0.4);
    s[0].velocity = {-2, 0.5, 0.3};
    s[1].velocity = {0.4, -0.2, 0.1};
    s[0].angular_velocity = {1, 5, -2};
    s[1].angular_velocity = {-3, 0.5, 2};
    World w = make_rigid_world(reg, {a, b}, s);
    for (double mu : {0.2, 3.0}) {
        World x = w;
        const Eigen::Vector3d p0 = total_linear_momentum(x), l0 = total_angular_momentum(x);
        Stepper st(NumericWorkflow::run(contact_spheres(all_bodies(x), ContactMaterial{constant_curve(0.8), constant_curve(mu)},
                                                        {}, x.layout_ptr())));
        st.step(x, 1e-3);
        CHECK((velocity(x, 0) - velocity(w, 0)).norm() > 0.1); // they collided
        CHECK((total_linear_momentum(x) - p0).norm() < 1e-13 * p0.norm());
        CHECK((total_angular_momentum(x) - l0).norm() < 1e-12 * l0.norm());
        // The conservation laws hold for an impulse of any size; the size is Newton's law at
        // the contact point: the normal relative velocity there reverses with factor e (the
        // lever arms are parallel to n, so neither friction nor the inertia tensors couple
        // into it). Catches a wrong effective mass with world inertia tensors.
        auto vn = [&](const World& y) {
            const Eigen::Vector3d ca = velocity(y, 0) + angular_velocity(y, 0).cross(-0.1 * n);
            const Eigen::Vector3d cb = velocity(y, 1) + angular_velocity(y, 1).cross(0.2 * n);
            return (ca - cb).dot(n);
        };
        CHECK(vn(w) < 0);
        CHECK(vn(x) == Approx(-0.8 * vn(w)).epsilon(1e-12));
    }
}

namespace {

/// Two solid spheres a (left) and b on the x axis, touching (gap 0) or `gap` apart.
World sphere_pair(double ma, double ra, double mb, double rb, const Eigen::Vector3d& va, const Eigen::Vector3d& vb,
                  double gap = 0) {
    Registry reg;
    reg.add("a");
    reg.add("b");
    std::vector<RigidInit> s(2);
    s[0].position = {-(ra + rb + gap), 0, 0};
    s[0].velocity = va;
    s[1].velocity = vb;
    return make_rigid_world(reg, {RigidBody::solid_sphere(ma, ra), RigidBody::solid_sphere(mb, rb)}, s);
}

/// One application of the sphere-sphere contact rule.
World contact_once(World w, const ContactMaterial& mat, ContactOptions o = {}) {
    Stepper st(NumericWorkflow::run(contact_spheres(all_bodies(w), mat, o, w.layout_ptr())));
    st.step(w, 1e-3);
    return w;
}

} // namespace

// Catches: a restitution applied squared or not at all between spheres (the e = 1 cradle
// cannot tell e from e²), a wrong reduced mass in the sphere-pair impulse.
TEST_CASE("two-sphere head-on impacts: outgoing relative speed is e times incoming, momentum kept", "[contact][physics]") {
    for (double e : {0.0, 0.25, 0.5, 0.9, 1.0}) {
        const World w = sphere_pair(1.0, 0.1, 3.0, 0.2, {2.0, 0, 0}, {-0.5, 0, 0});
        const World x = contact_once(w, ContactMaterial{constant_curve(e), constant_curve(0)});
        const double before = w.at(kVX, 0) - w.at(kVX, 1), after = x.at(kVX, 1) - x.at(kVX, 0);
        INFO("e = " << e << ": approach " << before << " m/s, separation " << after << " m/s");
        CHECK(after == Approx(e * before).margin(1e-12));
        CHECK(total_linear_momentum(x).x() == Approx(total_linear_momentum(w).x()).epsilon(1e-14));
        // the same through whole steps from a gap: the impact happens inside the run
        World y = sphere_pair(1.0, 0.1, 3.0, 0.2, {2.0, 0, 0}, {-0.5, 0, 0}, 0.01);
        Stepper s(rigid_contact_step(Force3D{}, all_bodies(y), {}, ContactMaterial{constant_curve(e), constant_curve(0)}, {},
                                     y.layout_ptr()));
        s.run(y, 1e-3, 50);
        CHECK(y.at(kVX, 1) - y.at(kVX, 0) == Approx(e * before).margin(1e-12));
    }
}

// Catches: a threshold compared the wrong way, on the wrong speed (relative vs absolute),
// or ignored (restitution_curve(e, v*) must give 0 below v* and e above).
TEST_CASE("restitution threshold: a sphere pair bounces just above it and not just below", "[contact][physics]") {
    const double e = 0.8, threshold = 1.0;
    for (double speed : {0.99, 1.01}) {
        // b moves too: the threshold applies to the relative approach speed, not a's speed
        const World w = sphere_pair(1.0, 0.1, 1.0, 0.1, {0.7 * speed, 0, 0}, {-0.3 * speed, 0, 0});
        const World x = contact_once(w, ContactMaterial{restitution_curve(e, threshold), constant_curve(0)});
        const double after = x.at(kVX, 1) - x.at(kVX, 0);
        INFO("approach " << speed << " m/s, separation " << after << " m/s");
        CHECK(after == Approx(speed < threshold ? 0.0 : e * speed).margin(1e-12));
    }
}

// Catches: friction between spheres missing, unclipped (no Coulomb limit), clipped to the
// wrong normal impulse, or with a wrong tangential effective mass (lever arms r²/I).
TEST_CASE("oblique sphere-sphere impacts: Coulomb friction sticks or slides as the impulse bound says", "[contact][physics]") {
    // a (1 kg) hits b (2 kg) along x at 2 m/s with a sideways speed vy; no spin. With
    // e = 0.5 the normal impulse is j_n = (1 + e) 2 / (1/ma + 1/mb) = 2 N s. For solid spheres
    // r²/I = 5/(2m), so the tangential inverse effective mass is K_t = 7/2 (1/ma + 1/mb) = 5.25
    // and stopping the slip takes j = vy / K_t; Coulomb allows at most μ j_n.
    const double ma = 1, mb = 2, r = 0.1, jn = 2.0, Kt = 3.5 * (1 / ma + 1 / mb);
    struct Case {
        double vy, mu;
        bool sticks;
    };
    for (const Case c : {Case{3.0, 0.2, false}, Case{0.3, 0.5, true}}) {
        const World w = sphere_pair(ma, r, mb, r, {2.0, c.vy, 0}, {0, 0, 0});
        const World x = contact_once(w, ContactMaterial{constant_curve(0.5), constant_curve(c.mu)});
        const double jt = c.sticks ? c.vy / Kt : c.mu * jn;
        // contact point velocities: a touches b at +r x̂ from its centre, b at −r x̂ from its own
        const Eigen::Vector3d ra(r, 0, 0), rb(-r, 0, 0);
        const Eigen::Vector3d slip = (velocity(x, 0) + angular_velocity(x, 0).cross(ra)) -
                                     (velocity(x, 1) + angular_velocity(x, 1).cross(rb));
        INFO("vy = " << c.vy << ", mu = " << c.mu << ": slip after " << slip.transpose());
        CHECK(x.at(kVY, 0) == Approx(c.vy - jt / ma).margin(1e-12));
        CHECK(x.at(kVY, 1) == Approx(jt / mb).margin(1e-12));
        CHECK(slip.y() == Approx(c.sticks ? 0.0 : c.vy - jt * Kt).margin(1e-12));
        CHECK(slip.x() == Approx(-0.5 * 2.0).margin(1e-12)); // a moves away from b at e × 2 m/s
        CHECK(total_angular_momentum(x).isApprox(total_angular_momentum(w), 1e-12));
    }
}

// Catches: a position correction split evenly instead of by inverse mass (the centre of mass
// would move), applied with the wrong sign or count of passes, or leaking into velocities.
TEST_CASE("a deep sphere-pair overlap is corrected along the normal, split by inverse mass", "[contact][physics]") {
    const double ma = 1, mb = 3, r = 0.1, depth = 0.05;
    const World w = sphere_pair(ma, r, mb, r, {0, 0, 0}, {0, 0, 0}, -depth);
    ContactOptions o; // β = 0.2, slop 1e-4, 4 passes: depth → slop + (depth − slop)(1 − β)^4
    const World x = contact_once(w, ContactMaterial{constant_curve(0), constant_curve(0.5)}, o);
    const double left = o.slop + (depth - o.slop) * std::pow(1 - o.baumgarte, o.position_iterations);
    const double moved = depth - left, wa = (1 / ma) / (1 / ma + 1 / mb);
    CHECK(x.at(kX, 0) == Approx(w.at(kX, 0) - wa * moved).margin(1e-15));
    CHECK(x.at(kX, 1) == Approx(w.at(kX, 1) + (1 - wa) * moved).margin(1e-15));
    CHECK(ma * x.at(kX, 0) + mb * x.at(kX, 1) == Approx(ma * w.at(kX, 0) + mb * w.at(kX, 1)).margin(1e-15));
    CHECK(velocity(x, 0).norm() == 0);
    CHECK(velocity(x, 1).norm() == 0);
    // repeated steps leave no more than the slop
    World y = w;
    Stepper s(rigid_contact_step(Force3D{}, all_bodies(y), {}, ContactMaterial{constant_curve(0), constant_curve(0.5)}, o,
                                 y.layout_ptr()));
    s.run(y, 1e-3, 20);
    CHECK(max_penetration(y, all_bodies(y), {}) == Approx(o.slop).epsilon(1e-3));
    CHECK(ma * y.at(kX, 0) + mb * y.at(kX, 1) == Approx(ma * w.at(kX, 0) + mb * w.at(kX, 1)).margin(1e-15));
}
