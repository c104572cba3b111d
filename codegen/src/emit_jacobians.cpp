// rhs_jacobian and input_jacobian (docs/generated-code.md): M, f, G, γ and the entries of
// ∂r/∂(y, u), ∂c/∂(y, u) from one CSE pass, split where the entries need q'' and λ: the
// saddle-point matrix is factored once, solved for q'' and λ, then for every column
// (equations.hpp: implicit differentiation).
#include "emit_detail.hpp"
#include "signatures.hpp"

#include <sstream>

namespace phynjo::codegen::detail {

namespace {

/// The head of generated function `fn`'s definition, in the flavor of `names`.
std::string head(const Names& names, const EquationsOfMotion& eom, const char* fn) {
    const Signature sig = signature(eom.mass_depends_on_velocities, fn);
    return definition(names.kernel() ? in_kernel(sig) : sig);
}

/// One Jacobian function: `fn` fills `out` ((2·dof)×cols, row-major) from ∂r (dof×cols) and
/// ∂c (n_constraints×cols); the top rows are `top` (the identity block of ∂q'/∂q' for
/// rhs_jacobian, zero for input_jacobian).
void emit_one(Definitions& s, const Model& m, const EquationsOfMotion& eom, const Names& names, const char* fn,
              const char* out, std::size_t cols, const std::vector<Expr>& dr, const std::vector<Expr>& dc, bool identity_top) {
    const std::size_t n = eom.dof, mc = eom.n_constraints;
    const std::string size_checks = names.kernel() ? std::string()
                                                   : "    check_size(q, " + std::to_string(n) + ", \"" + fn + "\", \"q\");\n" +
                                                         "    check_size(qdot, " + std::to_string(n) + ", \"" + fn + "\", \"qdot\");\n" +
                                                         "    check_size(" + out + ", " + std::to_string(2 * n * cols) + ", \"" + fn +
                                                         "\", \"" + out + "\");\n";
    s << head(names, eom, fn) << size_checks;
    if (cols == 0) {
        s << "    (void)P;\n    (void)t;\n";
        s.close();
        s << "\n";
        return;
    }
    std::vector<Expr> all;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i; j < n; ++j) all.push_back(eom.mass_matrix[i * n + j]);
    const std::size_t off_f = all.size();
    all.insert(all.end(), eom.forcing.begin(), eom.forcing.end());
    const std::size_t off_g = all.size();
    all.insert(all.end(), eom.constraint_matrix.begin(), eom.constraint_matrix.end());
    const std::size_t off_gamma = all.size();
    all.insert(all.end(), eom.gamma.begin(), eom.gamma.end());
    const std::size_t off_r = all.size();
    all.insert(all.end(), dr.begin(), dr.end());
    const std::size_t off_c = all.size();
    all.insert(all.end(), dc.begin(), dc.end());
    std::vector<Expr> late = eom.acceleration_symbols;
    late.insert(late.end(), eom.multiplier_symbols.begin(), eom.multiplier_symbols.end());
    std::vector<std::string> res;
    std::string early, later;
    bool uses_t = false, uses_p = false;
    body_split(names, all, late, res, early, later, uses_t, uses_p);
    const std::string where = m.name + "::" + fn;
    s << unused(true, uses_p) << early; // t is in the error messages
    auto array = [&](const char* name, std::size_t len, auto&& entry) {
        std::vector<std::string> entries;
        for (std::size_t k = 0; k < len; ++k) entries.push_back(entry(k));
        s << array_of(names, name, entries);
    };
    // M diagonal, no constraints (particles in Cartesian coordinates): rows divided by M_ii,
    // the numbers LDLᵀ gives for a diagonal matrix without its O(n³) factorization and
    // O(n²) per column
    const bool diagonal = mc == 0 && is_diagonal(eom.mass_matrix, n);
    if (diagonal) {
        std::vector<std::string> d;
        for (std::size_t i = 0; i < n; ++i) d.push_back(res[upper_index(i, i, n)]);
        s << diagonal_mass(names, d, names.raise(Failure::singular_mass_matrix, "\"" + where + ": the mass matrix is singular\""))
          << "    double acc[" << n << "];\n";
        for (std::size_t i = 0; i < n; ++i) s << "    acc[" << i << "] = (" << res[off_f + i] << ")/d[" << i << "];\n";
        s << "    (void)acc; // read by the entries only when M depends on q\n";
    } else {
        array("M", n * n, [&](std::size_t k) {
            const std::size_t i = k / n, j = k % n;
            return j <= i ? res[upper_index(i, j, n)] : std::string("0.0");
        });
        array("f", n, [&](std::size_t i) { return res[off_f + i]; });
        if (mc > 0) {
            array("G", mc * n, [&](std::size_t k) { return res[off_g + k]; });
            array("gamma", mc, [&](std::size_t k) { return res[off_gamma + k]; });
            s << "    const " << names.solves() << "KktFactor<" << n << ", " << mc << "> kkt(M, G, constraint_names, \"" << where
              << "\", t);\n"
              << "    double acc[" << n << "], lambda[" << mc << "];\n"
              << "    kkt.solve(f, gamma, acc, lambda);\n";
        } else {
            s << "    const " << names.solves() << "KktFactor<" << n << ", 0> kkt(M);\n"
              << "    double acc[" << n << "];\n"
              << "    kkt.solve(f, nullptr, acc, nullptr);\n";
        }
    }
    s << later;
    array("dr", n * cols, [&](std::size_t k) { return res[off_r + k]; });
    if (mc > 0) array("dc", mc * cols, [&](std::size_t k) { return res[off_c + k]; });
    const std::string z = names.size_type();
    s << "    for (" << z << " k = 0; k < " << n * cols << "; ++k) " << out << "[k] = 0.0;\n";
    if (identity_top) s << "    for (" << z << " i = 0; i < " << n << "; ++i) " << out << "[i * " << cols << " + " << n << " + i] = 1.0;\n";
    if (diagonal)
        s << "    for (" << z << " i = 0; i < " << n << "; ++i)\n"
          << "        for (" << z << " j = 0; j < " << cols << "; ++j) " << out << "[" << n * cols << " + i * " << cols
          << " + j] = dr[i * " << cols << " + j]/d[i];\n";
    else
        s << "    kkt.solve_columns(" << cols << ", dr, " << (mc > 0 ? "dc" : "nullptr") << ", " << names.data(out) << " + "
          << n * cols << ");\n";
    s << "    for (" << z << " k = " << n * cols << "; k < " << 2 * n * cols << "; ++k)\n"
      << "        if (" << (names.kernel() ? "!__builtin_isfinite(" : "!std::isfinite(") << out << "[k])) "
      << names.raise(Failure::non_finite, "\"" + where + ": non-finite result at t = \"", "t") << "\n";
    s.close();
    s << "\n";
}

} // namespace

