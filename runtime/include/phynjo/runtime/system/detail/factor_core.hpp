#pragma once
/// \file
/// The arithmetic of the solves of generated code, without a header and without throwing:
/// LDLᵀ of a symmetric N×N matrix with a pivoted-LU fallback (SymmetricCore), the saddle-point
/// system of a constrained model through the Schur complement (KktCore), and which constraint
/// rows depend on earlier ones (dependent_rows). Each reports a failure as a status; the
/// runtime's SymmetricFactor and KktFactor (symmetric_solve.hpp, kkt_solve.hpp) turn it into
/// their typed exceptions, a model kernel (kernel_support.hpp) into its status codes. One code
/// for both: a kernel solves with the operations, so the bits, of the CMake-built model.

namespace phynjo::runtime {

/// The relative size below which a pivot (or a 2×2 determinant) counts as zero: the mass
/// matrix is then singular at that state.
inline constexpr double kSingularTolerance = 1e-13;

namespace detail {

/// std::size_t, without <cstddef>.
using index = decltype(sizeof 0);

/// What a factorization found: the matrix factored, a NaN or infinite entry, or a singular
/// matrix (an LU pivot below kSingularTolerance times the largest entry).
enum class Factored { ok, non_finite, singular };

/// A symmetric N×N matrix factored for solving with several right-hand sides. LDLᵀ without
/// pivoting first (every positive definite matrix: the usual kinetic energy); when a pivot is
/// not positive — an indefinite but invertible matrix, e.g. the mass matrix of Bateman's dual
/// oscillator — LU with partial pivoting of the same matrix.
template <index N>
class SymmetricCore {
public:
    /// Factors the matrix whose lower triangle is `A` (row-major N×N; the upper part is not
    /// read). On Factored::singular, pivot() and pivot_value() say where.
    Factored factor(const double* A) {
        double top = 0; // the largest entry of the lower triangle
        for (index i = 0; i < N; ++i)
            for (index j = 0; j <= i; ++j) top = larger(top, __builtin_fabs(A[i * N + j]));
        for (index i = 0; i < N * N; ++i) F_[i] = A[i];
        // LDLᵀ: L below the diagonal, D on it; a pivot not above kSingularTolerance·max|A|
        // hands over to pivoted LU (which then decides whether A is singular).
        for (index j = 0; j < N; ++j) {
            double d = F_[j * N + j];
            for (index k = 0; k < j; ++k) d -= F_[j * N + k] * F_[j * N + k] * F_[k * N + k];
            if (!__builtin_isfinite(d)) return Factored::non_finite;
            if (!(d > kSingularTolerance * top)) {
                ldlt_ = false;
                break;
            }
            F_[j * N + j] = d;
            for (index i = j + 1; i < N; ++i) {
                double s = F_[i * N + j];
                for (index k = 0; k < j; ++k) s -= F_[i * N + k] * F_[j * N + k] * F_[k * N + k];
                F_[i * N + j] = s / d;
            }
        }
        if (ldlt_) return Factored::ok;
        // LU with partial pivoting on the full matrix rebuilt from the lower triangle. The
        // multiplier of row position r at step c is kept in F_[r][c] (rows are swapped from
        // column c on only), so solve() replays the elimination step by step.
        double scale = 0;
        for (index i = 0; i < N; ++i)
            for (index j = 0; j < N; ++j) {
                F_[i * N + j] = i >= j ? A[i * N + j] : A[j * N + i];
                scale = larger(scale, __builtin_fabs(F_[i * N + j]));
            }
        for (index c = 0; c < N; ++c) {
            index piv = c;
            for (index r = c + 1; r < N; ++r)
                if (__builtin_fabs(F_[r * N + c]) > __builtin_fabs(F_[piv * N + c])) piv = r;
            if (!(__builtin_fabs(F_[piv * N + c]) > kSingularTolerance * scale)) {
                pivot_ = c;
                pivot_value_ = F_[piv * N + c];
                return Factored::singular;
            }
            perm_[c] = piv;
            if (piv != c)
                for (index j = c; j < N; ++j) swap(F_[c * N + j], F_[piv * N + j]);
            for (index r = c + 1; r < N; ++r) {
                const double f = F_[r * N + c] / F_[c * N + c];
                for (index j = c + 1; j < N; ++j) F_[r * N + j] -= f * F_[c * N + j];
                F_[r * N + c] = f;
            }
        }
        return Factored::ok;
    }

