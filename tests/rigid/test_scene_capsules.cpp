// Model capsules in scenes, and model shapes against rigid boxes (docs/generated-code.md, *Models
// in the contact world*): a contact at a fraction s along a capsule acts on the model through
// J(s) = (1 − s) J₁ + s J₂. The oracles are textbook impacts: a rod pendulum struck at a
// distance d from its pivot has the effective mass I/d²; a free rod struck at b from its centre
// 1/(1/m + b²/I_c); and momentum, angular momentum and (e = 1) energy are conserved.
#include "bob_pendulum.hpp"
#include "free_rod.hpp"
#include "phynjo/runtime/runtime.hpp"
#include "rod_pendulum.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <tuple>

using namespace phynjo::runtime;

namespace {

ContactMaterial elastic(double e, double mu = 0) { return ContactMaterial{constant_curve(e), constant_curve(mu)}; }

/// One rigid body at `at` with velocity v, and one model instance.
Scene body_and(LagrangianSystem model, const RigidBody& body, const Eigen::Vector3d& at, const Eigen::Vector3d& v) {
    Registry reg;
    reg.add("body");
    RigidInit s;
    s.position = at;
    s.velocity = v;
    return make_scene(reg, {body}, {s}, {ModelInstance{"m", std::move(model)}}, contact_cache_fields());
}
/// One rigid ball of mass m2 and radius rb at `at` with velocity v, and one model instance.
Scene ball_and(LagrangianSystem model, double m2, double rb, const Eigen::Vector3d& at, const Eigen::Vector3d& v) {
    return body_and(std::move(model), RigidBody::solid_sphere(m2, rb), at, v);
}

void contacts_once(Scene& sc, ContactMaterial mat, ContactOptions options = {}) {
    Stepper st(NumericWorkflow::run(contact_rule(sc, {}, std::move(mat), options)));
    st.step(sc.world, 1e-3);
}

} // namespace

// Bugs caught: the capsule's point taken at an end instead of at s (the effective mass of the
// tip, m/3, for every d), the ends' weights swapped ((1 − s) for the far end), J(s)'s impulse
// not reaching q', restitution skipped for capsule rows, the contact not found mid-segment.
TEST_CASE("a rod pendulum striking a ball at a distance d from its pivot: effective mass I/d²", "[scene][capsule][physics]") {
    for (const auto& [d, m2, e] : {std::tuple{0.6, 1.0, 1.0}, std::tuple{0.3, 0.2, 0.5}, std::tuple{0.9, 2.0, 0.8},
                                   std::tuple{0.5, 0.5, 0.0}}) {
        for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
            CAPTURE(d, m2, e, scheme == ContactScheme::jacobi);
            rod_pendulum::Parameters P; // m = 1, l = 1, r = 0.05
            const double w = 2.0, rb = 0.04, I = P.m * P.l * P.l / 3;
            Scene sc = ball_and(rod_pendulum::system(P), m2, rb, {P.r + rb - 1e-6, -d, 0}, {0, 0, 0});
            const double q[1] = {0}, qd[1] = {w};
            set_model_state(sc, 0, q, qd);
            ContactOptions o;
            o.scheme = scheme;
            contacts_once(sc, elastic(e), o);
            const double meff = I / (d * d), v = w * d;
            const double v1 = (meff - e * m2) * v / (meff + m2), v2 = (1 + e) * meff * v / (meff + m2);
            CHECK(model_qdot(sc, 0)[0] * d == Approx(v1).margin(1e-9));
            CHECK(velocity(sc.world, 0).x() == Approx(v2).margin(1e-9));
            CHECK(std::abs(velocity(sc.world, 0).y()) < 1e-9);
            // angular momentum about the pivot: I θ' + (p × m2 v)_z
            const Eigen::Vector3d p = position(sc.world, 0), u = velocity(sc.world, 0);
            CHECK(I * model_qdot(sc, 0)[0] + m2 * (p.x() * u.y() - p.y() * u.x()) == Approx(I * w).epsilon(1e-9));
        }
    }
}