void emit_jacobians(const Model& m, const EquationsOfMotion& eom, Names names, Definitions& s) {
    for (std::size_t i = 0; i < eom.acceleration_symbols.size(); ++i)
        names.add_variable(eom.acceleration_symbols[i], "acc[" + std::to_string(i) + "]");
    for (std::size_t k = 0; k < eom.multiplier_symbols.size(); ++k)
        names.add_variable(eom.multiplier_symbols[k], "lambda[" + std::to_string(k) + "]");
    emit_one(s, m, eom, names, "rhs_jacobian", "J", 2 * eom.dof, eom.jacobian_r, eom.jacobian_c, true);
    emit_one(s, m, eom, names, "input_jacobian", "B", m.n_inputs(), eom.input_r, eom.input_c, false);
    // canonical_jacobian: p, F, ∂p/∂y, ∂F/∂y in one body (the Newton iteration of the
    // implicit midpoint rule evaluates them together)
    {
        const std::size_t n = eom.dof;
        std::vector<Expr> all = eom.momenta;
        all.insert(all.end(), eom.generalized_forces.begin(), eom.generalized_forces.end());
        all.insert(all.end(), eom.momenta_jacobian.begin(), eom.momenta_jacobian.end());
        all.insert(all.end(), eom.force_jacobian.begin(), eom.force_jacobian.end());
        std::vector<std::string> res;
        bool uses_t = false, uses_p = false;
        const std::string b = body(names, all, res, uses_t, uses_p);
        s << head(names, eom, "canonical_jacobian");
        if (!names.kernel())
            for (const auto& [name, len] : std::initializer_list<std::pair<const char*, std::size_t>>{
                     {"q", n}, {"qdot", n}, {"p", n}, {"F", n}, {"dp", 2 * n * n}, {"dF", 2 * n * n}})
                s << "    check_size(" << name << ", " << len << ", \"canonical_jacobian\", \"" << name << "\");\n";
        s << unused(uses_t, uses_p) << b;
        const char* outs[] = {"p", "F", "dp", "dF"};
        const std::size_t lens[] = {n, n, 2 * n * n, 2 * n * n};
        std::size_t k = 0;
        for (int o = 0; o < 4; ++o) {
            s << store_all(names, outs[o], std::vector<std::string>(res.begin() + static_cast<std::ptrdiff_t>(k),
                                                             res.begin() + static_cast<std::ptrdiff_t>(k + lens[o])));
            k += lens[o];
        }
        s.close();
        s << "\n";
    }
}

} // namespace phynjo::codegen::detail
