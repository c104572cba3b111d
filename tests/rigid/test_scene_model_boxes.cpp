// Model boxes in scenes (docs/language.md, *Shapes*): a `.lag` box is side b of point rows; a
// contact at the lever arm r from its centre acts on the model through the wrench (P, r × P),
// its generalised inverse mass gᵀ (G M⁻¹ Gᵀ) g with g = (u, r × u) and G its centre's and spin's
// Jacobian. The oracles are textbook impacts (a plate swinging about a pivot struck at d has
// the effective mass I/d²; a free plate struck off-centre 1/(1/m + b²/I)), momentum and
// angular momentum, and a plate that lands and lies flat.
#include "free_plate.hpp"
#include "free_rod.hpp"
#include "paddle.hpp"
#include "planar_ball.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <tuple>

using namespace phynjo::runtime;

namespace {

ContactMaterial elastic(double e, double mu = 0) { return ContactMaterial{constant_curve(e), constant_curve(mu)}; }

/// One rigid ball of mass m2 and radius rb at `at` with velocity v, and one model instance.
Scene ball_and(LagrangianSystem model, double m2, double rb, const Eigen::Vector3d& at, const Eigen::Vector3d& v) {
    Registry reg;
    reg.add("ball");
    RigidInit s;
    s.position = at;
    s.velocity = v;
    return make_scene(reg, {RigidBody::solid_sphere(m2, rb)}, {s}, {ModelInstance{"m", std::move(model)}},
                      contact_cache_fields());
}

/// Model instances alone (no rigid bodies), with the warm-start cache.
Scene models_only(std::vector<ModelInstance> models) {
    return make_scene(Registry{}, {}, {}, std::move(models), contact_cache_fields());
}

void contacts_once(Scene& sc, ContactMaterial mat, ContactOptions options = {}) {
    Stepper st(NumericWorkflow::run(contact_rule(sc, {}, std::move(mat), options)));
    st.step(sc.world, 1e-3);
}

} // namespace

// Bugs caught: the box's spin left out of its contact point's velocity (J_ω unused: the face
// point would move with the centre, ω l/2, instead of ω d), the wrench's moment r × P dropped
// (the effective mass of the centre, not I/d²), the impulse not reaching q', restitution
// skipped for a model box.
TEST_CASE("a paddle striking a ball at a distance d from its pivot: effective mass I/d²", "[scene][box][physics]") {
    for (const auto& [d, m2, e] : {std::tuple{0.6, 1.0, 1.0}, std::tuple{0.3, 0.2, 0.5}, std::tuple{0.9, 2.0, 0.8},
                                   std::tuple{0.5, 0.5, 0.0}}) {
        for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
            CAPTURE(d, m2, e, scheme == ContactScheme::jacobi);
            paddle::Parameters P; // m = 1, l = 1, w = 0.05
            const double om = 2.0, rb = 0.04, I = P.m * (P.l * P.l + P.w * P.w) / 3;
            Scene sc = ball_and(paddle::system(P), m2, rb, {P.w + rb - 1e-6, -d, 0}, {0, 0, 0});
            const double q[1] = {0}, qd[1] = {om};
            set_model_state(sc, 0, q, qd);
            ContactOptions o;
            o.scheme = scheme;
            contacts_once(sc, elastic(e), o);
            const double meff = I / (d * d), v = om * d;
            const double v1 = (meff - e * m2) * v / (meff + m2), v2 = (1 + e) * meff * v / (meff + m2);
            CHECK(model_qdot(sc, 0)[0] * d == Approx(v1).margin(1e-9));
            CHECK(velocity(sc.world, 0).x() == Approx(v2).margin(1e-9));
            CHECK(std::abs(velocity(sc.world, 0).y()) < 1e-9);
            // angular momentum about the pivot: I θ' + (p × m2 v)_z
            const Eigen::Vector3d p = position(sc.world, 0), u = velocity(sc.world, 0);
            CHECK(I * model_qdot(sc, 0)[0] + m2 * (p.x() * u.y() - p.y() * u.x()) == Approx(I * om).epsilon(1e-9));
        }
    }
}

