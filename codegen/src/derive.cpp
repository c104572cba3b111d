#include "phynjo/codegen/equations.hpp"

#include "phynjo/cas/cas.hpp"

#include <cmath>
#include <random>

namespace phynjo::codegen {

namespace {

using cas::Expr;

/// simplify() (expansion, sin²+cos² = 1) for small expressions, where it makes the
/// printed equations readable; for large ones only the sin²+cos² rule on the form as
/// derived (expansion costs much and does not pay: the emitter factors sums anyway).
Expr tidy(Expr e) {
    if (cas::tree_size(e) <= 150) return cas::simplify(e);
    return cas::trig_simplify_only(e);
}

/// The first column of the rows×cols matrix A (row-major expressions) that is linearly
/// dependent on the earlier columns at every one of a few random points (random q, q', t and
/// parameter values), or nothing.
std::optional<std::size_t> first_dependent_column(const Model& model, const std::vector<Expr>& A_expr, std::size_t rows,
                                                  std::size_t cols) {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> coord(-1.3, 1.3), positive(0.5, 2.0);
    std::optional<std::size_t> worst;
    for (int trial = 0; trial < 3; ++trial) {
        cas::Bindings<double> at;
        for (const auto& c : model.coordinates) {
            at[c.symbol] = coord(rng);
            at[cas::velocity(c.symbol)] = coord(rng);
        }
        for (const auto& p : model.parameters) at[p.symbol] = positive(rng);
        at[cas::time_symbol()] = positive(rng);
        std::vector<double> A;
        try {
            A = cas::evaluate(A_expr, at);
        } catch (const cas::Error&) {
            return std::nullopt; // cannot tell here; the runtime check reports it
        }
        double scale = 0;
        for (double v : A) scale = std::max(scale, std::fabs(v));
        // Gaussian elimination over columns in order, row pivoting.
        std::vector<bool> used(rows, false);
        std::optional<std::size_t> dependent;
        for (std::size_t col = 0; col < cols && !dependent; ++col) {
            std::size_t best = rows;
            double best_v = 0;
            for (std::size_t r = 0; r < rows; ++r)
                if (!used[r] && std::fabs(A[r * cols + col]) > best_v) {
                    best_v = std::fabs(A[r * cols + col]);
                    best = r;
                }
            if (best == rows || best_v <= 1e-10 * std::max(scale, 1e-300)) {
                dependent = col;
                break;
            }
            used[best] = true;
            for (std::size_t r = 0; r < rows; ++r) {
                if (used[r]) continue;
                const double factor = A[r * cols + col] / A[best * cols + col];
                for (std::size_t c = col; c < cols; ++c) A[r * cols + c] -= factor * A[best * cols + c];
            }
        }
        if (!dependent) return std::nullopt; // regular at this point: not identically singular
        worst = dependent;
    }
    return worst;
}

/// When row `k` of G (row-major, n columns) is c times an earlier row j with c free of the
/// state and of t: j, c and d = φ_k − c·φ_j, zero when constraint k repeats j, a nonzero constant
/// when no state satisfies both (`x = l` and `x = 2*l`). Nothing when no such row exists.
struct Multiple {
    std::size_t j;
    Expr c, d;
};
std::optional<Multiple> multiple_of_earlier(const Model& model, const EquationsOfMotion& eom,
                                                                std::size_t k) {
    const std::size_t n = eom.dof;
    auto row = [&](std::size_t r, std::size_t j) { return eom.constraint_matrix[r * n + j]; };
    auto stateless = [&](Expr e) {
        if (cas::contains(e, cas::time_symbol())) return false;
        for (const auto& c : model.coordinates)
            if (cas::contains(e, c.symbol) || cas::contains(e, cas::velocity(c.symbol))) return false;
        return true;
    };
    for (std::size_t j = 0; j < k; ++j) {
        std::size_t first = n;
        for (std::size_t i = 0; i < n && first == n; ++i)
            if (!row(j, i).is_zero()) first = i;
        if (first == n) continue;
        const Expr c = cas::simplify(row(k, first) / row(j, first));
        if (c.is_zero() || !stateless(c)) continue;
        bool multiple = true;
        for (std::size_t i = 0; i < n && multiple; ++i) multiple = cas::simplify(row(k, i) - c * row(j, i)).is_zero();
        if (!multiple) continue;
        const Expr d = cas::simplify(eom.residuals[k] - c * eom.residuals[j]);
        if (stateless(d)) return Multiple{j, c, d};
    }
    return std::nullopt;
}

/// The first coordinate whose column of M is dependent on the earlier ones at every one of a
/// few random points, or nothing.
std::optional<std::size_t> identically_singular(const Model& model, const std::vector<Expr>& M) {
    return first_dependent_column(model, M, model.dof(), model.dof());
}

/// The summands of a sum (with their coefficients; the constant term too), or {e}.
std::vector<Expr> summands(Expr e) {
    if (e.kind() != cas::Kind::Add) return {e};
    std::vector<Expr> out;
    const auto args = e.args();
    const auto coefs = cas::add_coefficients(e);
    for (std::size_t i = 0; i < args.size(); ++i) out.push_back(coefs[i] * args[i]);
    if (!cas::numeric_part(e).is_null() && !cas::numeric_part(e).is_zero()) out.push_back(cas::numeric_part(e));
    return out;
}

/// Fills the constraint part of `eom` (docs/language.md, *Constraints*): G, γ, φ and φ'.
void derive_constraints(const Model& model, const std::vector<Expr>& q, const std::vector<Expr>& qd,
                        EquationsOfMotion& eom) {
    const std::size_t n = model.dof(), m = model.constraints.size();
    const Expr t = cas::time_symbol();
    eom.n_constraints = m;
    eom.constraint_matrix.resize(m * n);
    for (std::size_t k = 0; k < m; ++k) {
        const Constraint& c = model.constraints[k];
        // the expression whose total time derivative is G q'' − γ: φ' (holonomic) or φ
        Expr level;
        if (c.holonomic) {
            std::vector<Expr> terms{cas::diff(c.phi, t)};
            for (std::size_t j = 0; j < n; ++j) {
                const Expr g = cas::diff(c.phi, q[j]);
                eom.constraint_matrix[k * n + j] = tidy(g);
                terms.push_back(g * qd[j]);
            }
            level = cas::add(terms);
        } else {
            level = c.phi;
            for (std::size_t j = 0; j < n; ++j) eom.constraint_matrix[k * n + j] = tidy(cas::diff(c.phi, qd[j]));
        }
        std::vector<Expr> rest{cas::diff(level, t)};
        for (std::size_t j = 0; j < n; ++j) rest.push_back(cas::diff(level, q[j]) * qd[j]);
        eom.gamma.push_back(tidy(-cas::add(rest)));
        eom.residuals.push_back(tidy(c.phi));
        eom.velocity_residuals.push_back(tidy(level));
        eom.residual_terms.push_back(summands(eom.residuals.back()));
        eom.velocity_residual_terms.push_back(summands(eom.velocity_residuals.back()));
    }
}

} // namespace

namespace {
std::optional<EquationsOfMotion> derive_impl(const Model& model, grammar::DiagnosticSink& sink, const DeriveLimits& limits);
}

std::optional<EquationsOfMotion> derive(const Model& model, grammar::DiagnosticSink& sink, const DeriveLimits& limits) {
    // A mathematical error while differentiating (for example 0^(q'^2), whose derivative
    // needs log 0) is the model's: report it at the lagrangian, do not throw.
    try {
        return derive_impl(model, sink, limits);
    } catch (const cas::Error& e) {
        sink.error(model.lagrangian_where.offset, model.lagrangian_where.length,
                   std::string("cannot derive the equations of motion: ") + e.what());
        return std::nullopt;
    }
}

namespace {
std::optional<EquationsOfMotion> derive_impl(const Model& model, grammar::DiagnosticSink& sink, const DeriveLimits& limits) {
    const std::size_t n = model.dof();
    const auto q = model.coordinate_symbols();
    std::vector<Expr> qd(n);
    for (std::size_t i = 0; i < n; ++i) qd[i] = cas::velocity(q[i]);
    const Expr L = model.lagrangian, t = cas::time_symbol();

    EquationsOfMotion eom;
    eom.dof = n;
    eom.momenta.resize(n);
    eom.mass_matrix.resize(n * n);
    eom.forcing.resize(n);
    eom.generalized_forces.resize(n);
    eom.nonconservative_forces.resize(n);
    std::vector<Expr> raw_p(n);
    for (std::size_t i = 0; i < n; ++i) {
        raw_p[i] = cas::diff(L, qd[i]);
        eom.momenta[i] = tidy(raw_p[i]);
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i; j < n; ++j) {
            const Expr m = tidy(cas::diff(raw_p[i], qd[j]));
            eom.mass_matrix[i * n + j] = eom.mass_matrix[j * n + i] = m;
        }
    for (const Expr& m : eom.mass_matrix)
        for (const Expr& v : qd)
            if (cas::contains(m, v)) eom.mass_depends_on_velocities = true;
    if (auto bad = identically_singular(model, eom.mass_matrix)) {
        const Coordinate& c = model.coordinates[*bad];
        const bool absent = !cas::contains(L, qd[*bad]);
        sink.error(c.where.offset, c.where.length,
                   "the mass matrix is singular for every state: the equations of motion cannot be solved for " + c.name +
                       "''" + (absent ? " (" + c.name + "' does not appear in the Lagrangian)" : ""));
        return std::nullopt;
    }
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<Expr> terms{cas::diff(L, q[i]), model.forces[i], -cas::diff(model.dissipation, qd[i])};
        eom.generalized_forces[i] = tidy(cas::add(terms));
        eom.nonconservative_forces[i] = tidy(cas::add(std::span(terms).subspan(1)));
        for (std::size_t j = 0; j < n; ++j) {
            const Expr d = cas::diff(raw_p[i], q[j]);
            if (!d.is_zero()) terms.push_back(-(d * qd[j]));
        }
        terms.push_back(-cas::diff(raw_p[i], t));
        eom.forcing[i] = tidy(cas::add(terms));
    }
    derive_constraints(model, q, qd, eom);
    if (const std::size_t m = eom.n_constraints; m > 0) {
        // G identically rank deficient: the first row dependent on earlier ones (columns of Gᵀ)
        std::vector<Expr> Gt(n * m);
        for (std::size_t k = 0; k < m; ++k)
            for (std::size_t j = 0; j < n; ++j) Gt[j * m + k] = eom.constraint_matrix[k * n + j];
        if (auto bad = first_dependent_column(model, Gt, n, m)) {
            const Constraint& c = model.constraints[*bad];
            std::string what;
            const auto twin = *bad == 0 ? std::nullopt : multiple_of_earlier(model, eom, *bad);
            if (*bad == 0)
                what = "constraint '" + c.name + "' does not restrict the motion: its row of the constraint matrix G is zero";
            else if (twin && !twin->d.is_zero()) {
                what = "constraint '" + c.name + "' is inconsistent with constraint '" + model.constraints[twin->j].name +
                       "': (" + cas::to_string(eom.residuals[*bad]) + ") - " +
                       (twin->c.is_one() ? std::string() : "(" + cas::to_string(twin->c) + ")*") + "(" +
                       cas::to_string(eom.residuals[twin->j]) + ") = " + cas::to_string(twin->d) +
                       ", a constant that is not zero: no state satisfies both";
            }
            else if (twin)
                what = "constraint '" + c.name + "' repeats constraint '" + model.constraints[twin->j].name +
                       "' (its residual is a constant multiple of that one's): remove one of them";
            else
                what = "constraint '" + c.name + "' is redundant for every state: its row of the constraint matrix G is a "
                       "combination of the rows of the constraints before it (a constraint written twice, or implied by "
                       "others" + std::string(*bad >= n ? "; there are more constraints than coordinates" : "") + ")";
            sink.error(c.where.offset, c.where.length, what);
            for (std::size_t k = 0; k < *bad && k < 8; ++k)
                sink.note(model.constraints[k].where.offset, model.constraints[k].where.length,
                          "constraint '" + model.constraints[k].name + "' is here");
            return std::nullopt;
        }
    }
    std::vector<Expr> e_terms;
    for (std::size_t i = 0; i < n; ++i) e_terms.push_back(qd[i] * raw_p[i]);
    e_terms.push_back(-L);
    eom.energy = tidy(cas::add(e_terms));
    std::vector<Expr> all = eom.mass_matrix;
    for (auto* v : {&eom.forcing, &eom.momenta, &eom.generalized_forces, &eom.constraint_matrix, &eom.gamma,
                    &eom.residuals, &eom.velocity_residuals})
        all.insert(all.end(), v->begin(), v->end());
    all.push_back(eom.energy);
    if (const std::size_t nodes = cas::dag_size(all); nodes > limits.max_nodes) {
        sink.error(model.lagrangian_where.offset, model.lagrangian_where.length,
                   "the equations of motion are too large: " + std::to_string(nodes) +
                       " distinct subexpressions (the limit is " + std::to_string(limits.max_nodes) + ")");
        return std::nullopt;
    }
    return eom;
}
} // namespace

