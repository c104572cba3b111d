// Scenes: generated models and rigid bodies in one world, one contact rule (contact/scene.hpp).
// Impacts of a .lag pendulum's bob on free spheres against the textbook (head-on splits,
// angular momentum about the pivot for an oblique hit), a model ball resting on the ground, a
// constrained model keeping its constraint through impacts, immovable directions, domains,
// and bit-identical runs on 1, 2 and 4 threads.
#include "bob_pendulum.hpp"
#include "double_bob.hpp"
#include "phynjo/runtime/runtime.hpp"
#include "planar_ball.hpp"
#include "ring_bead.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>

using namespace phynjo::runtime;

namespace {

constexpr double g = 9.81;

ContactMaterial elastic(double e, double mu = 0) { return ContactMaterial{constant_curve(e), constant_curve(mu)}; }

/// A bob pendulum (mass m1, pivot (0, 0), l = 1, r = 0.05) hanging at th = 0 with angular
/// velocity w, and a free rigid sphere (mass m2, r = 0.05) at rest at `at`.
Scene bob_and_ball(double m1, double w, double m2, const Eigen::Vector3d& at, double th = 0) {
    bob_pendulum::Parameters P;
    P.m = m1;
    Registry reg;
    reg.add("ball");
    RigidInit s;
    s.position = at;
    Scene sc = make_scene(reg, {RigidBody::solid_sphere(m2, 0.05)}, {s}, {ModelInstance{"pend", bob_pendulum::system(P)}},
                          contact_cache_fields());
    const double q[1] = {th}, qd[1] = {w};
    set_model_state(sc, 0, q, qd);
    return sc;
}

/// The contact rule alone, once: the impulses of an instant.
void contacts_once(Scene& sc, ContactMaterial mat, double dt = 1e-3, ContactOptions options = {}) {
    Stepper st(NumericWorkflow::run(contact_rule(sc, {}, std::move(mat), options)));
    st.step(sc.world, dt);
}

/// L_z about the origin (the pivot): the bob's m l² θ' plus the ball's (r × m v)_z.
double angular_momentum_z(const Scene& sc, double m1, double m2) {
    const double w = model_qdot(sc, 0)[0];
    const Eigen::Vector3d p = position(sc.world, 0), v = velocity(sc.world, 0);
    return m1 * w + m2 * (p.x() * v.y() - p.y() * v.x());
}

} // namespace

// Bugs caught: the model's effective mass taken as 1/m of nothing (J ignored: the bob would act
// as a wall or a feather), an impulse applied to q' without M⁻¹ (wrong split for m1 ≠ 1), the
// sign of the model side's impulse, restitution skipped for model rows.
TEST_CASE("a pendulum bob striking a resting sphere head-on: the textbook split of speeds", "[scene][physics]") {
    for (const auto& [m1, m2, e] : {std::tuple{1.0, 1.0, 1.0}, std::tuple{1.0, 1.0, 0.5}, std::tuple{2.0, 1.0, 1.0},
                                   std::tuple{2.0, 1.0, 0.3}, std::tuple{1.0, 3.0, 0.8}}) {
      for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
        CAPTURE(m1, m2, e, scheme == ContactScheme::jacobi);
        const double v = 1.5; // the bob's speed along +x at the bottom (l = 1)
        Scene sc = bob_and_ball(m1, v, m2, {0.1, -1, 0});
        ContactOptions o;
        o.scheme = scheme;
        contacts_once(sc, elastic(e), 1e-3, o);
        const double v1 = (m1 - e * m2) * v / (m1 + m2), v2 = (1 + e) * m1 * v / (m1 + m2);
        CHECK(model_qdot(sc, 0)[0] == Approx(v1).margin(1e-12));
        CHECK(velocity(sc.world, 0).x() == Approx(v2).margin(1e-12));
        CHECK(std::abs(velocity(sc.world, 0).y()) < 1e-12);
        // The proxy follows the model: its velocity is l θ' along x.
        CHECK(velocity(sc.world, sc.models[0].spheres[0]).x() == Approx(v1).margin(1e-12));
        if (e == 1.0) {
            const double before = 0.5 * m1 * v * v;
            CHECK(0.5 * m1 * v1 * v1 + 0.5 * m2 * v2 * v2 == Approx(before).epsilon(1e-13));
        }
      }
    }
    // Equal masses, e = 1: the bob stops and the ball leaves with its speed, through whole steps.
    Scene sc = bob_and_ball(1, 1.5, 1, {0.1, -1, 0});
    Stepper st(scene_step(sc, Force3D{}, {}, elastic(1), {}));
    st.step(sc.world, 1e-3);
    CHECK(std::abs(model_qdot(sc, 0)[0]) < 1e-9); // it then falls back from θ ≈ 0 under gravity
    CHECK(velocity(sc.world, 0).x() == Approx(1.5).margin(1e-12));
}

