// The linearization about a state, exact: the state substituted into M, f, G, γ and the
// Jacobian entries of derive_jacobians, the saddle-point system solved symbolically
// (Gauss–Jordan, pivots chosen by their size at the parameters' defaults), every entry
// simplified. Eigenvalues of A at the defaults by Eigen.
#include "phynjo/codegen/linearize.hpp"

#include "phynjo/cas/cas.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace phynjo::codegen {

namespace {

using cas::Expr;

/// Gauss–Jordan elimination of K X = R (see solve_exact).
std::vector<Expr> gauss_jordan(std::vector<Expr> K, std::vector<Expr> R, std::size_t p, std::size_t c,
                              const cas::Bindings<double>& at, const std::string& singular) {
    auto value = [&](Expr e) { return std::fabs(cas::evaluate(e, at)); };
    double scale = 0;
    for (Expr e : K) scale = std::max(scale, value(e));
    for (std::size_t col = 0; col < p; ++col) {
        std::size_t best = col;
        double best_v = -1;
        for (std::size_t r = col; r < p; ++r)
            if (const double v = value(K[r * p + col]); v > best_v) {
                best_v = v;
                best = r;
            }
        if (!(best_v > 1e-12 * scale)) throw LinearizeError(singular);
        if (best != col) {
            for (std::size_t j = 0; j < p; ++j) std::swap(K[col * p + j], K[best * p + j]);
            for (std::size_t j = 0; j < c; ++j) std::swap(R[col * c + j], R[best * c + j]);
        }
        const Expr inv = cas::pow(K[col * p + col], Expr(-1));
        for (std::size_t r = 0; r < p; ++r) {
            if (r == col || K[r * p + col].is_zero()) continue;
            const Expr factor = cas::simplify(K[r * p + col] * inv);
            for (std::size_t j = col; j < p; ++j) K[r * p + j] = cas::simplify(K[r * p + j] - factor * K[col * p + j]);
            for (std::size_t j = 0; j < c; ++j) R[r * c + j] = cas::simplify(R[r * c + j] - factor * R[col * c + j]);
        }
    }
    for (std::size_t r = 0; r < p; ++r)
        for (std::size_t j = 0; j < c; ++j) R[r * c + j] = cas::simplify(R[r * c + j] / K[r * p + r]);
    return R;
}

/// The determinant of the submatrix of A (row-major, `stride` columns) on `rows` × `cols`
/// (equal sizes), expanded: Laplace expansion along the rows, memoized on the set of
/// columns left (2^k subsets for k columns).
Expr determinant(const std::vector<Expr>& A, std::size_t stride, const std::vector<std::size_t>& rows,
                 const std::vector<std::size_t>& cols) {
    const std::size_t k = rows.size();
    std::unordered_map<std::uint32_t, Expr> memo;
    auto rec = [&](auto&& self, std::uint32_t left, std::size_t r) -> Expr {
        if (r == k) return Expr(1);
        if (auto it = memo.find(left); it != memo.end()) return it->second;
        std::vector<Expr> terms;
        int sign = 1;
        for (std::size_t c = 0; c < k; ++c) {
            if (!(left >> c & 1u)) continue;
            const Expr a = A[rows[r] * stride + cols[c]];
            if (!a.is_zero()) terms.push_back(Expr(sign) * a * self(self, left & ~(1u << c), r + 1));
            sign = -sign;
        }
        const Expr d = terms.empty() ? Expr(0) : cas::expand(cas::add(terms));
        memo.emplace(left, d);
        return d;
    };
    return rec(rec, k == 0 ? 0u : (k >= 32 ? ~0u : (1u << k) - 1), 0);
}

/// The factors of one product as (base, positive integer power); other factors power 1.
std::vector<std::pair<Expr, long>> monomial_factors(Expr term) {
    std::vector<std::pair<Expr, long>> out;
    auto one = [&](Expr f) {
        if (f.kind() == cas::Kind::Pow && f.args()[1].is_integer() && f.args()[1].value() > 0 &&
            f.args()[1].value() < 1000)
            out.emplace_back(f.args()[0], f.args()[1].value().get_num().get_si());
        else if (f.kind() != cas::Kind::Number && f.kind() != cas::Kind::Pow)
            out.emplace_back(f, 1);
    };
    if (term.kind() == cas::Kind::Mul)
        for (Expr f : term.args()) one(f);
    else one(term);
    return out;
}

/// The largest monomial dividing every term of the expanded expression `e` (a sum, or one
/// product), as (base, power) pairs: what a numerator and a determinant may share.
std::vector<std::pair<Expr, long>> monomial_content(Expr e) {
    if (e.kind() != cas::Kind::Add) return monomial_factors(e);
    const Expr constant = cas::numeric_part(e);
    if (!constant.is_null() && !constant.is_zero()) return {};
    std::vector<std::pair<Expr, long>> common;
    bool first = true;
    for (Expr term : e.args()) {
        const auto f = monomial_factors(term);
        if (first) common = f;
        else {
            std::vector<std::pair<Expr, long>> kept;
            for (const auto& [base, k] : common)
                for (const auto& [b2, k2] : f)
                    if (b2 == base) kept.emplace_back(base, std::min(k, k2));
            common = std::move(kept);
        }
        first = false;
        if (common.empty()) break;
    }
    return common;
}

/// The monomial both contents share, as an expression (1 when none).
Expr shared_monomial(const std::vector<std::pair<Expr, long>>& a, const std::vector<std::pair<Expr, long>>& b) {
    std::vector<Expr> factors;
    for (const auto& [base, k] : a)
        for (const auto& [b2, k2] : b)
            if (b2 == base) factors.push_back(cas::pow(base, Expr(std::min(k, k2))));
    return factors.empty() ? Expr(1) : cas::mul(factors);
}

/// Largest system solved by the adjugate (Cramer's rule): its results are one expanded
/// numerator over the expanded determinant, so a monomial determinant cancels (the
/// cart-pole's g·m/M); above, Gauss–Jordan.
constexpr std::size_t kAdjugateMax = 8;

/// Solves K X = R exactly (K p×p, R p×c, row-major). Up to kAdjugateMax unknowns by the
/// adjugate, X = adj(K) R / det K; above by Gauss–Jordan, pivoting on the largest entry at
/// `at` (the parameters' defaults). Throws LinearizeError when K is singular there.
std::vector<Expr> solve_exact(std::vector<Expr> K, std::vector<Expr> R, std::size_t p, std::size_t c,
                              const cas::Bindings<double>& at, const std::string& singular) {
    if (p <= kAdjugateMax) {
        std::vector<std::size_t> all(p);
        for (std::size_t i = 0; i < p; ++i) all[i] = i;
        const Expr D = determinant(K, p, all, all);
        double scale = 0;
        for (Expr e : K) scale = std::max(scale, std::fabs(cas::evaluate(e, at)));
        const double d = std::fabs(cas::evaluate(D, at));
        if (!(d > 1e-12 * std::pow(std::max(scale, 1e-300), static_cast<double>(p)))) throw LinearizeError(singular);
        // cofactors C_ij = (−1)^(i+j) det(K without row i and column j)
        std::vector<Expr> C(p * p);
        for (std::size_t i = 0; i < p; ++i)
            for (std::size_t j = 0; j < p; ++j) {
                std::vector<std::size_t> rows, cols;
                for (std::size_t r = 0; r < p; ++r)
                    if (r != i) rows.push_back(r);
                for (std::size_t q = 0; q < p; ++q)
                    if (q != j) cols.push_back(q);
                C[i * p + j] = ((i + j) % 2 ? Expr(-1) : Expr(1)) * determinant(K, p, rows, cols);
            }
        const Expr inv = cas::pow(D, Expr(-1));
        const auto D_content = monomial_content(D);
        std::vector<Expr> X(p * c);
        for (std::size_t j = 0; j < p; ++j) // x_j = Σ_i C_ij r_i / D
            for (std::size_t col = 0; col < c; ++col) {
                std::vector<Expr> terms;
                for (std::size_t i = 0; i < p; ++i) terms.push_back(C[i * p + j] * R[i * c + col]);
                const Expr N = cas::expand(cas::add(terms));
                // a monomial the numerator shares with the determinant cancels: the example
                // cart-pole's −3 g lh² mp²/(4 lh² mc mp + lh² mp²) reads −3 g mp/(4 mc + mp)
                const Expr g = N.is_zero() ? Expr(1) : shared_monomial(monomial_content(N), D_content);
                if (g.is_one()) X[j * c + col] = cas::simplify(N * inv);
                else {
                    const Expr ginv = cas::pow(g, Expr(-1));
                    X[j * c + col] = cas::simplify(cas::expand(N * ginv) * cas::pow(cas::expand(D * ginv), Expr(-1)));
                }
            }
        return X;
    }
    return gauss_jordan(std::move(K), std::move(R), p, c, at, singular);
}


} // namespace