    /// Overwrites b (length N) with x solving A x = b.
    void solve(double* b) const {
        if (ldlt_) {
            for (index i = 0; i < N; ++i)
                for (index k = 0; k < i; ++k) b[i] -= F_[i * N + k] * b[k];
            for (index i = 0; i < N; ++i) b[i] /= F_[i * N + i];
            for (index i = N; i-- > 0;)
                for (index k = i + 1; k < N; ++k) b[i] -= F_[k * N + i] * b[k];
            return;
        }
        for (index c = 0; c < N; ++c) {
            if (perm_[c] != c) swap(b[c], b[perm_[c]]);
            for (index r = c + 1; r < N; ++r) b[r] -= F_[r * N + c] * b[c];
        }
        for (index i = N; i-- > 0;) {
            double x = b[i];
            for (index j = i + 1; j < N; ++j) x -= F_[i * N + j] * b[j];
            b[i] = x / F_[i * N + i];
        }
    }

    /// True when the LDLᵀ factorization succeeded (the matrix is positive definite).
    [[nodiscard]] bool positive_definite() const noexcept { return ldlt_; }
    /// The LU step that found no pivot, and the largest candidate it had.
    [[nodiscard]] index pivot() const noexcept { return pivot_; }
    [[nodiscard]] double pivot_value() const noexcept { return pivot_value_; }

private:
    /// std::max(a, b): b when a < b, else a.
    static double larger(double a, double b) { return a < b ? b : a; }
    static void swap(double& a, double& b) {
        const double t = a;
        a = b;
        b = t;
    }

    double F_[N * N];
    index perm_[N]{};
    bool ldlt_ = true;
    index pivot_ = 0;
    double pivot_value_ = 0;
};

/// What a saddle-point factorization found: M's factorization (its status, SymmetricCore's
/// pivot) or, M factored, that of G M⁻¹ Gᵀ.
struct KktFactored {
    enum Part { mass, schur } part = mass;
    Factored status = Factored::ok;
    index pivot = 0;
    double pivot_value = 0;
    [[nodiscard]] bool ok() const noexcept { return status == Factored::ok; }
};

/// The factored saddle-point matrix [M −Gᵀ; G 0] of a state, for solving
///   M x − Gᵀλ = b,   G x = g
/// for several right-hand sides: x = u + Yλ with u = M⁻¹b, Y = M⁻¹Gᵀ, and (G Y) λ = g − G u.
/// `M` holds the lower triangle of the symmetric N×N mass matrix (row-major), `G` is C×N
/// row-major and must outlive the factor.
template <index N, index C>
class KktCore {
public:
    KktFactored factor(const double* M, const double* G) {
        G_ = G;
        if (const Factored f = m_.factor(M); f != Factored::ok)
            return {KktFactored::mass, f, m_.pivot(), m_.pivot_value()};
        for (index k = 0; k < C; ++k) {
            for (index i = 0; i < N; ++i) Y_[k][i] = G_[k * N + i];
            m_.solve(Y_[k]);
        }
        double S[C * C];
        for (index a = 0; a < C; ++a)
            for (index b = 0; b <= a; ++b) {
                double s = 0;
                for (index i = 0; i < N; ++i) s += G_[a * N + i] * Y_[b][i];
                S[a * C + b] = s;
            }
        const Factored f = s_.factor(S);
        return {KktFactored::schur, f, s_.pivot(), s_.pivot_value()};
    }

    /// x (N) and λ (C) for the right-hand side b (N), g (C).
    void solve(const double* b, const double* g, double* x, double* lambda) const {
        double u[N], r[C];
        for (index i = 0; i < N; ++i) u[i] = b[i];
        m_.solve(u);
        for (index a = 0; a < C; ++a) {
            double ga = g[a];
            for (index i = 0; i < N; ++i) ga -= G_[a * N + i] * u[i];
            r[a] = ga;
        }
        s_.solve(r);
        for (index i = 0; i < N; ++i) {
            double v = u[i];
            for (index k = 0; k < C; ++k) v += Y_[k][i] * r[k];
            x[i] = v;
        }
        for (index k = 0; k < C; ++k) lambda[k] = r[k];
    }

