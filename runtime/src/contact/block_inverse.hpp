#pragma once
// The small inverses of a manifold's block (internal to runtime/src/contact; tested on their
// own in tests/rigid/test_block_inverse.cpp): K of up to four contact points of one pair of
// bodies, K_pq = 1/m_a + 1/m_b + (r_a,p × n)·I_a⁻¹(r_a,q × n) + (r_b,p × n)·I_b⁻¹(r_b,q × n),
// stored 4 × 4 row-major with the first m × m used.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace phynjo::runtime::contact_detail {

/// f(n) with n as std::integral_constant<int, n> for n = 1 to 4 — loops over it then unroll,
/// the same operations in the same order — and as the int otherwise.
template <class F>
inline decltype(auto) with_fixed_count(int n, F&& f) {
    switch (n) {
    case 1: return f(std::integral_constant<int, 1>{});
    case 2: return f(std::integral_constant<int, 2>{});
    case 3: return f(std::integral_constant<int, 3>{});
    case 4: return f(std::integral_constant<int, 4>{});
    default: return f(n);
    }
}

namespace block_inverse_detail {

/// invert_spd_checked's elimination, n an int or a std::integral_constant (with_fixed_count).
template <class Size>
inline bool gauss_jordan(double* a, Size n, double floor) {
    for (int k = 0; k < n; ++k)
        if (!(a[4 * k + k] > 0)) return false;
    double diag[4];
    for (int k = 0; k < n; ++k) diag[k] = a[4 * k + k];
    for (int k = 0; k < n; ++k) {
        if (!(a[4 * k + k] > floor * diag[k])) return false;
        const double p = 1 / a[4 * k + k];
        a[4 * k + k] = 1;
        for (int j = 0; j < n; ++j) a[4 * k + j] *= p;
        for (int i = 0; i < n; ++i) {
            if (i == k) continue;
            const double f = a[4 * i + k];
            a[4 * i + k] = 0;
            for (int j = 0; j < n; ++j) a[4 * i + j] -= f * a[4 * k + j];
        }
    }
    return true;
}

} // namespace block_inverse_detail

/// In place: the inverse of the symmetric positive definite n × n matrix a (row-major,
/// stride 4, n ≤ 4) by Gauss–Jordan elimination (no pivoting needed); false (a left in pieces)
/// when a pivot falls to `floor` of its diagonal entry or below: singular to working precision.
inline bool invert_spd_checked(double* a, int n, double floor = 1e-9) {
    return with_fixed_count(n, [&](auto size) { return block_inverse_detail::gauss_jordan(a, size, floor); });
}

/// invert_spd_checked for a matrix known to be positive definite (K_SS + 1e-9 diag).
inline void invert_spd(double* a, int n) { invert_spd_checked(a, n, 0.0); }

/// K⁺, the pseudo-inverse of the block matrix k (m ≤ 4 points), into inv (4 × 4, zero beyond
/// m) without an eigen-decomposition; false when the manifold is degenerate (all points on a
/// line, points that coincide), inv then undefined. ua_j = r_a,j × n; t1, t2 an orthonormal
/// basis of the plane ⟂ n. Four points of a face give K of rank 3: K u = 0 for the points'
/// affine dependency u (Σ u_j = 0, Σ u_j r_j ∥ n — the same for both bodies, whose lever arms
/// differ by a constant), so K⁺ = (K + s u uᵀ)⁻¹ − u uᵀ / s for unit u and any s > 0. Fewer
/// points give K of full rank: K⁺ = K⁻¹.
inline bool closed_form_pinv(const double* k, int m, const double* t1, const double* t2, const double (*ua)[3],
                             double* inv) {
    double a[16];
    std::copy_n(k, 16, a);
    double u[4] = {0, 0, 0, 0}, s = 0;
    if (m == 4) {
        // u_j: the signed 3 × 3 minors of the rows (1, x_j, y_j), (x, y) the points' lever arms
        // in the plane ⟂ n.
        double x[4], y[4], span = 0;
        for (int j = 0; j < 4; ++j) {
            x[j] = ua[j][0] * t1[0] + ua[j][1] * t1[1] + ua[j][2] * t1[2];
            y[j] = ua[j][0] * t2[0] + ua[j][1] * t2[1] + ua[j][2] * t2[2];
            span = std::max({span, std::abs(x[j] - x[0]), std::abs(y[j] - y[0])});
        }
        auto minor = [&](int i0, int i1, int i2) {
            return (x[i1] - x[i0]) * (y[i2] - y[i0]) - (x[i2] - x[i0]) * (y[i1] - y[i0]);
        };
        u[0] = minor(1, 2, 3), u[1] = -minor(0, 2, 3), u[2] = minor(0, 1, 3), u[3] = -minor(0, 1, 2);
        const double norm = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + u[3] * u[3]);
        if (!(norm > 1e-6 * span * span)) return false;
        for (double& c : u) c /= norm;
        s = (a[0] + a[5] + a[10] + a[15]) / 4;
        for (int p = 0; p < 4; ++p)
            for (int q = 0; q < 4; ++q) a[4 * p + q] += s * u[p] * u[q];
    }
    if (!invert_spd_checked(a, m)) return false;
    for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
            inv[4 * p + q] = p < m && q < m ? a[4 * p + q] - (m == 4 ? u[p] * u[q] / s : 0.0) : 0.0;
    return true;
}

/// K⁺ of the block matrix k (m ≤ 4 points) into inv by K's eigen-decomposition, eigenvalues
/// at or below 1e-10 of the largest taken as zero: the degenerate manifolds closed_form_pinv
/// refuses.
inline void eigen_pinv(const double* k, int m, double* inv) {
    Eigen::Matrix4d kk = Eigen::Matrix4d::Identity(); // padded: block-diagonal with 𝟙
    for (int p = 0; p < m; ++p)
        for (int q = 0; q < m; ++q) kk(p, q) = k[4 * p + q];
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(kk);
    const Eigen::Vector4d l = es.eigenvalues();
    const double floor = 1e-10 * l.cwiseAbs().maxCoeff();
    Eigen::Vector4d li;
    for (int i = 0; i < 4; ++i) li(i) = l(i) > floor ? 1 / l(i) : 0.0;
    const Eigen::Matrix4d pinv = es.eigenvectors() * li.asDiagonal() * es.eigenvectors().transpose();
    for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q) inv[4 * p + q] = p < m && q < m ? pinv(p, q) : 0.0;
}

} // namespace phynjo::runtime::contact_detail
