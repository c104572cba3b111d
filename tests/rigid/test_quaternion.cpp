// Quaternions: matrix round trips (including half-turns), composition, and the two
// orientation updates (unit norm kept, exactness, convergence order).
#include "phynjo/runtime/rigid/quaternion.hpp"

#include "property.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

using phynjo::runtime::Quaternion;

namespace {

Quaternion random_unit(std::mt19937& rng) {
    std::normal_distribution<double> n;
    return Quaternion{n(rng), n(rng), n(rng), n(rng)}.normalized();
}

double distance(const Quaternion& a, const Quaternion& b) { // up to the sign (q and −q are one rotation)
    const double d1 = std::abs(a.w - b.w) + std::abs(a.x - b.x) + std::abs(a.y - b.y) + std::abs(a.z - b.z);
    const double d2 = std::abs(a.w + b.w) + std::abs(a.x + b.x) + std::abs(a.y + b.y) + std::abs(a.z + b.z);
    return std::min(d1, d2);
}

} // namespace

TEST_CASE("quaternion to matrix is a proper rotation and agrees with Eigen", "[rigid][quaternion]") {
    std::mt19937 rng(7);
    for (int k = 0; k < 1000; ++k) {
        const Quaternion q = random_unit(rng);
        const Eigen::Matrix3d r = q.to_matrix();
        CHECK((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-14);
        CHECK(std::abs(r.determinant() - 1) < 1e-14);
        const Eigen::Matrix3d ref = Eigen::Quaterniond(q.w, q.x, q.y, q.z).toRotationMatrix();
        CHECK((r - ref).cwiseAbs().maxCoeff() < 1e-15);
        const Eigen::Vector3d v(0.3, -1.2, 2.5);
        CHECK((q.rotate(v) - r * v).norm() < 1e-14);
        CHECK((q.rotate_inverse(v) - r.transpose() * v).norm() < 1e-14);
    }
}

TEST_CASE("matrix to quaternion inverts to_matrix, half-turns included", "[rigid][quaternion]") {
    phynjo::test::check_property("from_matrix(to_matrix(q)) = ±q", [] {
        const auto a = *rc::gen::inRange(-1000, 1001);
        const auto b = *rc::gen::inRange(-1000, 1001);
        const auto c = *rc::gen::inRange(-1000, 1001);
        const auto d = *rc::gen::inRange(-1000, 1001);
        RC_PRE(a != 0 || b != 0 || c != 0 || d != 0);
        const Quaternion q = Quaternion{double(a), double(b), double(c), double(d)}.normalized();
        RC_ASSERT(distance(Quaternion::from_matrix(q.to_matrix()), q) < 1e-14);
    }, {.cases = 2000});
    // Half-turns (w = 0, trace −1) about each axis and a diagonal: the branches of Shepperd's method.
    for (const Eigen::Vector3d& axis : {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, 1),
                                       Eigen::Vector3d(1, 1, 1)}) {
        const Quaternion q = Quaternion::from_axis_angle(axis, M_PI);
        CHECK(distance(Quaternion::from_matrix(q.to_matrix()), q) < 1e-15);
    }
}

TEST_CASE("the Hamilton product composes rotations", "[rigid][quaternion]") {
    std::mt19937 rng(8);
    for (int k = 0; k < 200; ++k) {
        const Quaternion a = random_unit(rng), b = random_unit(rng);
        CHECK(((a * b).to_matrix() - a.to_matrix() * b.to_matrix()).cwiseAbs().maxCoeff() < 1e-14);
    }
}

TEST_CASE("the exponential update is exact for constant angular velocity and stays unit", "[rigid][quaternion]") {
    const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, -2).normalized();
    const double rate = 3.0, dt = 1e-3;
    Quaternion q = Quaternion::from_axis_angle(Eigen::Vector3d(0, 0, 1), 0.4);
    const Quaternion q0 = q;
    const int steps = 100000;
    double worst_norm = 0;
    for (int k = 0; k < steps; ++k) {
        q = phynjo::runtime::integrate_exponential(q, rate * axis, dt);
        worst_norm = std::max(worst_norm, std::abs(q.norm() - 1));
    }
    const Quaternion expected = Quaternion::from_axis_angle(axis, rate * steps * dt) * q0;
    CHECK(distance(q, expected) < 1e-10); // 1e5 compositions: round-off only
    CHECK(worst_norm < 1e-15);
}

TEST_CASE("the first-order update converges with order 1 and stays unit", "[rigid][quaternion]") {
    // A body-frame angular velocity that varies in time; the update takes ω at the start of
    // each step (explicit Euler), so its global error is O(h). Reference: the exponential map
    // with the midpoint body rate ω_B(t + h/2) rotated to the world frame, at a 100× finer step.
    auto omega_body = [](double t) { return Eigen::Vector3d(std::cos(t), std::sin(2 * t), 0.5); };
    const double T = 1.0;
    const Quaternion q0 = Quaternion::from_axis_angle(Eigen::Vector3d(1, 0, 0), 0.3);
    Quaternion exact = q0;
    {
        const int n = 200000;
        const double h = T / n;
        for (int k = 0; k < n; ++k)
            exact = phynjo::runtime::integrate_exponential(exact, exact.rotate(omega_body((k + 0.5) * h)), h);
    }
    double errors[2];
    int i = 0;
    for (int n : {500, 1000}) {
        Quaternion q = q0;
        for (int k = 0; k < n; ++k) q = phynjo::runtime::integrate_first_order(q, omega_body(k * T / n), T / n);
        CHECK(std::abs(q.norm() - 1) < 1e-15);
        errors[i++] = distance(q, exact);
    }
    const double order = std::log2(errors[0] / errors[1]);
    INFO("errors " << errors[0] << ", " << errors[1] << ", observed order " << order);
    CHECK(order > 0.9);
    CHECK(order < 1.1);
}