Linearization linearize(const Model& model, const EquationsOfMotion& derived,
                        const std::vector<std::pair<std::string, Expr>>& at) {
    EquationsOfMotion eom = derived;
    derive_jacobians(model, eom);
    const std::size_t n = eom.dof, m = eom.n_constraints, p = n + m;
    Linearization lin;
    const auto q = model.coordinate_symbols();
    std::unordered_map<Expr, Expr> sub;
    for (std::size_t i = 0; i < n; ++i) {
        sub[q[i]] = Expr(0);
        sub[cas::velocity(q[i])] = Expr(0);
    }
    sub[cas::time_symbol()] = Expr(0);
    std::vector<Expr> parameters;
    cas::Bindings<double> defaults;
    for (const Parameter& par : model.parameters) {
        parameters.push_back(par.symbol);
        defaults[par.symbol] = par.default_value;
        lin.defaults.emplace_back(par.name, par.default_value);
        if (par.input) {
            lin.input_names.push_back(par.name);
            sub[par.symbol] = par.value; // u0: the input's default unless --at gives it
        }
    }
    for (const auto& [written, value] : at) {
        std::string name = written;
        const bool velocity = !name.empty() && name.back() == '\'';
        if (velocity) name.pop_back();
        Expr target;
        if (name == "t" && !velocity) target = cas::time_symbol();
        for (const Parameter& par : model.parameters)
            if (par.input && par.name == name && !velocity) target = par.symbol;
        for (std::size_t i = 0; i < n && target.is_null(); ++i)
            if (model.coordinates[i].name == name) target = velocity ? cas::velocity(q[i]) : q[i];
        if (target.is_null())
            throw LinearizeError("'" + written + "' is not a coordinate, a velocity (x'), an input or t of model " +
                                 model.name);
        for (Expr v : cas::free_variables(value))
            if (std::find(parameters.begin(), parameters.end(), v) == parameters.end() || sub.count(v))
                throw LinearizeError("the value of " + written + " may use numbers and parameters only, not '" +
                                     cas::to_string(v) + "'");
        sub[target] = value;
    }
    for (std::size_t i = 0; i < n; ++i) lin.state_names.push_back(model.coordinates[i].name);
    for (std::size_t i = 0; i < n; ++i) lin.state_names.push_back(model.coordinates[i].name + "'");
    for (std::size_t i = 0; i < n; ++i) lin.state.push_back(sub[q[i]]);
    for (std::size_t i = 0; i < n; ++i) lin.state.push_back(sub[cas::velocity(q[i])]);
    lin.time = sub[cas::time_symbol()];
    auto here = [&](Expr e) { return cas::simplify(cas::subs(e, sub)); };

    // the saddle-point matrix [M −Gᵀ; G 0] at the state, and q'', λ there
    std::vector<Expr> K(p * p, Expr(0)), rhs(p);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) K[i * p + j] = here(eom.mass_matrix[i * n + j]);
    for (std::size_t k = 0; k < m; ++k)
        for (std::size_t j = 0; j < n; ++j) {
            const Expr g = here(eom.constraint_matrix[k * n + j]);
            K[(n + k) * p + j] = g;
            K[j * p + n + k] = -g;
        }
    for (std::size_t i = 0; i < n; ++i) rhs[i] = here(eom.forcing[i]);
    for (std::size_t k = 0; k < m; ++k) rhs[n + k] = here(eom.gamma[k]);
    const std::string singular = "the equations cannot be solved for the accelerations at this state (the mass "
                                 "matrix, or G M^-1 G^T with constraints, is singular there)";
    const std::vector<Expr> solution = solve_exact(K, rhs, p, 1, defaults, singular);
    for (std::size_t i = 0; i < n; ++i) sub[eom.acceleration_symbols[i]] = solution[i];
    for (std::size_t k = 0; k < m; ++k) sub[eom.multiplier_symbols[k]] = solution[n + k];

    // A = [0 I; ∂q''/∂q ∂q''/∂q'], B = [0; ∂q''/∂u]
    auto lower = [&](const std::vector<Expr>& dr, const std::vector<Expr>& dc, std::size_t cols) {
        std::vector<Expr> R(p * cols);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < cols; ++j) R[i * cols + j] = here(dr[i * cols + j]);
        for (std::size_t k = 0; k < m; ++k)
            for (std::size_t j = 0; j < cols; ++j) R[(n + k) * cols + j] = here(dc[k * cols + j]);
        return cols == 0 ? R : solve_exact(K, R, p, cols, defaults, singular);
    };
    const std::size_t N = 2 * n, U = lin.input_names.size();
    const auto dA = lower(eom.jacobian_r, eom.jacobian_c, N);
    const auto dB = lower(eom.input_r, eom.input_c, U);
    lin.A.assign(N * N, Expr(0));
    lin.B.assign(N * U, Expr(0));
    for (std::size_t i = 0; i < n; ++i) {
        lin.A[i * N + n + i] = Expr(1);
        for (std::size_t j = 0; j < N; ++j) lin.A[(n + i) * N + j] = dA[i * N + j];
        for (std::size_t j = 0; j < U; ++j) lin.B[(n + i) * U + j] = dB[i * U + j];
    }
    for (std::size_t i = 0; i < n; ++i) lin.rate.push_back(lin.state[n + i]);
    for (std::size_t i = 0; i < n; ++i) lin.rate.push_back(solution[i]);
    for (Expr r : lin.rate) lin.rate_values.push_back(cas::evaluate(r, defaults));

    Eigen::MatrixXd An(N, N);
    for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < N; ++j) {
            const double a = cas::evaluate(lin.A[i * N + j], defaults);
            An(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = a;
            lin.A_values.push_back(a);
        }
    const Eigen::EigenSolver<Eigen::MatrixXd> solver(An, false);
    for (Eigen::Index k = 0; k < solver.eigenvalues().size(); ++k) lin.eigenvalues.push_back(solver.eigenvalues()[k]);
    std::stable_sort(lin.eigenvalues.begin(), lin.eigenvalues.end(), [](auto a, auto b) {
        return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag();
    });
    return lin;
}