/// Fills the Jacobian part of `eom` (see EquationsOfMotion): ∂r/∂y, ∂c/∂y, ∂r/∂u, ∂c/∂u.
/// r and c are linear in â and λ̂, so each entry is a small sum; only nodes that contain the
/// variable are visited (the atom masks), and the derivatives of shared subexpressions are
/// memoized across rows.
void derive_jacobians(const Model& model, EquationsOfMotion& eom) {
    const std::size_t n = eom.dof, m = eom.n_constraints;
    std::vector<Expr> y = model.coordinate_symbols();
    for (std::size_t i = 0; i < n; ++i) y.push_back(cas::velocity(y[i]));
    eom.acceleration_symbols.clear();
    eom.multiplier_symbols.clear();
    for (std::size_t i = 0; i < n; ++i) eom.acceleration_symbols.push_back(cas::symbol("@a" + std::to_string(i)));
    for (std::size_t k = 0; k < m; ++k) eom.multiplier_symbols.push_back(cas::symbol("@l" + std::to_string(k)));
    const auto& a = eom.acceleration_symbols;
    const auto& l = eom.multiplier_symbols;
    std::vector<Expr> r(n), c(m);
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<Expr> terms{eom.forcing[i]};
        for (std::size_t k = 0; k < n; ++k) terms.push_back(-(eom.mass_matrix[i * n + k] * a[k]));
        for (std::size_t k = 0; k < m; ++k) terms.push_back(eom.constraint_matrix[k * n + i] * l[k]);
        r[i] = cas::add(terms);
    }
    for (std::size_t k = 0; k < m; ++k) {
        std::vector<Expr> terms{eom.gamma[k]};
        for (std::size_t i = 0; i < n; ++i) terms.push_back(-(eom.constraint_matrix[k * n + i] * a[i]));
        c[k] = cas::add(terms);
    }
    eom.jacobian_r.resize(n * 2 * n);
    eom.jacobian_c.resize(m * 2 * n);
    eom.momenta_jacobian.resize(n * 2 * n);
    eom.force_jacobian.resize(n * 2 * n);
    for (std::size_t j = 0; j < 2 * n; ++j) {
        for (std::size_t i = 0; i < n; ++i) {
            eom.jacobian_r[i * 2 * n + j] = cas::diff(r[i], y[j]);
            // ∂p/∂q' is M, already derived
            eom.momenta_jacobian[i * 2 * n + j] =
                j < n ? cas::diff(eom.momenta[i], y[j]) : eom.mass_matrix[i * n + (j - n)];
        }
        for (std::size_t k = 0; k < m; ++k) eom.jacobian_c[k * 2 * n + j] = cas::diff(c[k], y[j]);
    }
    // ∂F/∂y with F = ∂L/∂q + N (N the non-conservative part), from the symmetry of the
    // second derivatives of L: ∂²L/∂q_i∂q_j is derived once for j ≥ i, and ∂²L/∂q_i∂q'_j is
    // ∂p_j/∂q_i, derived just above. Half the entries of differentiating F whole, and the
    // two halves of a symmetric block print as one expression (nlink_cart(40):
    // bench/RESULTS.md). Exact either way: the expressions differ, not the functions.
    auto fj = [&](std::size_t i, std::size_t j) -> Expr& { return eom.force_jacobian[i * 2 * n + j]; };
    for (std::size_t i = 0; i < n; ++i) {
        const Expr N = eom.nonconservative_forces[i];
        for (std::size_t j = i; j < n; ++j) fj(i, j) = cas::diff(eom.generalized_forces[i], y[j]);
        for (std::size_t j = 0; j < i; ++j) // ∂F_i/∂q_j = ∂F_j/∂q_i − ∂N_j/∂q_i + ∂N_i/∂q_j
            fj(i, j) = cas::add(std::vector<Expr>{fj(j, i), -cas::diff(eom.nonconservative_forces[j], y[i]), cas::diff(N, y[j])});
        for (std::size_t j = 0; j < n; ++j)
            fj(i, n + j) = cas::add(std::vector<Expr>{eom.momenta_jacobian[j * 2 * n + i], cas::diff(N, y[n + j])}); // ∂p_j/∂q_i + ∂N_i/∂q_j'
    }
    // Inputs (a parameter's value cannot depend on one, so ∂/∂u is the whole derivative).
    std::vector<Expr> inputs;
    for (const Parameter& p : model.parameters)
        if (p.input) inputs.push_back(p.symbol);
    const std::size_t K = inputs.size();
    eom.input_r.resize(n * K);
    eom.input_c.resize(m * K);
    for (std::size_t u = 0; u < K; ++u) {
        for (std::size_t i = 0; i < n; ++i) eom.input_r[i * K + u] = cas::diff(r[i], inputs[u]);
        for (std::size_t k = 0; k < m; ++k) eom.input_c[k * K + u] = cas::diff(c[k], inputs[u]);
    }
}

} // namespace phynjo::codegen
