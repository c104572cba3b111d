// Shapes (docs/language.md, *Shapes*; docs/generated-code.md): the generated shape_positions
// against the model's kinematics written out by hand, sphere_jacobians against central
// differences of shape_positions, the radii, the names and kinds; boxes' orientations against
// rotation matrices by hand, their angular-velocity Jacobians against ω = vee(Ṙ Rᵀ) by central
// differences.
#include "shapes.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

constexpr std::size_t kValues = 57;                        // entries of shape_positions
constexpr std::array<std::size_t, 3> kBoxes{36, 43, 50};    // offsets of lid, tilt, crate in X
using Mat = std::array<std::array<double, 3>, 3>;

/// The kinematics of shapes.lag, by hand: bob1, rod1 (2 ends), bob2, rod2 (2 ends), post, float,
/// arm and lever (2 ends each), then the boxes' centres (their orientations: box_rotation).
std::vector<double> by_hand(const shapes::Parameters& P, double t, double th1, double th2) {
    const double x1 = P.l1 * std::sin(th1), y1 = -P.l1 * std::cos(th1);
    const double x2 = x1 + P.l2 * std::sin(th2) * std::cos(th1), y2 = y1 + P.l2 * std::sin(th2) * std::sin(th1),
                 z2 = -P.l2 * std::cos(th2);
    return {x1, y1, 0, 0, 0, 0, x1, y1, 0, x2, y2, z2, x1, y1, 0, x2, y2, z2, 1, -2, 0, P.h, P.a * std::sin(P.w * t), 0,
            0,  0,  0, x1, y1, 0, x1, y1, 0, x2, y2, z2, (x1 + x2) / 2, (y1 + y2) / 2, z2 / 2, x1 / 2, y1 / 2, 0, -1, -2, 0};
}

Mat multiply(const Mat& a, const Mat& b) {
    Mat c{};
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j)
            for (std::size_t k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
    return c;
}

/// The rotation by `angle` about the unit `axis` as a matrix: cos A I + sin A [a]× + (1 − cos A) a aᵀ.
Mat axis_angle(std::array<double, 3> a, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    Mat r{};
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j) r[i][j] = (i == j ? c : 0.0) + (1 - c) * a[i] * a[j];
    r[0][1] -= s * a[2], r[0][2] += s * a[1], r[1][0] += s * a[2], r[1][2] -= s * a[0], r[2][0] -= s * a[1], r[2][1] += s * a[0];
    return r;
}