// Bugs caught: an impulse applied at the wrong place or along the wrong direction on the model
// (the pivot would take a moment), B = M⁻¹Jᵀ transposed, a model-side normal not from the
// centres, restitution applied to the tangential part.
TEST_CASE("an oblique hit conserves angular momentum about the pivot (and energy when e = 1)", "[scene][physics]") {
    for (const double e : {1.0, 0.6}) {
        CAPTURE(e);
        const double m1 = 1.3, m2 = 0.7, th = 0.4;
        // The bob at (sin θ, −cos θ); the ball touching it along a direction 50° away from
        // the bob's velocity.
        const Eigen::Vector3d bob{std::sin(th), -std::cos(th), 0};
        const double a = th + 0.9;
        const Eigen::Vector3d ball = bob + 0.1 * Eigen::Vector3d{std::cos(a), std::sin(a), 0};
        Scene sc = bob_and_ball(m1, 2.0, m2, ball, th);
        // Kinetic energy: the bob's ½ m1 (l θ')², the ball's ½ m2 v².
        auto kinetic = [&] {
            const double w = model_qdot(sc, 0)[0];
            return 0.5 * m1 * w * w + 0.5 * m2 * velocity(sc.world, 0).squaredNorm();
        };
        const double l0 = angular_momentum_z(sc, m1, m2), e0 = kinetic();
        contacts_once(sc, elastic(e));
        CHECK(velocity(sc.world, 0).norm() > 0.5); // it was struck
        CHECK(angular_momentum_z(sc, m1, m2) == Approx(l0).epsilon(1e-12));
        const double e1 = kinetic();
        if (e == 1.0)
            CHECK(e1 == Approx(e0).epsilon(1e-12));
        else
            CHECK(e1 < e0);
        // The ball leaves along the line of centres (frictionless).
        const Eigen::Vector3d n = (ball - bob).normalized();
        CHECK(velocity(sc.world, 0).normalized().dot(n) == Approx(1).epsilon(1e-12));
    }
}

// Bugs caught: position correction not passed through the model (it would sink or be ignored),
// an impulse on the model that does not reach q', a contact cache keyed wrongly for proxies
// (a resting ball bouncing every other step).
TEST_CASE("a model ball resting on the ground: no drift, no jitter, overlap below 0.5 mm", "[scene][physics]") {
    Scene sc = make_scene(Registry{}, {}, {}, {ModelInstance{"ball", planar_ball::system({})}}, contact_cache_fields());
    const ContactMaterial mat{restitution_curve(0.5, 0.2), constant_curve(0.5)};
    Stepper st(scene_step(sc, Force3D{}, {Plane::ground()}, mat, {}));
    const double dt = 1e-3;
    double y_at_5 = 0, lo = 1e9, hi = -1e9, worst_overlap = 0, worst_speed = 0;
    for (int k = 1; k <= 10000; ++k) {
        st.step(sc.world, dt);
        const double y = model_q(sc, 0)[1];
        worst_overlap = std::max(worst_overlap, k > 3000 ? 0.1 - y : 0.0);
        if (k == 5000) y_at_5 = y;
        if (k > 9000) {
            lo = std::min(lo, y);
            hi = std::max(hi, y);
            worst_speed = std::max(worst_speed, std::abs(model_qdot(sc, 0)[1]));
        }
    }
    const double y = model_q(sc, 0)[1];
    CHECK(0.1 - y < 0.5e-3);
    CHECK(worst_overlap < 0.5e-3);
    CHECK(std::abs(y - y_at_5) < 1e-6); // no drift
    CHECK(hi - lo < 1e-6);              // no jitter
    // The velocity the model leaves its step with is the free fall of one step at most: the
    // impulse zeroes the approach at the start of the step, then the model steps under gravity.
    CHECK(worst_speed <= g * dt * (1 + 1e-9));
    CHECK(max_penetration(sc.world, sc.spheres, std::vector<Plane>{Plane::ground()}) < 0.5e-3);
}

