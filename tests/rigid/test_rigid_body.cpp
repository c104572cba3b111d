// Rigid bodies: the torque-free asymmetric top against Landau's elliptic-function solution,
// conservation laws, projectile motion, validation of bodies, and rune domains.
#include "phynjo/runtime/runtime.hpp"

#include <boost/math/special_functions/ellint_1.hpp>
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace phynjo::runtime;

namespace {

/// One body with I = diag(I1, I2, I3), spinning with body rate ω0 from the identity orientation.
World top(const Eigen::Vector3d& moments, const Eigen::Vector3d& omega0, const Quaternion& q0 = Quaternion::identity()) {
    Registry r;
    r.add("top");
    RigidBody b;
    b.mass = 2;
    b.inertia = moments.asDiagonal();
    RigidInit s;
    s.orientation = q0;
    s.angular_velocity = q0.rotate(omega0);
    return make_rigid_world(r, {b}, {s});
}

Eigen::Vector3d body_rate(const World& w) { return orientation(w, 0).rotate_inverse(angular_velocity(w, 0)); }

} // namespace

TEST_CASE("torque-free asymmetric top: the intermediate-axis flip has Landau's period", "[rigid][physics]") {
    // I1 < I2 < I3, spin mostly about the intermediate axis. With M² > 2E·I2, Landau & Lifshitz
    // §37: ω2 = A sn(λt, k), λ = √((I3−I2)(M²−2E I1)/(I1 I2 I3)),
    // k² = (I2−I1)(2E I3−M²)/((I3−I2)(M²−2E I1)); ω2 changes sign every 2K(k)/λ.
    const double I1 = 1, I2 = 2, I3 = 3;
    const Eigen::Vector3d om0(0.01, 1.0, 0.02);
    World w = top({I1, I2, I3}, om0, Quaternion::from_axis_angle(Eigen::Vector3d(1, 1, 0), 0.7));
    const double E2 = I1 * om0.x() * om0.x() + I2 * om0.y() * om0.y() + I3 * om0.z() * om0.z(); // 2E
    const double M2 = I1 * I1 * om0.x() * om0.x() + I2 * I2 * om0.y() * om0.y() + I3 * I3 * om0.z() * om0.z();
    REQUIRE(M2 > E2 * I2);
    const double lambda = std::sqrt((I3 - I2) * (M2 - E2 * I1) / (I1 * I2 * I3));
    const double k = std::sqrt((I2 - I1) * (E2 * I3 - M2) / ((I3 - I2) * (M2 - E2 * I1)));
    const double half_period = 2 * boost::math::ellint_1(k) / lambda;

    const auto layout = w.layout_ptr();
    Stepper stepper(rigid_leapfrog(Force3D{}, all_bodies(w), layout));
    const double dt = 1e-3;
    const double E0 = rigid_kinetic_energy(w);
    const Eigen::Vector3d L0 = total_angular_momentum(w);
    std::vector<double> crossings;
    double prev = body_rate(w).y(), worst_e = 0, worst_l = 0, worst_q = 0, worst_lmag = 0;
    const int steps = static_cast<int>(3.2 * half_period / dt);
    for (int n = 1; n <= steps; ++n) {
        stepper.step(w, dt);
        const double cur = body_rate(w).y();
        if ((prev > 0) != (cur > 0)) crossings.push_back((n - 1 + prev / (prev - cur)) * dt); // linear interpolation
        prev = cur;
        worst_e = std::max(worst_e, std::abs(rigid_kinetic_energy(w) - E0) / E0);
        worst_l = std::max(worst_l, (total_angular_momentum(w) - L0).norm() / L0.norm());
        worst_lmag = std::max(worst_lmag, std::abs(total_angular_momentum(w).norm() - L0.norm()) / L0.norm());
        worst_q = std::max(worst_q, std::abs(orientation(w, 0).norm() - 1));
    }
    INFO("half period " << half_period << " s; crossings at " << (crossings.size() > 0 ? crossings[0] : -1) << ", "
                        << (crossings.size() > 1 ? crossings[1] : -1) << ", "
                        << (crossings.size() > 2 ? crossings[2] : -1));
    // ω2 = A sn(λt + τ0): consecutive zeros 2K/λ apart (τ0 is set by ω(0); 3.2 half-periods
    // hold three zeros).
    REQUIRE(crossings.size() == 3);
    for (std::size_t j = 0; j + 1 < 3; ++j)
        CHECK(std::abs(crossings[j + 1] - crossings[j] - half_period) < 1e-4 * half_period);
    // Energy and |M| are quadratic invariants of the implicit-midpoint kick and untouched by the
    // rotation drift: conserved to round-off (5e4 steps). The direction of M is conserved to O(dt²).
    INFO("energy error " << worst_e << ", |M| error " << worst_lmag << ", angular momentum error " << worst_l
                         << ", |q| - 1 " << worst_q);
    CHECK(worst_e < 1e-10);
    CHECK(worst_lmag < 1e-10); // catches a kick that keeps E but not |M| (e.g. a wrong gyroscopic sign)
    CHECK(worst_l < 1e-4);
    CHECK(worst_q < 1e-15);
}

