// The pseudo-inverse of a manifold's block matrix K in closed form (runtime/src/contact/
// block_inverse.hpp) against an independent oracle: the Moore–Penrose inverse from Eigen's
// singular value decomposition, and the four Penrose conditions checked directly, on random
// manifolds — two bodies of random mass and inertia (or a body on a plane), a random normal,
// points in the contact plane at random depths along the normal. Bugs caught: a wrong sign of
// a minor of the affine dependency u (K u ≠ 0, so (K + s uuᵀ)⁻¹ − uuᵀ/s is no pseudo-inverse),
// u not normalised, the regularised inverse of a rank-3 K kept as its pseudo-inverse, a
// degenerate manifold (points on a line, coinciding) accepted instead of sent to the
// eigen-decomposition, and the eigen-decomposition's cut of small eigenvalues.
#include "block_inverse.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <random>

using namespace phynjo::runtime::contact_detail;

namespace {

struct Manifold {
    int m = 0;
    double n[3], t1[3], t2[3];
    double k[16];
    double ua[4][3];
};

Eigen::Vector3d unit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    return Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
}

/// I⁻¹ of a random rigid body in world axes (principal moments 0.05..2 kg m², turned).
Eigen::Matrix3d random_inverse_inertia(std::mt19937& rng) {
    std::uniform_real_distribution<double> moment(0.05, 2.0);
    std::normal_distribution<double> g;
    const Eigen::Matrix3d r = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d inv(1 / moment(rng), 1 / moment(rng), 1 / moment(rng));
    return r * inv.asDiagonal() * r.transpose();
}

/// A manifold of points x_j = c + a_j t1 + b_j t2 + d_j n (in-plane coordinates given, depth
/// d_j random) between a body at pa and one at pb, or a plane when `plane`:
/// K_pq = 1/m_a + 1/m_b + (r_a,p × n)·I_a⁻¹(r_a,q × n) + (r_b,p × n)·I_b⁻¹(r_b,q × n).
Manifold make_manifold(std::mt19937& rng, const std::vector<Eigen::Vector2d>& in_plane, bool plane) {
    std::uniform_real_distribution<double> mass(0.1, 10.0), depth(-1e-3, 1e-3), off(-0.5, 0.5);
    Manifold mf;
    mf.m = static_cast<int>(in_plane.size());
    const Eigen::Vector3d n = unit(rng);
    // Any orthonormal basis of the plane: the solver's own tangent_basis is not used here.
    Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    for (int d = 0; d < 3; ++d) mf.n[d] = n[d], mf.t1[d] = t1[d], mf.t2[d] = t2[d];
    const double ima = 1 / mass(rng), imb = plane ? 0.0 : 1 / mass(rng);
    const Eigen::Matrix3d ia = random_inverse_inertia(rng);
    const Eigen::Matrix3d ib = plane ? Eigen::Matrix3d::Zero() : random_inverse_inertia(rng);
    const Eigen::Vector3d c(off(rng), off(rng), off(rng));
    const Eigen::Vector3d pa = c + 0.3 * n + Eigen::Vector3d(off(rng), off(rng), off(rng)) * 0.2;
    const Eigen::Vector3d pb = c - 0.3 * n + Eigen::Vector3d(off(rng), off(rng), off(rng)) * 0.2;
    Eigen::Vector3d ua[4], ub[4];
    for (int j = 0; j < mf.m; ++j) {
        const Eigen::Vector3d x = c + in_plane[j].x() * t1 + in_plane[j].y() * t2 + depth(rng) * n;
        ua[j] = (x - pa).cross(n);
        ub[j] = (x - pb).cross(n);
        for (int d = 0; d < 3; ++d) mf.ua[j][d] = ua[j][d];
    }
    for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
            mf.k[4 * p + q] = p < mf.m && q < mf.m ? ima + imb + ua[p].dot(ia * ua[q]) + (plane ? 0.0 : ub[p].dot(ib * ub[q]))
                                                  : 0.0;
    return mf;
}

Eigen::MatrixXd block(const double* a, int m) {
    Eigen::MatrixXd out(m, m);
    for (int p = 0; p < m; ++p)
        for (int q = 0; q < m; ++q) out(p, q) = a[4 * p + q];
    return out;
}

/// The Moore–Penrose inverse by SVD, singular values at or below 1e-10 of the largest cut.
Eigen::MatrixXd svd_pinv(const Eigen::MatrixXd& k) {
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(k, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::VectorXd s = svd.singularValues();
    const double cut = 1e-10 * s.maxCoeff();
    for (Eigen::Index i = 0; i < s.size(); ++i) s(i) = s(i) > cut ? 1 / s(i) : 0.0;
    return svd.matrixV() * s.asDiagonal() * svd.matrixU().transpose();
}

/// κ(K) over its nonzero singular values (those above 1e-10 of the largest).
double condition(const Eigen::MatrixXd& k) {
    const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(k).singularValues();
    double low = s(0);
    for (Eigen::Index i = 0; i < s.size(); ++i)
        if (s(i) > 1e-10 * s(0)) low = s(i);
    return s(0) / low;
}

/// Round-off of a solve at condition κ: a few ε κ (random triangles include thin ones, κ up
/// to 1e8); a wrong formula misses by O(1).
double tolerance(double kappa) { return 1e-12 + 16 * std::numeric_limits<double>::epsilon() * kappa; }

/// X is K's pseudo-inverse: the four Penrose conditions, and X equal to the SVD's, all
/// relative to the sizes of K and X; nothing written beyond the m × m block.
void require_pseudo_inverse(const Manifold& mf, const double* inv) {
    const Eigen::MatrixXd k = block(mf.k, mf.m), x = block(inv, mf.m), oracle = svd_pinv(k);
    const double nk = k.norm(), nx = oracle.norm(), kappa = condition(k), tol = tolerance(kappa);
    INFO("m = " << mf.m << ", κ = " << kappa);
    CHECK((k * x * k - k).norm() <= tol * nk);
    CHECK((x * k * x - x).norm() <= tol * nx);
    CHECK(((k * x) - (k * x).transpose()).norm() <= tol);
    CHECK(((x * k) - (x * k).transpose()).norm() <= tol);
    CHECK((x - oracle).norm() <= tol * nx);
    for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
            if (p >= mf.m || q >= mf.m) CHECK(inv[4 * p + q] == 0.0);
}

std::vector<Eigen::Vector2d> random_points(std::mt19937& rng, int m) {
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::vector<Eigen::Vector2d> pts;
    for (int j = 0; j < m; ++j) pts.emplace_back(u(rng), u(rng));
    return pts;
}

} // namespace