/// The generated quaternion (w, x, y, z) at X[at] as a rotation matrix.
Mat quaternion_matrix(const std::vector<double>& X, std::size_t at) {
    const double w = X[at], x = X[at + 1], y = X[at + 2], z = X[at + 3];
    return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
             {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
             {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

/// The boxes' orientations by hand: lid's −z along the second link and its y turned by th1
/// about z; tilt turned by th1 + 2 th2 about (1, 1, 1)/√3, then by th1 about z; crate not turned.
std::array<Mat, 3> box_rotations(double th1, double th2) {
    const double s = 1 / std::sqrt(3.0);
    const Mat z1 = axis_angle({0, 0, 1}, th1);
    return {multiply(z1, axis_angle({0, 1, 0}, th2)), multiply(z1, axis_angle({s, s, s}, th1 + 2 * th2)),
            Mat{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}};
}

/// shape_positions at (t, q + dq e_j).
std::vector<double> positions_at(const shapes::Parameters& P, double t, std::array<double, 2> q, std::size_t j, double dq) {
    q[j] += dq;
    std::vector<double> X(kValues);
    shapes::shape_positions(P, t, q, X);
    return X;
}

/// ∂X/∂q_j of every entry of shape_positions at (t, q): the fourth-order central difference,
/// h = 1e-4 (error ~h⁴, far below the 1e-9 the tests allow).
std::vector<double> position_derivative(const shapes::Parameters& P, double t, const std::array<double, 2>& q, std::size_t j) {
    const double h = 1e-4;
    const auto p2 = positions_at(P, t, q, j, 2 * h), p1 = positions_at(P, t, q, j, h), m1 = positions_at(P, t, q, j, -h),
               m2 = positions_at(P, t, q, j, -2 * h);
    std::vector<double> d(kValues);
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = (m2[i] - p2[i] + 8 * (p1[i] - m1[i])) / (12 * h);
    return d;
}

} // namespace

// Bugs caught: a shape's points out of file order, a segment given 3 entries, a sphere's
// centre from the wrong let, the names or kinds wrong, a radius from the file's number
// instead of the parameter.
TEST_CASE("shape_positions: the model's kinematics in file order, with the names, kinds and radii", "[codegen][shapes]") {
    STATIC_REQUIRE(shapes::n_shapes == 11);
    STATIC_REQUIRE(shapes::n_spheres == 4);
    STATIC_REQUIRE(shapes::n_capsules == 2);
    STATIC_REQUIRE(shapes::n_boxes == 3);
    CHECK(shapes::shape_names == std::array<std::string_view, 11>{"bob1", "rod1", "bob2", "rod2", "post", "float", "arm",
                                                                  "lever", "lid", "tilt", "crate"});
    CHECK(shapes::shape_is_sphere ==
          std::array<bool, 11>{true, false, true, false, true, true, false, false, false, false, false});
    CHECK(shapes::shape_kinds == std::array<unsigned char, 11>{1, 0, 1, 0, 1, 1, 2, 2, 3, 3, 3});
    shapes::Parameters P;
    P.h = 0.25;
    std::mt19937_64 rng(20261203);
    std::uniform_real_distribution<double> angle(-3, 3), time(0, 5);
    for (int k = 0; k < 20; ++k) {
        const double th1 = angle(rng), th2 = angle(rng), t = time(rng);
        const std::array<double, 2> q{th1, th2};
        std::vector<double> X(kValues);
        shapes::shape_positions(P, t, q, X);
        const auto want = by_hand(P, t, th1, th2);
        std::size_t i = 0;
        for (std::size_t b = 0; b < 3; ++b) {
            for (; i < kBoxes[b] + 3; ++i) CHECK(X[i] == Approx(want[i - 4 * b]).margin(1e-14));
            const Mat R = quaternion_matrix(X, i), R0 = box_rotations(th1, th2)[b];
            for (std::size_t r = 0; r < 3; ++r)
                for (std::size_t c = 0; c < 3; ++c) CHECK(R[r][c] == Approx(R0[r][c]).margin(1e-14));
            i += 4;
        }
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
    std::array<double, 9> h{};
    P.a = 2;
    shapes::box_half_extents(P, h);
    CHECK(h == std::array<double, 9>{0.05, 0.025, 0.125, 0.2, 0.05, 0.02, 0.25, 0.25, 0.125});
    std::vector<double> wrong(kValues - 1);
    CHECK_THROWS_AS(shapes::shape_positions(P, 0, std::array<double, 2>{0, 0}, wrong), std::invalid_argument);
}

// Bug caught: a turn's axis that a parameter makes zero at run time (the analyzer saw only the
// defaults) normalised by dividing by zero — NaN orientations and Jacobians, silently.
TEST_CASE("a box's axis made zero by its parameter is refused, naming the turn and the box", "[codegen][shapes]") {
    shapes::Parameters P;
    std::vector<double> X(kValues), J(3 * 6 * 2);
    const std::array<double, 2> q{0.3, -0.2};
    for (const double k : {0.0, std::nan("")}) {
        P.k = k;
        for (int f = 0; f < 2; ++f) {
            try {
                if (f == 0)
                    shapes::shape_positions(P, 0, q, X);
                else
                    shapes::box_jacobians(P, 0, q, J);
                FAIL("no error for k = " << k);
            } catch (const std::invalid_argument& e) {
                const std::string what = e.what();
                CHECK(what.find(f == 0 ? "shapes::shape_positions: " : "shapes::box_jacobians: ") == 0);
                CHECK(what.find("the axis of turn 1 of box 'tilt' has length zero at these parameters") != std::string::npos);
            }
        }
    }
    P.k = -2; // any other length: the same axis as k = 1 reversed (a turn the other way), finite
    shapes::shape_positions(P, 0, q, X);
    shapes::box_jacobians(P, 0, q, J);
    for (const double x : X) CHECK(std::isfinite(x));
    for (const double x : J) CHECK(std::isfinite(x));
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

// Bugs caught: ω from the turns in the wrong order (the first axis not carried by the later
// turns), an axis used without normalising it, the centre's rows and ω's swapped, ∂A/∂q of one
// turn only, a fixed box given a nonzero row; box_half_extents out of order.
TEST_CASE("box_jacobians: the centre's ∂X/∂q and ω = vee(Ṙ Rᵀ) by central differences", "[codegen][shapes]") {
    shapes::Parameters P;
    std::mt19937_64 rng(20261206);
    std::uniform_real_distribution<double> angle(-3, 3);
    const double h = 1e-4;
    for (int k = 0; k < 20; ++k) {
        std::array<double, 2> q{angle(rng), angle(rng)};
        const double t = 0.9;
        std::vector<double> J(3 * 6 * 2);
        shapes::box_jacobians(P, t, q, J);
        const std::vector<double> X = positions_at(P, t, q, 0, 0);
        for (std::size_t j = 0; j < 2; ++j) {
            const std::vector<double> d = position_derivative(P, t, q, j);
            const auto p2 = positions_at(P, t, q, j, 2 * h), p1 = positions_at(P, t, q, j, h), m1 = positions_at(P, t, q, j, -h),
                       m2 = positions_at(P, t, q, j, -2 * h);
            for (std::size_t b = 0; b < 3; ++b) {
                for (std::size_t a = 0; a < 3; ++a) CHECK(J[b * 12 + a * 2 + j] == Approx(d[kBoxes[b] + a]).margin(1e-9));
                // Ṙ by the same fourth-order difference of the rotation matrices, then Ṙ Rᵀ.
                const Mat R = quaternion_matrix(X, kBoxes[b] + 3), A = quaternion_matrix(p2, kBoxes[b] + 3),
                          B = quaternion_matrix(p1, kBoxes[b] + 3), C = quaternion_matrix(m1, kBoxes[b] + 3),
                          D = quaternion_matrix(m2, kBoxes[b] + 3);
                Mat Rdot{}, Rt{};
                for (std::size_t r = 0; r < 3; ++r)
                    for (std::size_t c = 0; c < 3; ++c) {
                        Rdot[r][c] = (D[r][c] - A[r][c] + 8 * (B[r][c] - C[r][c])) / (12 * h);
                        Rt[r][c] = R[c][r];
                    }
                const Mat W = multiply(Rdot, Rt);
                const std::array<double, 3> omega{W[2][1], W[0][2], W[1][0]};
                CHECK(W[1][2] == Approx(-W[2][1]).margin(1e-9)); // skew: a rotation's rate
                for (std::size_t a = 0; a < 3; ++a) CHECK(J[b * 12 + (3 + a) * 2 + j] == Approx(omega[a]).margin(1e-9));
            }
        }
        for (std::size_t e = 24; e < 36; ++e) CHECK(J[e] == 0.0); // crate: no coordinate
    }
    std::vector<double> wrong(35);
    CHECK_THROWS_AS(shapes::box_jacobians(P, 0, std::array<double, 2>{0, 0}, wrong), std::invalid_argument);
}