// Bugs caught: a position correction applied to the proxy only (the model would stay in the
// ground and the correction repeat forever), one not divided by the effective mass (a model
// launched out of the overlap), Jacobi's accumulated corrections lost for model spheres.
TEST_CASE("a model sphere overlapping the ground at the start is pushed out gently", "[scene][physics]") {
    for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
        CAPTURE(scheme == ContactScheme::jacobi);
        Scene sc = make_scene(Registry{}, {}, {}, {ModelInstance{"ball", planar_ball::system({})}}, contact_cache_fields());
        const double q0[2] = {0, 0.08}, v0[2] = {0, 0}; // 2 cm into the ground (r = 0.1 m)
        set_model_state(sc, 0, q0, v0);
        CHECK(max_penetration(sc.world, sc.spheres, std::vector<Plane>{Plane::ground()}) == Approx(0.02));
        ContactOptions o;
        o.scheme = scheme;
        Stepper st(scene_step(sc, Force3D{}, {Plane::ground()}, elastic(0.5, 0.5), o));
        double top = 0;
        for (int k = 0; k < 500; ++k) {
            st.step(sc.world, 1e-3);
            top = std::max(top, model_q(sc, 0)[1]);
        }
        CHECK(max_penetration(sc.world, sc.spheres, std::vector<Plane>{Plane::ground()}) < 0.2e-3);
        CHECK(top < 0.1 + 1e-3);                      // out of the ground, not thrown up
        CHECK(std::abs(model_qdot(sc, 0)[1]) < 0.02); // position correction moves q, not q'
    }
}

// Bugs caught: an impulse that ignores the constraints (B = M⁻¹Jᵀ without the projection: the
// bead would leave its ring at the impulse), a position correction that breaks them.
TEST_CASE("a constrained model in contact keeps its constraint", "[scene][physics]") {
    Registry reg;
    reg.add("ball");
    RigidInit s;
    s.position = {0.3, -1, 0}; // in the bead's way along the ring
    Scene sc = make_scene(reg, {RigidBody::solid_sphere(0.5, 0.05)}, {s}, {ModelInstance{"bead", ring_bead::system({})}},
                          contact_cache_fields());
    const double q0[2] = {0, -1}, v0[2] = {3, 0};
    set_model_state(sc, 0, q0, v0);
    // Right after an impulse: the velocity constraint x x' + y y' = 0 holds.
    Stepper st(scene_step(sc, Force3D{}, {}, elastic(0.9), {}));
    bool struck = false;
    for (int k = 0; k < 400; ++k) {
        const double before = velocity(sc.world, 0).norm();
        Stepper(NumericWorkflow::run(contact_rule(sc, {}, elastic(0.9), {}))).step(sc.world, 1e-3);
        const auto q = model_q(sc, 0), v = model_qdot(sc, 0);
        if (velocity(sc.world, 0).norm() > before + 1e-9) {
            struck = true;
            CHECK(std::abs(q[0] * v[0] + q[1] * v[1]) < 1e-12 * (1 + std::hypot(v[0], v[1])));
        }
        sc.world.time -= 1e-3; // the contact rule alone advanced time: undo before the full step
        st.step(sc.world, 1e-3);
        const auto q1 = model_q(sc, 0);
        CHECK(std::abs(q1[0] * q1[0] + q1[1] * q1[1] - 1) < 1e-9);
    }
    CHECK(struck);
}

