#pragma once
/// \file
/// What a model kernel (phynjo-lagc --emit=kernel; docs/command-line.md, *Kernels*) includes:
/// the C table's declarations (kernel_abi.h), the lanes' math, the solves of M q'' = f and of
/// the saddle-point system (the runtime's own arithmetic, factor_core.hpp, so the bits of the
/// CMake-built model), Parameters' Derived, and failures as the table's status codes. It
/// includes no C++ standard header, and neither does the kernel: g++ reads a few hundred lines
/// before the model's code instead of a hundred thousand, which is most of a small model's
/// build (0.14 s against 0.4 s for an empty file with <string>, on the bench machine).
#include "phynjo/runtime/system/detail/derived.hpp"
#include "phynjo/runtime/system/detail/factor_core.hpp"
#include "phynjo/runtime/system/detail/lanes.hpp"
#include "phynjo/runtime/system/kernel_abi.h"

namespace phynjo::kernel {

using runtime::detail::index;

/// What a kernel's function throws, caught by its C table's wrapper: a status of kernel_abi.h
/// and the message the runtime throws with it (the text of the CMake-built model's exception).
struct Failure {
    int status;
    char what[480];

    Failure(int code, const char* text) : status(code) {
        what[0] = '\0';
        append(text);
    }
    /// `before`, the number as std::to_string prints it ("%f"), `after`.
    Failure(int code, const char* before, double value, const char* after = "") : Failure(code, before) {
        append_number(value);
        append(after);
    }
    Failure(int code, const char* before, index value, const char* after = "") : Failure(code, before) {
        append_count(value);
        append(after);
    }
    Failure& append(const char* text) {
        index n = __builtin_strlen(what);
        while (*text && n + 1 < sizeof what) what[n++] = *text++;
        what[n] = '\0';
        return *this;
    }
    Failure& append_number(double value) {
        char buffer[360];
        __builtin_snprintf(buffer, sizeof buffer, "%f", value);
        return append(buffer);
    }
    Failure& append_count(index value) {
        char buffer[32];
        __builtin_snprintf(buffer, sizeof buffer, "%zu", value);
        return append(buffer);
    }
};

/// The failure of a mass matrix's factorization, as the runtime's SymmetricFactor words it.
[[noreturn, gnu::cold]] inline void fail_factor(runtime::detail::Factored status, index pivot, double value) {
    if (status == runtime::detail::Factored::non_finite) throw Failure(PHYNJO_NON_FINITE, "mass matrix has a non-finite entry");
    Failure f(PHYNJO_SINGULAR_MASS_MATRIX, "mass matrix is singular (pivot ", pivot, " is ");
    f.append_number(value).append(")");
    throw f;
}

/// G M⁻¹ Gᵀ singular: the constraints involved, as the runtime's throw_singular_constraints
/// words it.
template <index N, index C>
[[noreturn, gnu::cold]] void fail_constraints(const double* G, const char* const* names, const char* where, double t) {
    double R[C * N], T[C * C];
    index pivot_col[C], rows[C];
    const index n = runtime::detail::dependent_rows(G, C, N, R, T, pivot_col, rows);
    Failure f(PHYNJO_SINGULAR_CONSTRAINTS, where);
    f.append(": the constraints are singular at t = ").append_number(t).append(": ");
    if (n == 0) {
        f.append("G M^-1 G^T is singular although G has full rank (the mass matrix is indefinite) for");
        for (index k = 0; k < C; ++k) f.append(k ? ", '" : " '").append(names[k]).append("'");
    } else {
        f.append("'").append(names[rows[0]]).append("' ");
        if (n == 1) f.append("has a zero row in G here");
        else {
            f.append("is a combination of");
            for (index k = 1; k < n; ++k) f.append(k > 1 ? ", '" : " '").append(names[rows[k]]).append("'");
            f.append(" here");
        }
    }
    f.append(" (the multipliers are not determined: a dead point or a bifurcation of the mechanism?)");
    throw f;
}

/// The runtime's KktFactor (kkt_solve.hpp) with failures as Failure.
template <index N, index C>
class KktFactor {
public:
    KktFactor(const double* M, const double* G, const char* const* names, const char* where, double t) {
        const runtime::detail::KktFactored f = core_.factor(M, G);
        if (f.ok()) return;
        if (f.part == runtime::detail::KktFactored::schur && f.status == runtime::detail::Factored::singular)
            fail_constraints<N, C>(G, names, where, t);
        fail_factor(f.status, f.pivot, f.pivot_value);
    }
    void solve(const double* b, const double* g, double* x, double* lambda) const { core_.solve(b, g, x, lambda); }
    void solve_columns(index cols, const double* B, const double* Gc, double* X) const { core_.solve_columns(cols, B, Gc, X); }

private:
    runtime::detail::KktCore<N, C> core_;
};

template <index N>
class KktFactor<N, 0> {
public:
    explicit KktFactor(const double* M) {
        if (const runtime::detail::KktFactored f = core_.factor(M); !f.ok()) fail_factor(f.status, f.pivot, f.pivot_value);
    }
    void solve(const double* b, const double* g, double* x, double* lambda) const { core_.solve(b, g, x, lambda); }
    void solve_columns(index cols, const double* B, const double* Gc, double* X) const { core_.solve_columns(cols, B, Gc, X); }

private:
    runtime::detail::KktCore<N, 0> core_;
};

/// The runtime's solve_symmetric (symmetric_solve.hpp).
template <index N>
inline void solve_symmetric(double (&M)[N * N], double (&b)[N]) {
    runtime::detail::SymmetricCore<N> core;
    if (const runtime::detail::Factored f = core.factor(M); f != runtime::detail::Factored::ok)
        fail_factor(f, core.pivot(), core.pivot_value());
    core.solve(b);
}

/// The runtime's solve_constrained (kkt_solve.hpp): q'' and λ, checked finite.
template <index N, index C>
inline void solve_constrained(const double (&M)[N * N], const double (&f)[N], const double (&G)[C * N], const double (&gamma)[C],
                              double* qddot, double* lambda, const char* const* names, const char* where, double t) {
    const KktFactor<N, C> kkt(M, G, names, where, t);
    kkt.solve(f, gamma, qddot, lambda);
    for (index i = 0; i < N; ++i)
        if (!__builtin_isfinite(qddot[i]))
            throw Failure(PHYNJO_NON_FINITE, where).append(": non-finite result at t = ").append_number(t);
    for (index k = 0; k < C; ++k)
        if (!__builtin_isfinite(lambda[k]))
            throw Failure(PHYNJO_NON_FINITE, where).append(": non-finite multiplier at t = ").append_number(t);
}

} // namespace phynjo::kernel