// Bugs caught: the lever arm measured from the wrong point (the pivot, or a corner), the
// wrench's moment with the wrong sign (the plate spun the wrong way), the box's spin Jacobian
// columns of another coordinate.
TEST_CASE("a ball striking a free plate off-centre: 1/m_eff = 1/m + b²/I, momentum and angular momentum", "[scene][box][physics]") {
    for (const auto& [b, m2, e] : {std::tuple{0.2, 1.0, 1.0}, std::tuple{-0.15, 0.4, 0.6}, std::tuple{0.25, 3.0, 1.0},
                                   std::tuple{0.0, 1.0, 0.3}}) {
        CAPTURE(b, m2, e);
        free_plate::Parameters P; // m = 1, a = 0.3, b = 0.1 (half extents), no gravity
        const double rb = 0.05, I = P.m * (P.a * P.a + P.b * P.b) / 3, v = 1.5;
        // the ball below the plate's lower face (y = −b), at x = b along it, rising at v
        Scene sc = ball_and(free_plate::system(P), m2, rb, {b, -P.b - rb + 1e-6, 0}, {0, v, 0});
        contacts_once(sc, elastic(e));
        const double meff = 1 / (1 / P.m + b * b / I);
        const double u1 = (1 + e) * m2 * v / (meff + m2), u2 = (m2 - e * meff) * v / (meff + m2); // the face point's, the ball's
        const std::vector<double> qd = model_qdot(sc, 0);
        const double face = qd[1] + qd[2] * b; // the struck point's vertical speed: y' + ph' b
        CHECK(face == Approx(u1).margin(1e-9));
        CHECK(velocity(sc.world, 0).y() == Approx(u2).margin(1e-9));
        CHECK(P.m * qd[1] + m2 * velocity(sc.world, 0).y() == Approx(m2 * v).epsilon(1e-9)); // momentum
        CHECK(std::abs(qd[0]) < 1e-9);
        // angular momentum about the origin: I ph' + (p × m2 u)_z (the plate's centre at the origin)
        const Eigen::Vector3d p = position(sc.world, 0), u = velocity(sc.world, 0);
        CHECK(I * qd[2] + m2 * (p.x() * u.y() - p.y() * u.x()) == Approx(m2 * b * v).margin(1e-9));
    }
}

// Bugs caught: the plane's rows of a model box missing or with the normal reversed (it falls
// through), the anchors of the box's points kept in the world frame while it turns (the
// corrections would push at stale points: it would not come to lie flat), energy from the
// contacts.
TEST_CASE("a plate dropped tilted onto the ground lands and lies flat, at rest, without sinking", "[scene][box][physics]") {
    free_plate::Parameters P;
    P.g = 9.81;
    Scene sc = make_scene(Registry{}, {}, {}, {ModelInstance{"plate", free_plate::system(P)}}, contact_cache_fields());
    const double q[3] = {0, 0.6, 0.4}, qd[3] = {0, 0, 0};
    set_model_state(sc, 0, q, qd);
    // restitution below 5 cm/s off, as for resting rigid boxes (a constant e would bounce it by
    // e g dt every step, and a bouncing contact carries no load for friction)
    Stepper st(scene_step(sc, Force3D{}, {Plane::ground()}, ContactMaterial{restitution_curve(0.2, 0.05), constant_curve(0.5)}, {}));
    const double e0 = scene_energy(sc);
    double highest = e0, lowest = 1e9;
    for (int k = 0; k < 4000; ++k) {
        st.step(sc.world, 1e-3);
        const std::vector<double> x = model_q(sc, 0);
        // the lowest corner's height: y − a |sin ph| − b |cos ph|
        const double low = x[1] - P.a * std::abs(std::sin(x[2])) - P.b * std::abs(std::cos(x[2]));
        lowest = std::min(lowest, low);
        highest = std::max(highest, scene_energy(sc));
    }
    const std::vector<double> x = model_q(sc, 0), v = model_qdot(sc, 0);
    CHECK(highest <= e0 + 1e-9);             // no energy from the contacts
    CHECK(lowest > -2e-3);                   // it never sank more than 2 mm
    CHECK(x[1] == Approx(P.b).margin(5e-4)); // lying on its long face
    CHECK(std::abs(std::sin(x[2])) < 1e-3);
    CHECK(std::abs(v[0]) + std::abs(v[1]) + std::abs(v[2]) < 0.02);
    for (int k = 0; k < 1000; ++k) st.step(sc.world, 1e-3);
    const std::vector<double> y = model_q(sc, 0);
    CHECK(std::abs(y[0] - x[0]) < 1e-4); // no creep
    CHECK(std::abs(y[1] - x[1]) < 1e-4);
    CHECK(std::abs(y[2] - x[2]) < 1e-4);
}