// Bugs caught: a division by a zero effective mass (NaN) when the model cannot move along the
// normal, a contact between two immovable sides given an impulse.
TEST_CASE("a contact the model cannot move along is a static side: no NaN, no impulse", "[scene][guards]") {
    // The bob hangs at θ = 0 pressed 1 mm into the ground below it: along the rod it cannot move.
    bob_pendulum::Parameters P;
    Scene sc = make_scene(Registry{}, {}, {}, {ModelInstance{"pend", bob_pendulum::system(P)}}, contact_cache_fields());
    const std::vector<Plane> floor{Plane{{0, 1, 0}, -1.049}};
    Stepper st(scene_step(sc, Force3D{}, floor, elastic(0.5, 0.5), {}));
    const RunReport rep = st.run_guarded(sc.world, 1e-3, 200);
    CHECK(rep.completed);
    CHECK(model_q(sc, 0)[0] == 0);
    CHECK(model_qdot(sc, 0)[0] == 0);
    // A free ball dropped on the hanging bob: the bob is a static side for it (it bounces).
    Registry reg;
    reg.add("ball");
    RigidInit s;
    s.position = {0, -0.9, 0};
    s.velocity = {0, -1, 0};
    Scene sc2 = make_scene(reg, {RigidBody::solid_sphere(1, 0.05)}, {s}, {ModelInstance{"pend", bob_pendulum::system(P)}},
                           contact_cache_fields());
    Stepper st2(NumericWorkflow::run(contact_rule(sc2, {}, elastic(1), {})));
    st2.step(sc2.world, 1e-3);
    CHECK(velocity(sc2.world, 0).y() == Approx(1).margin(1e-12));
    CHECK(model_qdot(sc2, 0)[0] == 0);
}

// Bugs caught: a model rule whose domain misses its proxies or coordinates (par with the contact
// rule would be accepted and race), two instances sharing components.
TEST_CASE("scene domains: par refuses what overlaps, names are checked", "[scene][guards]") {
    Scene sc = make_scene(Registry{}, {}, {},
                          {ModelInstance{"a", bob_pendulum::system({})}, ModelInstance{"b", bob_pendulum::system({})}});
    using W = NumericWorkflow;
    CHECK_NOTHROW(W::par(W::run(model_rule(sc, 0)), W::run(model_rule(sc, 1))));
    CHECK_THROWS_AS(W::par(W::run(model_rule(sc, 0)), W::run(contact_rule(sc, {}, elastic(1), {}))), DomainOverlapError);
    CHECK(sc.world.layout().components.find("a.th").has_value());
    CHECK(sc.world.layout().components.find("b.bob").has_value());
    CHECK_THROWS_AS(make_scene(Registry{}, {}, {}, {ModelInstance{"a", bob_pendulum::system({})},
                                                    ModelInstance{"a", bob_pendulum::system({})}}),
                    std::invalid_argument);
    bob_pendulum::Parameters bad;
    bad.r = -0.1;
    CHECK_THROWS_WITH(make_scene(Registry{}, {}, {}, {ModelInstance{"a", bob_pendulum::system(bad)}}),
                      Catch::Contains("radius") && Catch::Contains("'bob'"));
}

// Bugs caught: a par branch of the scene step that reads what another writes (threads would
// race), scratch shared between model instances, an order that depends on the thread count.
TEST_CASE("scenes are bit-identical on 1, 2 and 4 threads", "[scene][determinism]") {
    auto run = [](unsigned threads) {
        Registry reg;
        std::vector<RigidInit> init;
        for (int i = 0; i < 12; ++i) {
            reg.add("ball" + std::to_string(i));
            RigidInit s;
            s.position = {-0.6 + 0.11 * i, 0.06 + 0.2 * (i % 3), 0.01 * (i % 2)};
            init.push_back(s);
        }
        std::vector<ModelInstance> models;
        for (int k = 0; k < 3; ++k) {
            bob_pendulum::Parameters P;
            P.px = -0.5 + 0.5 * k;
            P.py = 1.2;
            P.m = 1 + k;
            models.push_back({"p" + std::to_string(k), bob_pendulum::system(P)});
        }
        Scene sc = make_scene(reg, std::vector<RigidBody>(12, RigidBody::solid_sphere(0.3, 0.05)), init, std::move(models),
                              contact_cache_fields());
        for (std::size_t k = 0; k < 3; ++k) {
            const double q[1] = {1.2 - 0.3 * static_cast<double>(k)}, qd[1] = {0};
            set_model_state(sc, k, q, qd);
        }
        Executor ex(threads);
        Stepper st(scene_step(sc, Force3D::gravity(g), {Plane::ground()}, {restitution_curve(0.5, 0.1), constant_curve(0.4)}, {}),
                   threads > 1 ? &ex : nullptr);
        st.run(sc.world, 1e-3, 1500);
        return sc.world.hash();
    };
    const auto h1 = run(1);
    CHECK(run(2) == h1);
    CHECK(run(4) == h1);
}

