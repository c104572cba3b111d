// Block elimination of q' = v and a banded LU of the Schur complement. See velocity_schur.hpp.
#include "velocity_schur.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace phynjo::runtime::integrators {

void BandedLu::reset(std::size_t n, std::size_t kl, std::size_t ku) {
    n_ = n;
    kl_ = kl;
    ku_ = ku;
    width_ = 2 * kl + ku + 1;
    a_.assign((n + kl) * width_, 0.0);
    inv_diag_.resize(n);
    piv_.resize(n);
    b_.assign(n + kl + ku + 1, 0.0);
}

std::size_t BandedLu::factor(std::span<const double> A, std::size_t n) {
    assert(A.size() >= n * n);
    std::size_t kl = 0, ku = 0;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (A[i * n + j] != 0.0) {
                if (i > j) kl = std::max(kl, i - j);
                else ku = std::max(ku, j - i);
            }
    reset(n, kl, ku);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i > kl ? i - kl : 0; j <= std::min(n - 1, i + ku); ++j) at(i, j) = A[i * n + j];
    return factor();
}

std::size_t BandedLu::factor() {
    const std::size_t n = n_, kl = kl_, w = width_;
    interchanged_ = false;
    // row i's entry of column j at a[i * w + j + kl − i]: along a column, the offset falls by
    // one a row (stride w − 1)
    double* a = a_.data();
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t last_row = std::min(n - 1, k + kl);
        std::size_t p = k;
        for (std::size_t i = k + 1; i <= last_row; ++i)
            if (std::fabs(at(i, k)) > std::fabs(at(p, k))) p = i;
        piv_[k] = p;
        if (at(p, k) == 0.0) return k + 1;
        const std::size_t span = kl + ku_ + 1; // columns k … k + kl + ku
        double* rk = a + k * w + kl;           // row k from column k
        if (p != k) {
            interchanged_ = true;
            double* rp = a + p * w + (k + kl - p);
            for (std::size_t j = 0; j < span; ++j) std::swap(rk[j], rp[j]);
        }
        const double inv = 1.0 / rk[0];
        inv_diag_[k] = inv;
        for (std::size_t i = k + 1; i <= last_row; ++i) {
            double* ri = a + i * w + (k + kl - i); // row i from column k
            const double l = ri[0] * inv;
            ri[0] = l;
            if (l != 0.0)
                for (std::size_t j = 1; j < span; ++j) ri[j] -= l * rk[j];
        }
        for (std::size_t j = 1; j < span; ++j) rk[j] *= inv; // row k of D⁻¹U, for the back substitution
    }
    return 0;
}

namespace {

/// The substitutions of BandedLu::solve on x (zeros past n), the band's widths as template
/// arguments where they are small (the loops unrolled), else at run time (KL = -1).
template <int KL, int SPAN>
void substitute(std::size_t n, std::size_t kl_rt, std::size_t span_rt, std::size_t w, const double* a, const double* inv_diag,
                const std::size_t* piv, bool interchanged, double* x) {
    const std::size_t kl = KL >= 0 ? static_cast<std::size_t>(KL) : kl_rt;
    const std::size_t span = KL >= 0 ? static_cast<std::size_t>(SPAN) : span_rt;
    for (std::size_t k = 0; k < n; ++k) { // L, with the interchanges in the order they were made
        if (interchanged && piv[k] != k) std::swap(x[k], x[piv[k]]);
        const double xk = x[k];
        const double* col = a + (k + 1) * w + kl - 1; // (k + 1, k), then down the column
        for (std::size_t r = 0; r < kl; ++r) x[k + 1 + r] -= col[r * (w - 1)] * xk;
    }
    for (std::size_t k = n; k-- > 0;) { // U = D (D⁻¹U): the nearest unknown last, one FMA on the chain
        const double* rk = a + k * w + kl + 1; // (k, k + 1) … of D⁻¹U
        double s = x[k] * inv_diag[k];
        for (std::size_t j = span; j-- > 0;) s -= rk[j] * x[k + 1 + j];
        x[k] = s;
    }
}

} // namespace

void BandedLu::solve(double* b) const {
    const std::size_t n = n_, span = kl_ + ku_; // U's superdiagonals
    double* x = b_.data(); // zeros past n: the loops run their full length, the rows past n are zero
    std::copy(b, b + n, x);
    auto run = [&](auto f) { f(n, kl_, span, width_, a_.data(), inv_diag_.data(), piv_.data(), interchanged_, x); };
    switch (kl_ <= 2 && ku_ <= 2 ? kl_ * 3 + ku_ : 9) { // kl, ku ≤ 2 unrolled: diagonal, bidiagonal, tridiagonal, pentadiagonal …
    case 0: run(substitute<0, 0>); break;
    case 1: run(substitute<0, 1>); break;
    case 2: run(substitute<0, 2>); break;
    case 3: run(substitute<1, 1>); break;
    case 4: run(substitute<1, 2>); break;
    case 5: run(substitute<1, 3>); break;
    case 6: run(substitute<2, 2>); break;
    case 7: run(substitute<2, 3>); break;
    case 8: run(substitute<2, 4>); break;
    default: run(substitute<-1, 0>);
    }
    std::copy(x, x + n, b);
}

VelocitySchur::VelocitySchur(std::size_t n) : n_(n), r_(n), first_(n), last_(n) {}

void VelocitySchur::set_jacobian(const double* J) {
    const std::size_t n = n_, N = 2 * n;
    J_ = J;
    kl_ = ku_ = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double* row = J + (n + i) * N; // (J_q | J_v) of row i of the accelerations
        first_[i] = n;
        last_[i] = 0;
        std::size_t lo = i, hi = i; // S's nonzero columns: the diagonal, J_q's and J_v's
        for (std::size_t j = 0; j < n; ++j) {
            if (row[j] != 0.0) {
                first_[i] = std::min(first_[i], j);
                last_[i] = j + 1;
            }
            if (row[j] != 0.0 || row[n + j] != 0.0) {
                lo = std::min(lo, j);
                hi = std::max(hi, j);
            }
        }
        kl_ = std::max(kl_, i - lo);
        ku_ = std::max(ku_, hi - i);
    }
}

std::size_t VelocitySchur::factor(double c) {
    const std::size_t n = n_, N = 2 * n;
    c_ = c;
    lu_.reset(n, kl_, ku_);
    for (std::size_t i = 0; i < n; ++i) {
        const double* row = J_ + (n + i) * N;
        for (std::size_t j = i > kl_ ? i - kl_ : 0; j <= std::min(n - 1, i + ku_); ++j)
            lu_.at(i, j) = (i == j ? 1.0 : 0.0) - c * row[n + j] - c * c * row[j];
    }
    return lu_.factor();
}

void VelocitySchur::solve(const double* b, double* x) {
    const std::size_t n = n_, N = 2 * n;
    for (std::size_t i = 0; i < n; ++i) { // r = b₂ + c J_q b₁, before x is written (x may be b)
        const double* row = J_ + (n + i) * N;
        double s = 0;
        for (std::size_t j = first_[i]; j < last_[i]; ++j) s += row[j] * b[j];
        r_[i] = b[n + i] + c_ * s;
    }
    lu_.solve(r_.data());
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = b[i] + c_ * r_[i];
        x[n + i] = r_[i];
    }
}

} // namespace phynjo::runtime::integrators