// Bugs caught: model box–rigid box pairs missing (the box passes through the plate), the
// manifold's sides swapped (the normal pulling them together), a model box's impulse applied
// to the wrong end of its row.
TEST_CASE("a rigid box striking a free plate face-on: separation e × approach, momentum kept", "[scene][box][physics]") {
    for (const double e : {1.0, 0.5, 0.0}) {
        CAPTURE(e);
        free_plate::Parameters P; // m = 1, half extents 0.3 × 0.1 × 0.2, no gravity
        const double m2 = 2.0, h = 0.1, v = 1.2;
        Registry reg;
        reg.add("box");
        RigidInit s;
        s.position = {0, P.b + h - 1e-6, 0}; // on the plate's upper face, centred: no turn
        s.velocity = {0, -v, 0};
        Scene sc = make_scene(reg, {RigidBody::solid_box(m2, {h, h, h})}, {s}, {ModelInstance{"m", free_plate::system(P)}},
                              contact_cache_fields());
        contacts_once(sc, elastic(e));
        const std::vector<double> qd = model_qdot(sc, 0);
        const double u = velocity(sc.world, 0).y();
        CHECK(P.m * qd[1] + m2 * u == Approx(-m2 * v).epsilon(1e-9));      // momentum
        CHECK(u - qd[1] == Approx(e * v).margin(1e-9));                    // separation = e × approach
        CHECK(std::abs(qd[2]) < 1e-9);                                     // struck at the centre: no spin
        CHECK(angular_velocity(sc.world, 0).norm() < 1e-9);
    }
}

// Bugs caught: a model box's rows depending on the thread count, a box's contacts computed from
// another model's coordinates.
TEST_CASE("model boxes: two plates and a box falling together, bit-identical on 1 and 4 threads", "[scene][box][determinism]") {
    auto run = [](unsigned threads) {
        free_plate::Parameters P;
        P.g = 9.81;
        Registry reg;
        reg.add("box");
        RigidInit s;
        s.position = {0.1, 1.0, 0};
        s.orientation = Quaternion{std::cos(0.2), 0, 0, std::sin(0.2)};
        Scene sc = make_scene(reg, {RigidBody::solid_box(1, {0.1, 0.1, 0.1})}, {s},
                              {ModelInstance{"a", free_plate::system(P)}, ModelInstance{"b", free_plate::system(P)}},
                              contact_cache_fields());
        const double qa[3] = {0, 0.3, 0.2}, qb[3] = {0.5, 0.7, -0.3}, z[3] = {0, 0, 0};
        set_model_state(sc, 0, qa, z);
        set_model_state(sc, 1, qb, z);
        Executor ex(threads);
        Stepper st(scene_step(sc, Force3D::gravity(9.81), {Plane::ground()},
                              ContactMaterial{restitution_curve(0.3, 0.05), constant_curve(0.5)}, {}),
                   threads > 1 ? &ex : nullptr);
        st.run(sc.world, 1e-3, 1500);
        return std::tuple{sc.world.hash(), model_q(sc, 0), model_q(sc, 1), position(sc.world, 0)};
    };
    const auto one = run(1), four = run(4);
    CHECK(std::get<0>(one) == std::get<0>(four));
    const std::vector<double> a = std::get<1>(one), b = std::get<2>(one);
    CHECK(a[1] > 0.05); // both plates ended above the ground (their half height is 0.1 m)
    CHECK(b[1] > 0.05);
    CHECK(std::get<3>(one).y() > 0.05);
}