// Bugs caught: an impact between two model spheres resolved with the wrong effective masses (the
// motion would not pass whole down the row: two balls would leave), restitution passes that stop
// after one contact, a model stepped before its impulses (hand-overs a step late and drifting).
// Tolerance: an impact is resolved at the start of the step in which the bobs come to touch, up
// to dt early, so hand-over k lies within (k + 1) dt of the analytic time.
TEST_CASE("Newton's cradle of five .lag pendulums hands over at T/4 + k T/2, like the rigid row", "[scene][physics]") {
    const int n = 5;
    const double r = 0.05, th0 = -0.5, dt = 1e-3;
    std::vector<ModelInstance> models;
    for (int i = 0; i < n; ++i) {
        bob_pendulum::Parameters P;
        P.r = r, P.px = 2 * r * i;
        models.push_back({"p" + std::to_string(i), bob_pendulum::system(P)});
    }
    Scene sc = make_scene(Registry{}, {}, {}, std::move(models), contact_cache_fields());
    const double q0[1] = {th0}, v0[1] = {0};
    set_model_state(sc, 0, q0, v0);
    Stepper st(scene_step(sc, Force3D{}, {}, elastic(1), {}));
    double a = 1, b = std::sqrt(1 - std::pow(std::sin(std::abs(th0) / 2), 2)); // K(k) by the AGM
    for (int i = 0; i < 30; ++i) {
        const double an = (a + b) / 2;
        b = std::sqrt(a * b);
        a = an;
    }
    const double T = 4 * std::sqrt(1 / g) * M_PI / (2 * a);
    const double w_max = std::sqrt(2 * g * (1 - std::cos(th0)));
    std::vector<int> who;
    std::vector<double> when;
    int prev = 0;
    for (int s = 1; s <= 3700; ++s) {
        st.step(sc.world, dt);
        int moving = -1, count = 0;
        for (std::size_t i = 0; i < n; ++i)
            if (std::abs(model_qdot(sc, i)[0]) > 0.01 * w_max || std::abs(model_q(sc, i)[0]) > 0.01) {
                moving = static_cast<int>(i);
                ++count;
            }
        CHECK(count <= 1); // one bob swings at a time (the middle ones stay put)
        if (moving >= 0 && moving != prev) {
            who.push_back(moving);
            when.push_back(s * dt);
            prev = moving;
        }
    }
    CAPTURE(who, when);
    REQUIRE(who.size() == 4);
    CHECK(who == std::vector<int>{4, 0, 4, 0}); // the rigid row's sequence (test_contacts: cradle)
    for (std::size_t k = 0; k < 4; ++k) {
        CAPTURE(k, when[k]);
        CHECK(std::abs(when[k] - (T / 4 + static_cast<double>(k) * T / 2)) <= (static_cast<double>(k) + 1) * dt);
    }
    // The swing keeps its amplitude: the first bob, swinging again, reaches θ0 (energy through 4 impacts).
    double top = 0;
    for (int s = 0; s < 600; ++s) {
        st.step(sc.world, dt);
        top = std::max(top, std::abs(model_q(sc, 0)[0]));
    }
    CHECK(top == Approx(std::abs(th0)).epsilon(1e-3));
}

namespace {

/// A model ball (planar_ball: m = 1, r = 0.1) at rest at the origin and a rigid sphere (m2,
/// r2) touching it along the direction n, moving with velocity v.
Scene ball_struck(double m2, double r2, const Eigen::Vector3d& n, const Eigen::Vector3d& v, double gap = 0) {
    Registry reg;
    reg.add("rigid");
    RigidInit s;
    s.position = (0.1 + r2 + gap) * n;
    s.velocity = v;
    Scene sc = make_scene(reg, {RigidBody::solid_sphere(m2, r2)}, {s}, {ModelInstance{"b", planar_ball::system({})}},
                          contact_cache_fields());
    const double q[2] = {0, 0}, qd[2] = {0, 0};
    set_model_state(sc, 0, q, qd);
    return sc;
}

} // namespace