// Bugs caught: A(s)'s cross term 2 s (1 − s) sym A₁₂ dropped or counted once (the effective
// mass of a free rod is that of its centre and spin together, both ends moving), B(s) with
// one end's columns only, the second end's velocity not following an impulse (a second pass
// would see a wrong relative velocity).
TEST_CASE("a ball striking a free rod off-centre: 1/m_eff = 1/m + b²/I, momentum and angular momentum", "[scene][capsule][physics]") {
    for (const auto& [b, m2, e] : {std::tuple{0.3, 1.0, 1.0}, std::tuple{-0.15, 0.4, 0.6}, std::tuple{0.45, 3.0, 1.0},
                                   std::tuple{0.0, 1.0, 0.3}}) {
        CAPTURE(b, m2, e);
        free_rod::Parameters P; // m = 1, l = 1, r = 0.05, g = 0, lying along x
        const double u = 1.5, rb = 0.05, Ic = P.m * P.l * P.l / 12;
        Scene sc = ball_and(free_rod::system(P), m2, rb, {b, P.r + rb - 1e-6, 0}, {0, -u, 0});
        contacts_once(sc, elastic(e));
        const double meff = 1 / (1 / P.m + b * b / Ic);
        const double ball = (m2 - e * meff) * -u / (m2 + meff), point = (1 + e) * m2 * -u / (m2 + meff);
        const std::vector<double> v = model_qdot(sc, 0); // x', y', ph'
        const Eigen::Vector3d vb = velocity(sc.world, 0), pb = position(sc.world, 0);
        CHECK(vb.y() == Approx(ball).margin(1e-9));
        CHECK(v[1] + v[2] * b == Approx(point).margin(1e-9)); // the struck point's velocity
        CHECK(std::abs(v[0]) < 1e-12);
        CHECK(P.m * v[1] + m2 * vb.y() == Approx(-m2 * u).epsilon(1e-12));
        CHECK(Ic * v[2] + m2 * (pb.x() * vb.y() - pb.y() * vb.x()) == Approx(-m2 * u * b).margin(1e-12));
        if (e == 1.0)
            CHECK(0.5 * P.m * v[1] * v[1] + 0.5 * Ic * v[2] * v[2] + 0.5 * m2 * vb.squaredNorm() ==
                  Approx(0.5 * m2 * u * u).epsilon(1e-12));
    }
}

// Bugs caught: no rows between a capsule and a plane (the rod falls through), one end's row
// only (it tips over the other), a position correction not passed to the capsule's model, or
// the capsule's point of a row moved to the wrong end by the correction.
TEST_CASE("a rod dropped tilted onto the ground lands and lies flat, at rest, without sinking", "[scene][capsule][physics]") {
    free_rod::Parameters P;
    P.g = 9.81;
    Scene sc = make_scene(Registry{}, {}, {}, {ModelInstance{"rod", free_rod::system(P)}}, contact_cache_fields());
    const double q[3] = {0, 0.8, 0.4}, qd[3] = {0, 0, 0};
    set_model_state(sc, 0, q, qd);
    Stepper st(scene_step(sc, Force3D{}, {Plane::ground()}, elastic(0.2, 0.5), {}));
    const double e0 = scene_energy(sc);
    double highest = e0, lowest = 1e9;
    for (int k = 0; k < 4000; ++k) {
        st.step(sc.world, 1e-3);
        const std::vector<double> x = model_q(sc, 0);
        const double low = x[1] - 0.5 * P.l * std::abs(std::sin(x[2])) - P.r; // the lower end's clearance
        lowest = std::min(lowest, low);
        highest = std::max(highest, scene_energy(sc));
    }
    const std::vector<double> x = model_q(sc, 0), v = model_qdot(sc, 0);
    CHECK(highest <= e0 + 1e-9);                 // no energy from the contacts
    CHECK(lowest > -2e-3);                       // it never sank more than 2 mm
    CHECK(x[1] == Approx(P.r).margin(5e-4));     // lying on the ground, both ends down
    CHECK(std::abs(std::sin(x[2])) < 1e-3);
    CHECK(std::abs(v[0]) + std::abs(v[1]) + std::abs(v[2]) < 0.02);
    // and it stays: one more second changes nothing visible
    for (int k = 0; k < 1000; ++k) st.step(sc.world, 1e-3);
    const std::vector<double> y = model_q(sc, 0);
    CHECK(std::abs(y[0] - x[0]) < 1e-4);
    CHECK(std::abs(y[1] - x[1]) < 1e-4);
}