namespace {

std::string number(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

std::string complex_text(std::complex<double> z, double scale) {
    const double tiny = 1e-12 * std::max(1.0, scale);
    const double re = std::fabs(z.real()) <= tiny ? 0.0 : z.real(), im = std::fabs(z.imag()) <= tiny ? 0.0 : z.imag();
    if (im == 0) return number(re);
    return (re == 0 ? "" : number(re) + (im > 0 ? " + " : " - ")) + (re == 0 && im < 0 ? "-" : "") + number(std::fabs(im)) + "i";
}

} // namespace

std::string emit_linear(const Model& model, const Linearization& lin, bool latex) {
    const std::size_t N = lin.state_names.size(), U = lin.input_names.size();
    std::ostringstream s;
    auto print = [&](Expr e) { return latex ? cas::to_latex(e) : cas::to_string(e); };
    bool proved = true;
    for (Expr r : lin.rate) proved = proved && r.is_zero();
    // not proved zero: its value at the defaults against the size of A's entries there
    double residual = 0, size = 1;
    for (double v : lin.rate_values) residual = std::max(residual, std::fabs(v));
    for (double v : lin.A_values) size = std::max(size, std::fabs(v));
    const bool numerically = !proved && residual <= 1e-12 * size;
    const bool equilibrium = proved || numerically;
    double scale = 0;
    for (auto z : lin.eigenvalues) scale = std::max(scale, std::abs(z));
    std::size_t unstable = 0;
    for (auto z : lin.eigenvalues) unstable += z.real() > 1e-9 * std::max(1.0, scale) ? 1 : 0;
    const char* c = latex ? "% " : "# ";
    s << c << "Linearization of " << model.name << " about";
    for (std::size_t i = 0; i < N; ++i) s << (i ? ", " : " ") << lin.state_names[i] << " = " << cas::to_string(lin.state[i]);
    if (!lin.time.is_zero()) s << " at t = " << cas::to_string(lin.time);
    s << "\n" << c << "  y' = y'(y0) + A (y - y0) + B (u - u0),  y = (";
    for (std::size_t i = 0; i < N; ++i) s << (i ? ", " : "") << lin.state_names[i];
    s << "),  u = (";
    for (std::size_t i = 0; i < U; ++i) s << (i ? ", " : "") << lin.input_names[i];
    s << ")\n" << c << "y'(y0) = (";
    for (std::size_t i = 0; i < N; ++i) s << (i ? ", " : "") << cas::to_string(lin.rate[i]);
    s << ")";
    if (proved) s << ": an equilibrium\n";
    else {
        s << "\n" << c << "  = (";
        for (std::size_t i = 0; i < N; ++i) s << (i ? ", " : "") << number(lin.rate_values[i]);
        s << ") at the parameters' defaults: ";
        if (numerically && residual == 0)
            s << "an equilibrium at these values (not for every value of the parameters)\n";
        else if (numerically)
            s << "an equilibrium not proved symbolically, numerically zero to " << number(residual) << "\n";
        else
            s << "not an equilibrium (a linearization about a moving state)\n";
    }
    auto matrix = [&](const char* name, const std::vector<Expr>& M, std::size_t cols) {
        if (latex) {
            s << name << " = \\begin{pmatrix}\n";
            for (std::size_t i = 0; i < N; ++i) {
                s << "  ";
                for (std::size_t j = 0; j < cols; ++j) s << (j ? " & " : "") << print(M[i * cols + j]);
                s << (i + 1 < N ? " \\\\\n" : "\n");
            }
            s << "\\end{pmatrix}\n";
            return;
        }
        s << name << " =\n";
        for (std::size_t i = 0; i < N; ++i) {
            s << "  [";
            for (std::size_t j = 0; j < cols; ++j) s << (j ? ", " : "") << print(M[i * cols + j]);
            s << "]\n";
        }
    };
    matrix("A", lin.A, N);
    if (U > 0) matrix("B", lin.B, U);
    else s << c << "B: the model has no inputs\n";
    s << c << "eigenvalues of A at the parameters' defaults (";
    for (std::size_t k = 0; k < lin.defaults.size(); ++k)
        s << (k ? ", " : "") << lin.defaults[k].first << " = " << number(lin.defaults[k].second);
    s << "):\n" << c << " ";
    for (std::size_t k = 0; k < lin.eigenvalues.size(); ++k)
        s << (k ? ", " : " ") << complex_text(lin.eigenvalues[k], scale);
    s << "\n" << c;
    if (unstable > 0)
        s << unstable << " unstable mode" << (unstable > 1 ? "s" : "") << " (eigenvalues with a positive real part): "
          << (equilibrium ? "the equilibrium is unstable" : "nearby motions separate") << "\n";
    else
        s << "no eigenvalue with a positive real part"
          << (equilibrium ? " (marginal or stable to first order: a conservative model's equilibria have purely "
                            "imaginary pairs at best)"
                          : "")
          << "\n";
    return s.str();
}

} // namespace phynjo::codegen