// Bugs caught: the friction impulse on a rigid body struck by a model's sphere applied without
// its lever (no spin), with the lever from the wrong centre or of the wrong sign; friction not
// limited by Coulomb's law there; momentum or restitution wrong in an oblique frictional
// model–rigid impact. The oracles: linear momentum; the rigid ball's angular momentum about
// the contact point (every impulse acts there: I ω + (c − p) × m v is unchanged); Newton's law
// of restitution along n; |J_t| = μ J_n while it slides (the tangential speed 4 m/s is more
// than the friction impulse can stop: that needs 4 / (1/m1 + 3.5/m2) = 0.667 N s against
// μ J_n = 0.264 N s).
TEST_CASE("a rigid ball striking a model's sphere obliquely with friction: momentum, spin about the contact, Coulomb",
          "[scene][physics]") {
    const double m1 = 1, m2 = 0.7, r2 = 0.05, e = 0.6, mu = 0.2, a = 0.3;
    const Eigen::Vector3d n{std::cos(a), std::sin(a), 0}, t{-std::sin(a), std::cos(a), 0};
    const Eigen::Vector3d v0 = -2.0 * n + 4.0 * t;
    for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
        CAPTURE(scheme == ContactScheme::jacobi);
        Scene sc = ball_struck(m2, r2, n, v0);
        const Eigen::Vector3d p = position(sc.world, 0);
        ContactOptions o;
        o.scheme = scheme;
        contacts_once(sc, ContactMaterial{constant_curve(e), constant_curve(mu)}, 1e-3, o);
        const auto qd = model_qdot(sc, 0);
        const Eigen::Vector3d v1{qd[0], qd[1], 0}, v2 = velocity(sc.world, 0), w2 = angular_velocity(sc.world, 0);
        const Eigen::Vector3d J = m2 * (v2 - v0); // the impulse on the rigid ball; the model takes −J
        // momentum
        CHECK((m1 * v1 + m2 * v2 - m2 * v0).norm() < 1e-12);
        // restitution along n: approach 2 m/s, separation 0.6 × 2
        CHECK((v2 - v1).dot(n) == Approx(e * 2.0).margin(1e-12));
        // sliding: the tangential impulse is μ times the normal one, against the slip
        CHECK(J.dot(n) > 0);
        CHECK(J.dot(t) == Approx(-mu * J.dot(n)).margin(1e-12));
        // the lever: spin about z from the friction impulse at the contact point c = p − r2 n,
        // and the angular momentum about c conserved
        const double I = 0.4 * m2 * r2 * r2;
        const Eigen::Vector3d c = p - r2 * n;
        CHECK(w2.z() == Approx(((c - p).cross(J)).z() / I).margin(1e-9));
        CHECK(std::fabs(w2.z()) > 1);
        CHECK((I * w2 + (p - c).cross(m2 * v2) - (p - c).cross(m2 * v0)).norm() < 1e-12);
    }
}

// Bugs caught: the position correction of a rigid–model overlap pushing the wrong way, along
// the wrong direction, moving one side only, or split by mass instead of inverse mass (only
// the ground's side was ever corrected in a test). The oracle: the rigid pair's law
// (test_contacts): depth → slop + (depth − slop)(1 − β)^passes, each side moving along n by
// its share of the inverse masses, the centre of mass fixed; the model's effective mass along
// n is m1 (a free point).
TEST_CASE("a deep overlap of a rigid sphere and a model's sphere is corrected along the normal by inverse mass",
          "[scene][physics]") {
    const double m1 = 1, m2 = 3, r2 = 0.1, depth = 0.05, a = 0.7;
    const Eigen::Vector3d n{std::cos(a), std::sin(a), 0};
    Scene sc = ball_struck(m2, r2, n, Eigen::Vector3d::Zero(), -depth);
    const Eigen::Vector3d p0 = position(sc.world, 0);
    ContactOptions o;
    contacts_once(sc, ContactMaterial{constant_curve(0), constant_curve(0.5)}, 1e-3, o);
    const double left = o.slop + (depth - o.slop) * std::pow(1 - o.baumgarte, o.position_iterations);
    const double moved = depth - left, w1 = (1 / m1) / (1 / m1 + 1 / m2);
    const auto q = model_q(sc, 0);
    const Eigen::Vector3d d1{q[0], q[1], 0}, d2 = position(sc.world, 0) - p0;
    CHECK((d1 + w1 * moved * n).norm() < 1e-15);
    CHECK((d2 - (1 - w1) * moved * n).norm() < 1e-15);
    CHECK((m1 * d1 + m2 * d2).norm() < 1e-15);
    CHECK(velocity(sc.world, 0).norm() == 0);
    CHECK(model_qdot(sc, 0)[0] == 0);
    CHECK(model_qdot(sc, 0)[1] == 0);
}