// Bugs caught: a capsule row between two shapes of one model (a model would push itself),
// capsule rows in the warm-start cache (their point moves along the segment), thread counts
// changing the bits.
TEST_CASE("capsule scenes: two rods and a ball, bit-identical on 1 and 4 threads", "[scene][capsule][determinism]") {
    struct End {
        std::uint64_t hash;
        double ya, yb, ball;
    };
    auto run = [](unsigned threads) {
        free_rod::Parameters P;
        P.g = 9.81;
        Registry reg;
        reg.add("ball");
        RigidInit s;
        s.position = {0.2, 1.2, 0};
        Scene sc = make_scene(reg, {RigidBody::solid_sphere(1, 0.1)}, {s},
                              {ModelInstance{"a", free_rod::system(P)}, ModelInstance{"b", free_rod::system(P)}},
                              contact_cache_fields());
        const double qa[3] = {0, 0.3, 0.2}, qb[3] = {0.3, 0.7, -0.5}, z[3] = {0, 0, 0};
        set_model_state(sc, 0, qa, z);
        set_model_state(sc, 1, qb, z);
        Executor ex(threads);
        Stepper st(scene_step(sc, Force3D::gravity(9.81), {Plane::ground()}, elastic(0.3, 0.4), {}),
                   threads > 1 ? &ex : nullptr);
        st.run(sc.world, 1e-3, 1500);
        return End{sc.world.hash(), model_q(sc, 0)[1], model_q(sc, 1)[1], position(sc.world, 0).y()};
    };
    const End one = run(1), four = run(4);
    CHECK(one.hash == four.hash);
    // the rods ended on the ground or one on the other, the ball on them or the ground: none sank
    CHECK(one.ya > 0.045);
    CHECK(one.yb > 0.045);
    CHECK(one.ball > 0.095);
}

// Bugs caught: a model sphere meeting a box refused or ignored (scenes of spheres only), the
// model side of a point row taken as a rigid body of no mass (a wall: the box would leave at
// (1 + e) v), the box turned by an impulse through its centre, the impulse on the model side
// with the wrong sign.
TEST_CASE("a pendulum bob striking a free box face-on: the textbook split, the box not turned", "[scene][capsule][box][physics]") {
    for (const auto& [m1, m2, e] : {std::tuple{1.0, 1.0, 1.0}, std::tuple{2.0, 0.5, 0.4}, std::tuple{0.5, 1.5, 0.0}}) {
        for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
            CAPTURE(m1, m2, e, scheme == ContactScheme::jacobi);
            bob_pendulum::Parameters P; // l = 1, r = 0.05, pivot at the origin
            P.m = m1;
            const double w = 1.5, h = 0.1;
            Scene sc = body_and(bob_pendulum::system(P), RigidBody::solid_box(m2, {h, h, h}), {P.r + h - 1e-6, -1, 0}, {0, 0, 0});
            const double q[1] = {0}, qd[1] = {w};
            set_model_state(sc, 0, q, qd);
            ContactOptions o;
            o.scheme = scheme;
            contacts_once(sc, elastic(e), o);
            const double v1 = (m1 - e * m2) * w / (m1 + m2), v2 = (1 + e) * m1 * w / (m1 + m2);
            CHECK(model_qdot(sc, 0)[0] == Approx(v1).margin(1e-9));
            CHECK(velocity(sc.world, 0).x() == Approx(v2).margin(1e-9));
            CHECK(angular_velocity(sc.world, 0).norm() < 1e-9);
        }
    }
}