// Bugs caught: a model box's anchors kept in the world frame (right only while it is not
// turned: standing on its short face, its contact points would be taken a quarter turn away),
// a box's half extents read in the wrong order; make_scene accepting a box it cannot place.
TEST_CASE("a plate standing on its short face stays standing, at its height", "[scene][box][physics]") {
    free_plate::Parameters P;
    P.g = 9.81;
    Scene sc = make_scene(Registry{}, {}, {}, {ModelInstance{"plate", free_plate::system(P)}}, contact_cache_fields());
    const double half_pi = 2 * std::atan(1.0);
    const double q[3] = {0, P.a + 1e-3, half_pi}, qd[3] = {0, 0, 0};
    set_model_state(sc, 0, q, qd);
    Stepper st(scene_step(sc, Force3D{}, {Plane::ground()}, ContactMaterial{restitution_curve(0.2, 0.05), constant_curve(0.5)}, {}));
    double lowest = 1e9;
    for (int k = 0; k < 3000; ++k) {
        st.step(sc.world, 1e-3);
        lowest = std::min(lowest, model_q(sc, 0)[1] - P.a);
    }
    const std::vector<double> x = model_q(sc, 0);
    CHECK(lowest > -1e-3);                   // never sank a millimetre
    CHECK(x[1] == Approx(P.a).margin(5e-4)); // on the face of width 2b, its long side up
    CHECK(x[2] == Approx(half_pi).margin(1e-3));
    CHECK(std::abs(x[0]) < 1e-4);
    P.b = -0.1;
    CHECK_THROWS_WITH(make_scene(Registry{}, {}, {}, {ModelInstance{"plate", free_plate::system(P)}}),
                      Catch::Contains("box 'plate' of model 'plate' has half extent -0.1"));
}

// Other instances' shapes against a model box: both sides of a row are models, the impulse
// reaches each through its own B (a box's as the wrench (P, r × P)).

// Bugs caught: model box–model box pairs missing (the plates pass through each other), the
// impulse applied to one side only or with the same sign on both (momentum not kept), side a's
// wrench left out of the block (its K share, or its velocity change), the face's points solved
// one by one (an uneven push that turns the plates).
TEST_CASE("a free plate striking another face-on: separation e × approach, momentum kept, no turn", "[scene][box][physics]") {
    for (const bool upper_first : {true, false}) { // the striking plate as side a, then as side b
        for (const double e : {1.0, 0.5, 0.0}) {
            CAPTURE(upper_first, e);
            free_plate::Parameters P; // m = 1, half extents 0.3 × 0.1 × 0.2, no gravity
            const double v = 1.3;
            Scene sc = models_only({ModelInstance{"p", free_plate::system(P)}, ModelInstance{"q", free_plate::system(P)}});
            const std::size_t up = upper_first ? 0 : 1, low = 1 - up;
            const double qu[3] = {0, 2 * P.b - 1e-6, 0}, vu[3] = {0, -v, 0}, ql[3] = {0, 0, 0}, vl[3] = {0, 0, 0};
            set_model_state(sc, up, qu, vu);
            set_model_state(sc, low, ql, vl);
            contacts_once(sc, elastic(e));
            const std::vector<double> a = model_qdot(sc, up), b = model_qdot(sc, low);
            CHECK(a[1] + b[1] == Approx(-v).epsilon(1e-9)); // momentum (equal masses)
            CHECK(a[1] - b[1] == Approx(e * v).margin(1e-9)); // separation = e × approach
            CHECK(std::abs(a[2]) + std::abs(b[2]) < 1e-9);  // struck face on: no turn
            CHECK(std::abs(a[0]) + std::abs(b[0]) < 1e-9);
        }
    }
}