TEST_CASE("angular momentum error of the top falls as dt squared", "[rigid][physics]") {
    double err[2];
    int i = 0;
    for (double dt : {4e-3, 2e-3}) {
        World w = top({1, 2, 3}, {0.3, 1.0, 0.5});
        const Eigen::Vector3d L0 = total_angular_momentum(w);
        Stepper s(rigid_leapfrog(Force3D{}, all_bodies(w), w.layout_ptr()));
        double worst = 0;
        for (int n = 0; n < static_cast<int>(20.0 / dt); ++n) {
            s.step(w, dt);
            worst = std::max(worst, (total_angular_momentum(w) - L0).norm());
        }
        err[i++] = worst;
    }
    const double order = std::log2(err[0] / err[1]);
    INFO("errors " << err[0] << ", " << err[1] << ", order " << order);
    CHECK(order > 1.8);
    CHECK(order < 2.2);
}

TEST_CASE("the explicit gyroscopic step is first order and drifts in energy", "[rigid][physics]") {
    // Kept as the first design had it; the default scheme exists because of this drift.
    World w = top({1, 2, 3}, {0.3, 1.0, 0.5});
    const double E0 = rigid_kinetic_energy(w);
    Stepper s(rigid_leapfrog(Force3D{}, all_bodies(w), w.layout_ptr(), GyroscopicScheme::explicit_euler));
    s.run(w, 1e-3, 20000);
    CHECK(std::abs(rigid_kinetic_energy(w) - E0) / E0 > 1e-6);
}

TEST_CASE("constant torque spins up a sphere as omega = tau t / I", "[rigid][physics]") {
    Registry r;
    r.add("ball");
    World w = make_rigid_world(r, {RigidBody::solid_sphere(3, 0.2)});
    const double I = 0.4 * 3 * 0.04;
    const Force3D torque([](const State3D&, Index) { return std::pair<Vec3, Vec3>{Vec3{0, 0, 0}, Vec3{0.1, 0, 0.2}}; });
    Stepper s(rigid_leapfrog(torque, all_bodies(w), w.layout_ptr()));
    s.run(w, 1e-2, 500);
    CHECK((angular_velocity(w, 0) - Eigen::Vector3d(0.1, 0, 0.2) * 5 / I).norm() < 1e-11);
}

TEST_CASE("projectile under gravity follows the parabola exactly", "[rigid][physics]") {
    Registry r;
    r.add("ball");
    RigidInit s;
    s.position = {0, 10, 0};
    s.velocity = {3, 4, -1};
    s.angular_velocity = {0, 5, 0};
    World w = make_rigid_world(r, {RigidBody::solid_sphere(1, 0.1)}, {s});
    Stepper st(rigid_leapfrog(Force3D::gravity(9.81), all_bodies(w), w.layout_ptr()));
    st.run(w, 0.01, 100);
    const double t = 1.0;
    CHECK((position(w, 0) - Eigen::Vector3d(3 * t, 10 + 4 * t - 0.5 * 9.81 * t * t, -t)).norm() < 1e-12);
    CHECK((velocity(w, 0) - Eigen::Vector3d(3, 4 - 9.81 * t, -1)).norm() < 1e-12);
    // A sphere spinning about y: the orientation turned by 5 rad about y.
    CHECK((orientation(w, 0).to_matrix() - Quaternion::from_axis_angle({0, 1, 0}, 5.0).to_matrix()).norm() < 1e-12);
}