// Bugs caught: a model capsule meeting a box refused or ignored, the point on the capsule at the
// wrong fraction (the effective mass I/(l cos θ)² of the tip), the surface offset of the model
// side lost (the row's separation and position correction off by the radius).
TEST_CASE("a rod pendulum's tip striking a free box: effective mass I/(l cos θ)², angular momentum", "[scene][capsule][box][physics]") {
    // θ > 0: the rod leans away from the box (its side clear of the box's face)
    for (const auto& [th, m2, e] : {std::tuple{0.3, 1.0, 1.0}, std::tuple{0.15, 0.4, 0.5}, std::tuple{0.5, 2.0, 0.0}}) {
        CAPTURE(th, m2, e);
        rod_pendulum::Parameters P; // m = 1, l = 1, r = 0.05
        const double w = 2.0, h = 0.1, I = P.m * P.l * P.l / 3, c = P.l * std::cos(th);
        const Eigen::Vector3d at{P.l * std::sin(th) + P.r + h - 1e-6, -c, 0};
        Scene sc = body_and(rod_pendulum::system(P), RigidBody::solid_box(m2, {h, 0.3, h}), at, {0, 0, 0});
        const double q[1] = {th}, qd[1] = {w};
        set_model_state(sc, 0, q, qd);
        contacts_once(sc, elastic(e));
        const double meff = I / (c * c), v = w * c;
        const double v1 = (meff - e * m2) * v / (meff + m2), v2 = (1 + e) * meff * v / (meff + m2);
        CHECK(model_qdot(sc, 0)[0] * c == Approx(v1).margin(1e-6));
        CHECK(velocity(sc.world, 0).x() == Approx(v2).margin(1e-6));
        CHECK(angular_velocity(sc.world, 0).norm() < 1e-6);
        CHECK(I * model_qdot(sc, 0)[0] + c * m2 * velocity(sc.world, 0).x() == Approx(I * w).epsilon(1e-12));
    }
}

// Bugs caught: position corrections between a model capsule and boxes that add energy or let
// the boxes sink, boxes knocked by a model that pass through it, a scene of boxes and models
// that is not bit-identical on 1 and 4 threads.
TEST_CASE("a rod pendulum knocks a stack of three boxes: energy only lost, nothing sinks, any thread count", "[scene][capsule][box][physics]") {
    struct End {
        std::uint64_t hash;
        double highest, e0, lowest;
        Eigen::Vector3d top;
    };
    auto run = [](unsigned threads) {
        const double h = 0.1, mb = 0.5;
        Registry reg;
        std::vector<RigidInit> init;
        for (int i = 0; i < 3; ++i) {
            reg.add("box" + std::to_string(i));
            RigidInit s;
            s.position = {0.45, -1.1 + h + 2 * h * i, 0}; // on a floor at y = −1.1, below the rod's reach
            init.push_back(s);
        }
        const rod_pendulum::Parameters P; // l = 1, pivot at the origin: released from horizontal
        std::vector<RigidBody> boxes(3, RigidBody::solid_box(mb, {h, h, h}));
        Scene sc = make_scene(reg, boxes, init, {ModelInstance{"rod", rod_pendulum::system(P)}}, contact_cache_fields());
        const double q[1] = {-1.5707963267948966}, qd[1] = {0};
        set_model_state(sc, 0, q, qd);
        const Plane floor{Eigen::Vector3d(0, 1, 0), -1.1};
        Executor ex(threads);
        Stepper st(scene_step(sc, Force3D::gravity(9.81), {floor}, elastic(0.2, 0.5), {}), threads > 1 ? &ex : nullptr);
        auto total = [&] {
            double e = scene_energy(sc);
            for (Index i = 0; i < 3; ++i) e += mb * 9.81 * position(sc.world, i).y();
            return e;
        };
        End end{0, total(), total(), 1e9, {}};
        for (int k = 0; k < 3000; ++k) {
            st.step(sc.world, 1e-3);
            end.highest = std::max(end.highest, total());
            for (Index i = 0; i < 3; ++i) end.lowest = std::min(end.lowest, position(sc.world, i).y() + 1.1 - h);
        }
        end.hash = sc.world.hash();
        end.top = position(sc.world, 2);
        return end;
    };
    const End one = run(1), four = run(4);
    CHECK(one.hash == four.hash);
    CHECK(one.highest <= one.e0 + 1e-6);        // contacts only take energy away
    CHECK(one.lowest > -2e-3);                  // no box sank into the floor by more than 2 mm
    CHECK(std::abs(one.top.x() - 0.45) > 0.05); // the top box was knocked off its place
}