// Bugs caught: a wrong coupling solve for a model with several constraints in contact (G
// transposed, the projection P = I − M⁻¹Gᵀ(GM⁻¹Gᵀ)⁻¹G built from one row, M⁻¹ left out): with one
// constraint a transposed G gives the same numbers, with two it does not. The oracle: the
// model's change of velocity must be the saddle-point solution of
//     M Δq' − Gᵀ μ = −J_sᵀ J,   G Δq' = 0
// for the impulse J the rigid ball received (solved here by Eigen's LU), and the velocity
// constraints must still hold.
TEST_CASE("a two-constraint mechanism struck by a rigid ball responds as the KKT system says", "[scene][physics]") {
    const double a1 = 0.4, a2 = -0.3, mb = 0.8, rb = 0.05, e = 0.7;
    for (const double mu : {0.0, 0.3}) {
        CAPTURE(mu);
        double_bob::Parameters P;
        Registry reg;
        reg.add("ball");
        const std::vector<double> q0{std::sin(a1), -std::cos(a1), std::sin(a1) + std::sin(a2),
                                     -std::cos(a1) - std::cos(a2)};
        const Eigen::Vector3d bob{q0[2], q0[3], 0};
        const double a = 2.2; // the ball comes from the upper left of the lower bob
        const Eigen::Vector3d n{std::cos(a), std::sin(a), 0}, t{-std::sin(a), std::cos(a), 0};
        RigidInit s;
        s.position = bob + (P.r + rb) * n;
        s.velocity = -3.0 * n + 0.5 * t;
        Scene sc = make_scene(reg, {RigidBody::solid_sphere(mb, rb)}, {s}, {ModelInstance{"dp", double_bob::system(P)}},
                              contact_cache_fields());
        const std::vector<double> qd0(4, 0.0);
        set_model_state(sc, 0, q0, qd0);
        contacts_once(sc, ContactMaterial{constant_curve(e), constant_curve(mu)});
        const Eigen::Vector3d J = mb * (velocity(sc.world, 0) - s.velocity);
        CHECK(J.norm() > 0.5); // it was struck
        const LagrangianSystem sys = double_bob::system(P);
        std::vector<double> M(16), G(8), Js(12);
        sys.mass_matrix(0, q0, qd0, M);
        sys.constraint_matrix(0, q0, G);
        sys.sphere_jacobians(0, q0, Js);
        Eigen::MatrixXd K = Eigen::MatrixXd::Zero(6, 6);
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(6);
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) K(i, j) = M[static_cast<std::size_t>(i * 4 + j)];
            for (int k = 0; k < 2; ++k) K(i, 4 + k) = K(4 + k, i) = G[static_cast<std::size_t>(k * 4 + i)];
            for (int c = 0; c < 3; ++c) rhs(i) -= Js[static_cast<std::size_t>(c * 4 + i)] * J(c);
        }
        const Eigen::VectorXd x = K.fullPivLu().solve(rhs);
        const auto qd = model_qdot(sc, 0);
        for (int i = 0; i < 4; ++i) {
            CAPTURE(i);
            CHECK(qd[static_cast<std::size_t>(i)] == Approx(x(i)).margin(1e-12));
        }
        for (int k = 0; k < 2; ++k) {
            double v = 0;
            for (int i = 0; i < 4; ++i) v += G[static_cast<std::size_t>(k * 4 + i)] * qd[static_cast<std::size_t>(i)];
            CHECK(std::fabs(v) < 1e-12);
        }
        // the impact law at the bob: separation e × approach along n — exactly without
        // friction; with it, the bob's coupled normal and tangential responses (the constraints
        // make J_s B_s non-diagonal) leave the iterated solve 0.7% short (seen), bounded at 2%
        Eigen::Vector3d vbob = Eigen::Vector3d::Zero();
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 4; ++i) vbob(c) += Js[static_cast<std::size_t>(c * 4 + i)] * qd[static_cast<std::size_t>(i)];
        const double separation = (velocity(sc.world, 0) - vbob).dot(n);
        if (mu == 0) CHECK(separation == Approx(-e * s.velocity.dot(n)).margin(1e-12));
        else CHECK(separation == Approx(-e * s.velocity.dot(n)).epsilon(0.02));
    }
}
