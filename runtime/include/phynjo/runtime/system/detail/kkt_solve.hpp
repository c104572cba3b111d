#pragma once
/// \file
/// The saddle-point system of a constrained model (docs/language.md, *Constraints*):
///   M q'' = f + Gᵀλ,   G q'' = γ,
/// solved through the Schur complement: with u = M⁻¹f and Y = M⁻¹Gᵀ,
///   (G Y) λ = γ − G u,   q'' = u + Y λ.
/// M is factored once (LDLᵀ, or pivoted LU when indefinite) and solved for 1 + C right-hand
/// sides; G M⁻¹ Gᵀ (C×C, symmetric) is factored the same way. Fixed size, no allocation in
/// the regular case (bench/: `ratio kkt_four_bar` against a dense KKT solve).
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/system/detail/symmetric_solve.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::runtime {

namespace detail {

/// The constraints involved when G M⁻¹ Gᵀ is singular: the first row of G (C×N) that is a
/// combination of earlier rows at this state, and those rows (error path only: allocates).
inline std::vector<std::size_t> dependent_constraints(const double* G, std::size_t C, std::size_t N) {
    std::vector<double> R(C * N), T(C * C);
    std::vector<std::size_t> pivot_col(C), rows(C);
    rows.resize(dependent_rows(G, C, N, R.data(), T.data(), pivot_col.data(), rows.data()));
    return rows;
}

/// Solves A x = b in place (A p×p row-major, overwritten; b becomes x) by LU with partial
/// pivoting; false when A is singular (a pivot below 1e-14 times the largest entry).
inline bool dense_solve(std::span<double> A, std::span<double> b, std::size_t p) {
    double scale = 0;
    for (double a : A) scale = std::max(scale, std::fabs(a));
    for (std::size_t c = 0; c < p; ++c) {
        std::size_t piv = c;
        for (std::size_t i = c + 1; i < p; ++i)
            if (std::fabs(A[i * p + c]) > std::fabs(A[piv * p + c])) piv = i;
        if (!(std::fabs(A[piv * p + c]) > 1e-14 * scale)) return false;
        if (piv != c) {
            for (std::size_t j = 0; j < p; ++j) std::swap(A[c * p + j], A[piv * p + j]);
            std::swap(b[c], b[piv]);
        }
        for (std::size_t i = c + 1; i < p; ++i) {
            const double f = A[i * p + c] / A[c * p + c];
            for (std::size_t j = c; j < p; ++j) A[i * p + j] -= f * A[c * p + j];
            b[i] -= f * b[c];
        }
    }
    for (std::size_t i = p; i-- > 0;) {
        double x = b[i];
        for (std::size_t j = i + 1; j < p; ++j) x -= A[i * p + j] * b[j];
        b[i] = x / A[i * p + i];
    }
    return true;
}

[[noreturn]] inline void throw_singular_constraints(const double* G, std::size_t C, std::size_t N,
                                                    std::span<const std::string_view> names, std::string_view where,
                                                    double t) {
    const auto rows = dependent_constraints(G, C, N);
    std::vector<std::string> involved;
    std::string what = std::string(where) + ": the constraints are singular at t = " + std::to_string(t) + ": ";
    if (rows.empty()) {
        for (auto n : names) involved.emplace_back(n);
        what += "G M^-1 G^T is singular although G has full rank (the mass matrix is indefinite) for";
        for (std::size_t k = 0; k < names.size(); ++k) what += (k ? ", '" : " '") + std::string(names[k]) + "'";
    } else {
        for (auto r : rows) involved.emplace_back(names[r]);
        what += "'" + involved[0] + "' ";
        if (rows.size() == 1) what += "has a zero row in G here";
        else {
            what += "is a combination of";
            for (std::size_t k = 1; k < involved.size(); ++k) what += (k > 1 ? ", '" : " '") + involved[k] + "'";
            what += " here";
        }
    }
    what += " (the multipliers are not determined: a dead point or a bifurcation of the mechanism?)";
    throw SingularConstraints(what, std::move(involved));
}

} // namespace detail

/// The factored saddle-point matrix [M −Gᵀ; G 0] of a state, for solving
///   M x − Gᵀλ = b,   G x = g
/// for several right-hand sides (the accelerations, then the columns of a Jacobian by
/// implicit differentiation): x = u + Yλ with u = M⁻¹b, Y = M⁻¹Gᵀ, and (G Y) λ = g − G u.
/// `M` holds the lower triangle of the symmetric N×N mass matrix (row-major), `G` is C×N
/// row-major; both must outlive the factor. Throws SingularMassMatrix when M is singular,
/// SingularConstraints (naming the constraints involved, from `names`) when G M⁻¹ Gᵀ is;
/// `where` and `t` go into messages. Fixed size, no allocation in the regular case.
template <std::size_t N, std::size_t C>
class KktFactor {
public:
    KktFactor(const double* M, const double* G, const std::array<std::string_view, C>& names, std::string_view where,
              double t) {
        const detail::KktFactored f = core_.factor(M, G);
        if (f.ok()) return;
        if (f.part == detail::KktFactored::schur && f.status == detail::Factored::singular)
            detail::throw_singular_constraints(G, C, N, names, where, t);
        detail::throw_factor_failure(f.status, f.pivot, f.pivot_value);
    }

    /// x (N) and λ (C) for the right-hand side b (N), g (C).
    void solve(const double* b, const double* g, double* x, double* lambda) const { core_.solve(b, g, x, lambda); }

    /// The same for `cols` right-hand sides at once: B (N×cols) and Gc (C×cols) row-major
    /// give X (N×cols) row-major.
    void solve_columns(std::size_t cols, const double* B, const double* Gc, double* X) const {
        core_.solve_columns(cols, B, Gc, X);
    }

private:
    detail::KktCore<N, C> core_;
};

/// Without constraints: M x = b.
template <std::size_t N>
class KktFactor<N, 0> {
public:
    explicit KktFactor(const double* M) {
        if (const detail::KktFactored f = core_.factor(M); !f.ok()) detail::throw_factor_failure(f.status, f.pivot, f.pivot_value);
    }
    void solve(const double* b, const double* g, double* x, double* lambda) const { core_.solve(b, g, x, lambda); }
    void solve_columns(std::size_t cols, const double* B, const double* Gc, double* X) const {
        core_.solve_columns(cols, B, Gc, X);
    }

private:
    detail::KktCore<N, 0> core_;
};

/// q'' and λ of M q'' = f + Gᵀλ, G q'' = γ (KktFactor), checked finite: NonFiniteResult
/// otherwise.
template <std::size_t N, std::size_t C>
inline void solve_constrained(const double (&M)[N * N], const double (&f)[N], const double (&G)[C * N],
                              const double (&gamma)[C], std::span<double> qddot, std::span<double> lambda,
                              const std::array<std::string_view, C>& names, std::string_view where, double t) {
    const KktFactor<N, C> kkt(M, G, names, where, t);
    kkt.solve(f, gamma, qddot.data(), lambda.data());
    for (std::size_t i = 0; i < N; ++i)
        if (!std::isfinite(qddot[i]))
            throw NonFiniteResult(std::string(where) + ": non-finite result at t = " + std::to_string(t));
    for (std::size_t k = 0; k < C; ++k)
        if (!std::isfinite(lambda[k]))
            throw NonFiniteResult(std::string(where) + ": non-finite multiplier at t = " + std::to_string(t));
}

} // namespace phynjo::runtime