TEST_CASE("the closed-form pseudo-inverse of a face's four points equals the SVD's", "[contact][block]") {
    // A rank-3 K (its null vector the points' affine dependency): the bug it catches is a
    // wrong minor sign or scale of u, or a plain regularised inverse.
    std::mt19937 rng(37);
    for (int trial = 0; trial < 2000; ++trial) {
        const bool plane = trial % 2 == 1;
        const Manifold mf = make_manifold(rng, random_points(rng, 4), plane);
        CHECK(Eigen::FullPivLU<Eigen::MatrixXd>(block(mf.k, 4)).rank() == 3);
        double inv[16];
        REQUIRE(closed_form_pinv(mf.k, 4, mf.t1, mf.t2, mf.ua, inv));
        require_pseudo_inverse(mf, inv);
    }
    // A box's face on the ground: the four corners of a rectangle.
    const Manifold face = make_manifold(rng, {{-0.2, -0.1}, {0.2, -0.1}, {0.2, 0.1}, {-0.2, 0.1}}, true);
    double inv[16];
    REQUIRE(closed_form_pinv(face.k, 4, face.t1, face.t2, face.ua, inv));
    require_pseudo_inverse(face, inv);
}

TEST_CASE("three of four points on a line, and fewer points, still take the closed form", "[contact][block]") {
    std::mt19937 rng(38);
    for (int trial = 0; trial < 1000; ++trial) {
        // Three collinear of four (a clipped point on an edge): u has a zero, K still rank 3.
        std::vector<Eigen::Vector2d> pts = random_points(rng, 4);
        const double s = std::uniform_real_distribution<double>(0.2, 0.8)(rng);
        pts[2] = (1 - s) * pts[0] + s * pts[1];
        const Manifold four = make_manifold(rng, pts, trial % 2 == 0);
        double inv[16];
        REQUIRE(closed_form_pinv(four.k, 4, four.t1, four.t2, four.ua, inv));
        require_pseudo_inverse(four, inv);
        // One, two and three points in general position: K of full rank, K⁺ = K⁻¹.
        for (int m = 1; m <= 3; ++m) {
            const Manifold few = make_manifold(rng, random_points(rng, m), trial % 2 == 1);
            REQUIRE(closed_form_pinv(few.k, m, few.t1, few.t2, few.ua, inv));
            require_pseudo_inverse(few, inv);
        }
    }
}

TEST_CASE("degenerate manifolds are refused by the closed form and solved by the eigen-decomposition",
          "[contact][block]") {
    // Points on one line (or within round-off of one), or coinciding: K's rank falls below the
    // closed form's assumption.
    // Accepted, its inverse would be garbage (a pivot of round-off).
    std::mt19937 rng(39);
    for (int trial = 0; trial < 1000; ++trial) {
        std::uniform_real_distribution<double> u(-0.5, 0.5);
        const Eigen::Vector2d a(u(rng), u(rng)), b(u(rng), u(rng));
        const Eigen::Vector2d off = 1e-9 * Eigen::Vector2d(a.y() - b.y(), b.x() - a.x()); // ⟂ the line, 1e-9 of it
        const bool plane = trial % 2 == 0;
        const std::vector<std::vector<Eigen::Vector2d>> cases = {
            {a, b, 0.3 * a + 0.7 * b, -0.5 * a + 1.5 * b},       // four on a line (an edge on an edge)
            {a, b, 0.3 * a + 0.7 * b + off, -0.5 * a + 1.5 * b}, // four within 1e-9 of a line
            {a, b, 0.6 * a + 0.4 * b},                     // three on a line
            {a, a},                                        // two coinciding
        };
        for (const auto& pts : cases) {
            const Manifold mf = make_manifold(rng, pts, plane);
            double inv[16];
            CHECK_FALSE(closed_form_pinv(mf.k, mf.m, mf.t1, mf.t2, mf.ua, inv));
            eigen_pinv(mf.k, mf.m, inv);
            require_pseudo_inverse(mf, inv);
        }
    }
}

TEST_CASE("Gauss–Jordan inverts a positive definite block and refuses a singular one", "[contact][block]") {
    std::mt19937 rng(40);
    for (int trial = 0; trial < 500; ++trial) {
        const Manifold mf = make_manifold(rng, random_points(rng, 3), false);
        double a[16];
        std::copy_n(mf.k, 16, a);
        REQUIRE(invert_spd_checked(a, 3));
        const Eigen::MatrixXd k = block(mf.k, 3), x = block(a, 3);
        CHECK((k * x - Eigen::MatrixXd::Identity(3, 3)).norm() <= tolerance(condition(k)));
    }
    double singular[16] = {1, 1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    CHECK_FALSE(invert_spd_checked(singular, 2));
    double negative[16] = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    CHECK_FALSE(invert_spd_checked(negative, 2));
}
