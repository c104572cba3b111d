// Shapes (docs/language.md, *Shapes*; docs/generated-code.md): the generated shape_positions
// against the model's kinematics written out by hand, sphere_jacobians against central
// differences of shape_positions, the radii, the names and kinds.
#include "shapes.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace {

/// The kinematics of shapes.lag, by hand: bob1, rod1 (2 ends), bob2, rod2 (2 ends), post, float,
/// arm and lever (2 ends each).
std::vector<double> by_hand(const shapes::Parameters& P, double t, double th1, double th2) {
    const double x1 = P.l1 * std::sin(th1), y1 = -P.l1 * std::cos(th1);
    const double x2 = x1 + P.l2 * std::sin(th2) * std::cos(th1), y2 = y1 + P.l2 * std::sin(th2) * std::sin(th1),
                 z2 = -P.l2 * std::cos(th2);
    return {x1, y1, 0, 0, 0, 0, x1, y1, 0, x2, y2, z2, x1, y1, 0, x2, y2, z2, 1, -2, 0, P.h, P.a * std::sin(P.w * t), 0,
            0,  0,  0, x1, y1, 0, x1, y1, 0, x2, y2, z2};
}

/// ∂X/∂q_j of every entry of shape_positions at (t, q): the fourth-order central difference,
/// h = 1e-4 (error ~h⁴, far below the 1e-9 the tests allow).
std::vector<double> position_derivative(const shapes::Parameters& P, double t, const std::array<double, 2>& q, std::size_t j) {
    const double h = 1e-4;
    auto at = [&](double dq) {
        auto qq = q;
        qq[j] += dq;
        std::vector<double> X(36);
        shapes::shape_positions(P, t, qq, X);
        return X;
    };
    const auto p2 = at(2 * h), p1 = at(h), m1 = at(-h), m2 = at(-2 * h);
    std::vector<double> d(36);
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = (m2[i] - p2[i] + 8 * (p1[i] - m1[i])) / (12 * h);
    return d;
}

} // namespace

// Bugs caught: a shape's points out of file order, a segment given 3 entries, a sphere's
// centre from the wrong let, the names or kinds wrong, a radius from the file's number
// instead of the parameter.
TEST_CASE("shape_positions: the model's kinematics in file order, with the names, kinds and radii", "[codegen][shapes]") {
    STATIC_REQUIRE(shapes::n_shapes == 8);
    STATIC_REQUIRE(shapes::n_spheres == 4);
    STATIC_REQUIRE(shapes::n_capsules == 2);
    CHECK(shapes::shape_names == std::array<std::string_view, 8>{"bob1", "rod1", "bob2", "rod2", "post", "float", "arm", "lever"});
    CHECK(shapes::shape_is_sphere == std::array<bool, 8>{true, false, true, false, true, true, false, false});
    CHECK(shapes::shape_kinds == std::array<unsigned char, 8>{1, 0, 1, 0, 1, 1, 2, 2});
    shapes::Parameters P;
    P.h = 0.25;
    std::mt19937_64 rng(20261203);
    std::uniform_real_distribution<double> angle(-3, 3), time(0, 5);
    for (int k = 0; k < 20; ++k) {
        const double th1 = angle(rng), th2 = angle(rng), t = time(rng);
        const std::array<double, 2> q{th1, th2};
        std::vector<double> X(36);
        shapes::shape_positions(P, t, q, X);
        const auto want = by_hand(P, t, th1, th2);
        for (std::size_t i = 0; i < X.size(); ++i) CHECK(X[i] == Approx(want[i]).margin(1e-14));
    }
    std::array<double, 4> r{};
    shapes::sphere_radii(P, r);
    CHECK(r == std::array<double, 4>{0.1, 0.075, 0.2, 0.05});
    P.r2 = 0.3;
    shapes::sphere_radii(P, r);
    CHECK(r[1] == 0.3);
    std::array<double, 2> rc{};
    shapes::capsule_radii(P, rc);
    CHECK(rc == std::array<double, 2>{0.15, 0.04});
    std::vector<double> wrong(35);
    CHECK_THROWS_AS(shapes::shape_positions(P, 0, std::array<double, 2>{0, 0}, wrong), std::invalid_argument);
}

// Bugs caught: the Jacobian of a segment emitted as a sphere's (shifting every later one),
// ∂/∂q columns transposed, a Jacobian that misses the chain rule through a let, a fixed
// obstacle or a t-driven sphere given a nonzero Jacobian.
TEST_CASE("sphere_jacobians = central differences of the sphere centres", "[codegen][shapes]") {
    shapes::Parameters P;
    const std::array<std::size_t, 4> centre{0, 9, 18, 21}; // offsets of the spheres in X
    std::mt19937_64 rng(20261204);
    std::uniform_real_distribution<double> angle(-3, 3);
    for (int k = 0; k < 20; ++k) {
        std::array<double, 2> q{angle(rng), angle(rng)};
        const double t = 0.7;
        std::vector<double> J(4 * 3 * 2);
        shapes::sphere_jacobians(P, t, q, J);
        for (std::size_t j = 0; j < 2; ++j) {
            const std::vector<double> d = position_derivative(P, t, q, j);
            for (std::size_t s = 0; s < 4; ++s)
                for (std::size_t a = 0; a < 3; ++a) CHECK(J[s * 6 + a * 2 + j] == Approx(d[centre[s] + a]).margin(1e-9));
        }
        for (std::size_t e = 12; e < 24; ++e) CHECK(J[e] == 0.0); // post and float: no coordinate
    }
}

// Bugs caught: a capsule's Jacobian rows of one end only (6 × dof expected), its ends swapped,
// the capsules' block offset by a sphere's or segment's entries, the fixed end given a nonzero
// row; capsule_radii out of file order or sized as the spheres'.
TEST_CASE("capsule_jacobians = central differences of both ends", "[codegen][shapes]") {
    shapes::Parameters P;
    const std::array<std::size_t, 2> ends{24, 30}; // offsets of the capsules' first ends in X
    std::mt19937_64 rng(20261205);
    std::uniform_real_distribution<double> angle(-3, 3);
    for (int k = 0; k < 20; ++k) {
        std::array<double, 2> q{angle(rng), angle(rng)};
        const double t = 0.4;
        std::vector<double> J(2 * 6 * 2);
        shapes::capsule_jacobians(P, t, q, J);
        for (std::size_t j = 0; j < 2; ++j) {
            const std::vector<double> d = position_derivative(P, t, q, j);
            for (std::size_t c = 0; c < 2; ++c)
                for (std::size_t a = 0; a < 6; ++a) CHECK(J[c * 12 + a * 2 + j] == Approx(d[ends[c] + a]).margin(1e-9));
        }
        for (std::size_t e = 0; e < 6; ++e) CHECK(J[e] == 0.0); // arm's first end is fixed
    }
    std::vector<double> wrong(23);
    CHECK_THROWS_AS(shapes::capsule_jacobians(P, 0, std::array<double, 2>{0, 0}, wrong), std::invalid_argument);
}