    /// The same for `cols` right-hand sides at once: B (N×cols) and Gc (C×cols) row-major
    /// give X (N×cols) row-major.
    void solve_columns(index cols, const double* B, const double* Gc, double* X) const {
        for (index j = 0; j < cols; ++j) {
            double b[N], g[C], x[N], l[C];
            for (index i = 0; i < N; ++i) b[i] = B[i * cols + j];
            for (index k = 0; k < C; ++k) g[k] = Gc[k * cols + j];
            solve(b, g, x, l);
            for (index i = 0; i < N; ++i) X[i * cols + j] = x[i];
        }
    }

private:
    SymmetricCore<N> m_;
    const double* G_ = nullptr;
    double Y_[C][N];
    SymmetricCore<C> s_;
};

/// Without constraints: M x = b.
template <index N>
class KktCore<N, 0> {
public:
    KktFactored factor(const double* M, const double* = nullptr) {
        return {KktFactored::mass, m_.factor(M), m_.pivot(), m_.pivot_value()};
    }
    void solve(const double* b, const double*, double* x, double*) const {
        for (index i = 0; i < N; ++i) x[i] = b[i];
        m_.solve(x);
    }
    void solve_columns(index cols, const double* B, const double*, double* X) const {
        for (index j = 0; j < cols; ++j) {
            double x[N];
            for (index i = 0; i < N; ++i) x[i] = B[i * cols + j];
            m_.solve(x);
            for (index i = 0; i < N; ++i) X[i * cols + j] = x[i];
        }
    }

private:
    SymmetricCore<N> m_;
};

/// The constraints involved when G M⁻¹ Gᵀ is singular: the first row of G (C×N, row-major)
/// that is a combination of earlier rows at this state, then those rows, written to `rows`
/// (at most C); returns how many (0 when G has full rank: M is what makes G M⁻¹ Gᵀ
/// singular). Scratch: R (C·N), T (C·C), pivot_col (C). Error path only.
inline index dependent_rows(const double* G, index C, index N, double* R, double* T, index* pivot_col, index* rows) {
    for (index k = 0; k < C * N; ++k) R[k] = G[k]; // reduced rows; R = T·G
    for (index k = 0; k < C * C; ++k) T[k] = 0.0;
    for (index k = 0; k < C; ++k) T[k * C + k] = 1;
    double scale = 0;
    for (index k = 0; k < C * N; ++k) scale = scale < __builtin_fabs(R[k]) ? __builtin_fabs(R[k]) : scale;
    for (index k = 0; k < C; ++k) pivot_col[k] = N;
    for (index k = 0; k < C; ++k) {
        for (index e = 0; e < k; ++e) { // eliminate with the earlier independent rows
            const index c = pivot_col[e];
            if (c == N) continue;
            const double f = R[k * N + c] / R[e * N + c];
            for (index j = 0; j < N; ++j) R[k * N + j] -= f * R[e * N + j];
            for (index j = 0; j < C; ++j) T[k * C + j] -= f * T[e * C + j];
        }
        index best = N;
        for (index j = 0; j < N; ++j)
            if (__builtin_fabs(R[k * N + j]) > 1e-9 * scale &&
                (best == N || __builtin_fabs(R[k * N + j]) > __builtin_fabs(R[k * N + best])))
                best = j;
        if (best == N) { // row k depends on the earlier rows with the coefficients in T
            index n = 0;
            rows[n++] = k;
            for (index j = 0; j < k; ++j)
                if (__builtin_fabs(T[k * C + j]) > 1e-9) rows[n++] = j;
            return n;
        }
        pivot_col[k] = best;
    }
    return 0; // G has full rank: M is what makes G M⁻¹ Gᵀ singular
}

} // namespace detail
} // namespace phynjo::runtime