TEST_CASE("invalid bodies are rejected at construction, naming the component", "[rigid][guards]") {
    Registry r;
    r.add("wheel");
    auto fails = [&](RigidBody b, RigidInit s, const std::string& needle) {
        try {
            (void)make_rigid_world(r, {b}, {s});
            FAIL("accepted a body that should be invalid: " << needle);
        } catch (const InvalidBody& e) {
            INFO(e.what());
            CHECK(std::string(e.what()).find("'wheel'") != std::string::npos);
            CHECK(std::string(e.what()).find(needle) != std::string::npos);
        }
    };
    RigidBody ok = RigidBody::solid_sphere(1, 0.1);
    RigidBody b = ok;
    b.mass = 0;
    fails(b, {}, "mass");
    b.mass = std::nan("");
    fails(b, {}, "mass");
    b = ok;
    b.inertia = Eigen::Vector3d(1, 1, -1).asDiagonal();
    fails(b, {}, "not positive definite");
    b.inertia = Eigen::Vector3d(1, 1, 3).asDiagonal();
    fails(b, {}, "triangle inequality");
    b.inertia = Eigen::Matrix3d::Identity();
    b.inertia(0, 1) = 0.5;
    fails(b, {}, "not symmetric");
    b = ok;
    b.radius = -1;
    fails(b, {}, "radius");
    RigidInit s;
    s.orientation = Quaternion{1, 1, 0, 0};
    fails(ok, s, "not a unit quaternion");
    s.orientation = Quaternion{std::nan(""), 0, 0, 0};
    fails(ok, s, "not a unit quaternion");
    // Within the tolerance: accepted and stored normalised.
    s.orientation = Quaternion{1 + 1e-8, 0, 0, 0};
    World w = make_rigid_world(r, {ok}, {s});
    CHECK(orientation(w, 0).w == 1.0);
    CHECK_THROWS_AS(set_orientation(w, 0, Quaternion{0.5, 0, 0, 0}), InvalidBody);
}

TEST_CASE("runes declare their domains: par of translation and rotation drifts equals seq", "[rigid][workflow]") {
    Registry r;
    for (int i = 0; i < 6; ++i) r.add("b" + std::to_string(i));
    std::vector<RigidBody> bodies(6, RigidBody::box(2, {0.1, 0.2, 0.3}));
    std::vector<RigidInit> init(6);
    for (int i = 0; i < 6; ++i) {
        init[i].velocity = {0.1 * i, 1, -0.2};
        init[i].angular_velocity = {1, 0.5 * i, 0.3};
    }
    World a = make_rigid_world(r, bodies, init), b = a;
    const auto layout = a.layout_ptr();
    const ComponentSet all = all_bodies(a);
    using W = NumericWorkflow;
    const auto par = W::par(W::run(drift_trans(all, 1, layout)), W::run(drift_rot(all, 1, layout)));
    const auto seq = W::seq(W::run(drift_trans(all, 1, layout)), W::run(drift_rot(all, 1, layout)));
    Executor pool(2);
    Stepper(par, &pool).run(a, 0.01, 100);
    Stepper(seq).run(b, 0.01, 100);
    CHECK(a.tick == 100);
    CHECK(b.tick == 200); // seq takes two ticks a step, par one
    a.tick = b.tick;
    CHECK(a == b);
    // Two kicks of the same body in parallel: refused when built, naming what they share.
    try {
        (void)W::par(W::run(kick_force3d(Force3D::gravity(9.81), ComponentSet{0, 1}, 1, layout)),
                     W::run(kick_force3d(Force3D::gravity(9.81), ComponentSet{1, 2}, 1, layout)));
        FAIL("overlapping kicks accepted");
    } catch (const DomainOverlapError& e) {
        INFO(e.what());
        CHECK(std::string(e.what()).find("vx:b1") != std::string::npos);
    }
    // A kick reads every body (a Force3D may), so it cannot run beside a drift of any body.
    CHECK_THROWS_AS(W::par(W::run(kick_force3d(Force3D::gravity(9.81), ComponentSet{0}, 1, layout)),
                           W::run(drift_trans(ComponentSet{3}, 1, layout))),
                    DomainOverlapError);
}