// Bugs caught: a model rod's (capsule's) rows against a model box missing, its contact point
// taken at the wrong fraction s (another lever arm: the rod's spin and the plate's push would
// differ from the two-body impact), side a's impulse at its point not reaching its model.
TEST_CASE("a model rod's end striking a model plate off-centre: the two-body impact of their effective masses", "[scene][box][capsule][physics]") {
    for (const auto& [ph, bx, e] : {std::tuple{-0.3, 0.1, 1.0}, std::tuple{-0.6, -0.2, 0.5}, std::tuple{-0.2, 0.0, 0.0}}) {
        CAPTURE(ph, bx, e);
        free_plate::Parameters P; // m = 1, a = 0.3, b = 0.1
        free_rod::Parameters R;   // m = 1, l = 1, r = 0.05, along ph from x
        const double v = 0.8, Ip = P.m * (P.a * P.a + P.b * P.b) / 3, Ir = R.m * R.l * R.l / 12;
        const double cx = R.l / 2 * std::cos(ph), cy = R.l / 2 * std::sin(ph); // its lower end at (x + cx, y + cy)
        Scene sc = models_only({ModelInstance{"plate", free_plate::system(P)}, ModelInstance{"rod", free_rod::system(R)}});
        const double qp[3] = {0, 0, 0}, z[3] = {0, 0, 0};
        const double qr[3] = {bx - cx, P.b + R.r - 1e-7 - cy, ph}, vr[3] = {0, -v, 0};
        set_model_state(sc, 0, qp, z);
        set_model_state(sc, 1, qr, vr);
        contacts_once(sc, elastic(e));
        // K = 1/m_r + cx²/I_r + 1/m_p + bx²/I_p along y; impulse P = (1 + e) v / K
        const double K = 1 / R.m + cx * cx / Ir + 1 / P.m + bx * bx / Ip, J = (1 + e) * v / K;
        const std::vector<double> p = model_qdot(sc, 0), r = model_qdot(sc, 1);
        CHECK(r[1] == Approx(-v + J / R.m).margin(1e-9));
        CHECK(r[2] == Approx(cx * J / Ir).margin(1e-9));
        CHECK(p[1] == Approx(-J / P.m).margin(1e-9));
        CHECK(p[2] == Approx(-bx * J / Ip).margin(1e-9));
        CHECK(std::abs(p[0]) + std::abs(r[0]) < 1e-9); // frictionless: nothing along x
    }
}

// Bugs caught: a model sphere's rows against another model's box missing or its normal
// reversed, the sphere's impulse reaching the plate at the wrong lever arm.
TEST_CASE("a model ball striking a model plate off-centre: 1/m_eff = 1/m + b²/I, momentum and angular momentum", "[scene][box][physics]") {
    for (const auto& [bx, e] : {std::tuple{0.2, 1.0}, std::tuple{-0.1, 0.6}, std::tuple{0.0, 0.3}}) {
        CAPTURE(bx, e);
        free_plate::Parameters P;
        planar_ball::Parameters B; // m = 1, r = 0.1
        B.g = 0;
        const double v = 1.1, I = P.m * (P.a * P.a + P.b * P.b) / 3;
        Scene sc = models_only({ModelInstance{"ball", planar_ball::system(B)}, ModelInstance{"plate", free_plate::system(P)}});
        const double qb[2] = {bx, -P.b - B.r + 1e-7}, vb[2] = {0, v}, qp[3] = {0, 0, 0}, z[3] = {0, 0, 0};
        set_model_state(sc, 0, qb, vb);
        set_model_state(sc, 1, qp, z);
        contacts_once(sc, elastic(e));
        const double meff = 1 / (1 / P.m + bx * bx / I);
        const std::vector<double> ball = model_qdot(sc, 0), plate = model_qdot(sc, 1);
        CHECK(plate[1] + plate[2] * bx == Approx((1 + e) * B.m * v / (meff + B.m)).margin(1e-9)); // the struck point
        CHECK(ball[1] == Approx((B.m - e * meff) * v / (meff + B.m)).margin(1e-9));
        CHECK(P.m * plate[1] + B.m * ball[1] == Approx(B.m * v).epsilon(1e-9));
        CHECK(I * plate[2] + B.m * bx * ball[1] == Approx(B.m * bx * v).margin(1e-9)); // about the origin
    }
}

// Bugs caught: resting contacts between two models' boxes sinking (the position correction
// applied to one side only, or through the wrong lever arm), a model ball resting on a model
// plate falling through it, the rows of models' boxes not warm-started (the stack creeps
// sideways, about 1 mm/s: ten passes from nothing a step leave the off-centre load unbalanced)
// or their cache keys colliding.
TEST_CASE("a plate resting on a plate on the ground, and a ball on top: a stack of models stands", "[scene][box][physics]") {
    free_plate::Parameters P;
    P.g = 9.81;
    planar_ball::Parameters B; // r = 0.1, g = 9.81
    Scene sc = models_only({ModelInstance{"low", free_plate::system(P)}, ModelInstance{"high", free_plate::system(P)},
                            ModelInstance{"ball", planar_ball::system(B)}});
    const double ql[3] = {0, P.b + 2e-3, 0.01}, qh[3] = {0.05, 3 * P.b + 8e-3, -0.02}, qb[2] = {0.1, 4 * P.b + B.r + 0.02};
    const double z[3] = {0, 0, 0};
    set_model_state(sc, 0, ql, z);
    set_model_state(sc, 1, qh, z);
    set_model_state(sc, 2, qb, std::vector{0.0, 0.0});
    Stepper st(scene_step(sc, Force3D{}, {Plane::ground()}, ContactMaterial{restitution_curve(0.2, 0.05), constant_curve(0.5)}, {}));
    double sink = 0;
    for (int k = 0; k < 4000; ++k) {
        st.step(sc.world, 1e-3);
        const std::vector<double> l = model_q(sc, 0), h = model_q(sc, 1), b = model_q(sc, 2);
        if (k > 500) { // settled: how far each sits below where it rests
            sink = std::max({sink, P.b - l[1], 3 * P.b - h[1], 4 * P.b + B.r - b[1]});
        }
    }
    const std::vector<double> l = model_q(sc, 0), h = model_q(sc, 1), b = model_q(sc, 2);
    CHECK(sink < 1e-3); // no layer sank a millimetre
    CHECK(l[1] == Approx(P.b).margin(5e-4));
    CHECK(h[1] == Approx(3 * P.b).margin(1e-3));
    CHECK(b[1] == Approx(4 * P.b + B.r).margin(1.5e-3));
    CHECK(std::abs(std::sin(l[2])) < 1e-3);
    CHECK(std::abs(std::sin(h[2])) < 1e-3);
    const std::vector<double> vl = model_qdot(sc, 0), vh = model_qdot(sc, 1), vb = model_qdot(sc, 2);
    CHECK(std::abs(vl[0]) + std::abs(vl[1]) + std::abs(vl[2]) + std::abs(vh[0]) + std::abs(vh[1]) + std::abs(vh[2]) < 0.03);
    CHECK(std::abs(vb[0]) + std::abs(vb[1]) < 0.03);
    for (int k = 0; k < 1000; ++k) st.step(sc.world, 1e-3);
    const std::vector<double> h2 = model_q(sc, 1), b2 = model_q(sc, 2);
    CHECK(std::abs(h2[0] - h[0]) < 2e-4); // no creep
    CHECK(std::abs(h2[1] - h[1]) < 1e-4);
    CHECK(std::abs(b2[0] - b[0]) < 2e-4);
}
