// The model's functions in the generated source: mass_matrix, forcing, momenta,
// generalized_forces, accelerations (closed-form 1×1 and 2×2 solves; above, LDLᵀ with a
// pivoted-LU fallback for indefinite M), the constraints, events and shapes, energy and
// initial_state, each one straight-line body from one CSE pass; and the fused kernels over
// them (rk4_step, accelerations_energy_guards).
#include "emit_detail.hpp"
#include "signatures.hpp"

#include <sstream>

namespace phynjo::codegen::detail {

bool is_diagonal(const std::vector<Expr>& mass_matrix, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) // M is symmetric: the upper triangle decides
        for (std::size_t j = i + 1; j < n; ++j)
            if (!mass_matrix[i * n + j].is_zero()) return false;
    return true;
}

std::string diagonal_mass(const Names& names, const std::vector<std::string>& diagonal, const std::string& failure) {
    std::ostringstream s;
    s << "    const double d[" << diagonal.size() << "] = {";
    for (std::size_t i = 0; i < diagonal.size(); ++i) s << (i ? ", " : "") << diagonal[i];
    s << "};\n    double top = 0;\n";
    if (names.kernel()) // std::max(top, |v|) is top < |v| ? |v| : top
        s << "    for (double v : d) top = top < " << names.math() << "fabs(v) ? " << names.math() << "fabs(v) : top;\n";
    else
        s << "    for (double v : d) top = std::max(top, std::fabs(v));\n";
    s << "    for (double v : d)\n"
      << "        if (!(" << names.math() << "fabs(v) > phynjo::runtime::kSingularTolerance * top))\n"
      << "            " << failure << "\n";
    return s.str();
}

namespace {

/// The model's functions printed in file order, one step per group of them: the context the
/// steps share (the model, the optimize step's forms, the names, the output) and the results
/// of the last body (`res`, `uses_t`, `uses_p`).
struct FunctionPrinter {
    const Model& m;
    const OptimizedEquations& opt;
    const EquationsOfMotion& eom;
    const Names& names;
    Definitions& s;
    const std::string L = kLanes;
    const std::size_t n, mc, ne;
    /// The closing comment of the functions that share a file with accelerations_energy_guards
    /// (cores): the group is one unit of Definitions.
    const std::string glue = " // (one file with accelerations_energy_guards)\n";
    std::vector<std::string> res;
    bool uses_t = false, uses_p = false;
    /// The upper triangle of M, row by row, and each entry's (i, j).
    std::vector<Expr> upper;
    std::vector<std::pair<std::size_t, std::size_t>> upper_ij;

    FunctionPrinter(const Model& model, const OptimizedEquations& o, const Names& nm, Definitions& out)
        : m(model), opt(o), eom(o.eom), names(nm), s(out), n(model.dof()), mc(o.eom.n_constraints),
          ne(model.events.size()) {
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i; j < n; ++j) {
                upper.push_back(eom.mass_matrix[i * n + j]);
                upper_ij.emplace_back(i, j);
            }
    }

    std::string sizes(const char* fn, std::initializer_list<std::pair<const char*, std::size_t>> arrays) const {
        std::string c;
        if (names.kernel()) return c; // the C table passes arrays of these sizes
        for (const auto& [name, len] : arrays)
            c += "    check_size(" + std::string(name) + ", " + std::to_string(len) + ", \"" + fn + "\", \"" + name + "\");\n";
        return c;
    }
    /// A function with nothing to compute (no constraints, no events, no shapes): its sizes
    /// checked, its output empty.
    void empty(const char* fn) {
        const Signature sig = signature(eom.mass_depends_on_velocities, fn);
        const bool with_qdot = sig.parameters.size() == 5; // P, t, q, q', out
        const std::string out = sig.output();
        s << head(fn)
          << (with_qdot ? sizes(fn, {{"q", n}, {"qdot", n}, {out.c_str(), 0}}) : sizes(fn, {{"q", n}, {out.c_str(), 0}}))
          << "    (void)P;\n    (void)t;\n";
        s.close();
        s << "\n";
    }
    /// The head of generated function `fn`'s definition (signatures.hpp).
    std::string head(const char* fn) const {
        const Signature sig = signature(eom.mass_depends_on_velocities, fn);
        return definition(names.kernel() ? in_kernel(sig) : sig);
    }
    /// The loop index's type.
    std::string z() const { return names.size_type(); }
    /// M_ij (either triangle) among the results of a body whose first outputs are `upper`.
    const std::string& Mij(std::size_t i, std::size_t j) const { return res[upper_index(i, j, n)]; }

    void mass_matrix();
    void vector_functions();
    void constrained();
    void constraint_stubs();
    void cores();
    void lane_kernels();
    void apply_event();
    void shapes();
    void initial_state();
};

/// mass_matrix: the upper triangle from one CSE pass, mirrored.
void FunctionPrinter::mass_matrix() {
    const std::string b = body(names, upper, res, uses_t, uses_p);
    s << head("mass_matrix")
      << (eom.mass_depends_on_velocities ? sizes("mass_matrix", {{"q", n}, {"qdot", n}, {"M", n * n}})
                                         : sizes("mass_matrix", {{"q", n}, {"M", n * n}}))
      << unused(uses_t, uses_p) << b;
    for (std::size_t k = 0; k < upper.size(); ++k) {
        const auto [i, j] = upper_ij[k];
        s << "    M[" << i * n + j << "] = " << res[k] << ";\n";
        if (i != j) s << "    M[" << j * n + i << "] = M[" << i * n + j << "];\n";
    }
    s.close();
    s << "\n";
}

/// forcing, momenta, generalized_forces: vector-valued functions of (q, qdot).
void FunctionPrinter::vector_functions() {
    auto vector_function = [&](const char* fn, const char* out_name, const std::vector<Expr>& exprs) {
        const std::string b = body(names, exprs, res, uses_t, uses_p);
        s << head(fn) << sizes(fn, {{"q", n}, {"qdot", n}, {out_name, n}}) << unused(uses_t, uses_p) << b;
        for (std::size_t i = 0; i < n; ++i) s << "    " << out_name << "[" << i << "] = " << res[i] << ";\n";
        s.close();
        s << "\n";
    };
    vector_function("forcing", "f", eom.forcing);
    vector_function("momenta", "p", eom.momenta);
    vector_function("generalized_forces", "F", eom.generalized_forces);
}

/// With constraints: accelerations_and_multipliers (M, f, G and γ from one CSE pass, then
/// the KKT solve), accelerations, the residuals, G, γ and the scales.
void FunctionPrinter::constrained() {
    // accelerations_and_multipliers: M, f, G and γ from one CSE pass, then the KKT solve
    std::vector<Expr> all = upper;
    all.insert(all.end(), eom.forcing.begin(), eom.forcing.end());
    all.insert(all.end(), eom.constraint_matrix.begin(), eom.constraint_matrix.end());
    all.insert(all.end(), eom.gamma.begin(), eom.gamma.end());
    const std::string b = body(names, all, res, uses_t, uses_p);
    const std::size_t off_f = upper.size(), off_g = off_f + n, off_gamma = off_g + mc * n;
    s << head("accelerations_and_multipliers")
      << sizes("accelerations_and_multipliers", {{"q", n}, {"qdot", n}, {"qddot", n}, {"lambda", mc}})
      << unused(true, uses_p) << b;
    s << "    const double M[" << n * n << "] = {";
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) s << (i || j ? ", " : "") << (j <= i ? Mij(i, j) : "0.0");
    s << "};\n    const double f[" << n << "] = {";
    for (std::size_t i = 0; i < n; ++i) s << (i ? ", " : "") << res[off_f + i];
    s << "};\n    const double G[" << mc * n << "] = {";
    for (std::size_t k = 0; k < mc * n; ++k) s << (k ? ", " : "") << res[off_g + k];
    s << "};\n    const double gamma[" << mc << "] = {";
    for (std::size_t k = 0; k < mc; ++k) s << (k ? ", " : "") << res[off_gamma + k];
    s << "};\n    " << names.solves() << "solve_constrained<" << n << ", " << mc
      << ">(M, f, G, gamma, qddot, lambda, constraint_names, \"" << m.name
      << "::accelerations_and_multipliers\", t);\n";
    s.close();
    s << "\n";
    s << head("accelerations") << "    double lambda[" << mc << "];\n"
      << "    accelerations_and_multipliers(P, t, q, qdot, qddot, lambda);\n";
    s.close();
    s << "\n";
    // constraint_residuals, constraint_velocity_residuals, constraint_matrix
    auto rows = [&](const char* fn, const char* out, const std::vector<Expr>& exprs, bool with_qdot) {
        const std::string bb = body(names, exprs, res, uses_t, uses_p);
        s << head(fn)
          << (with_qdot ? sizes(fn, {{"q", n}, {"qdot", n}, {out, exprs.size()}}) : sizes(fn, {{"q", n}, {out, exprs.size()}}))
          << unused(uses_t, uses_p) << bb;
        for (std::size_t k = 0; k < exprs.size(); ++k) s << "    " << out << "[" << k << "] = " << res[k] << ";\n";
        s.close();
        s << "\n";
    };
    rows("constraint_residuals", "phi", eom.residuals, true);
    rows("constraint_velocity_residuals", "psi", eom.velocity_residuals, true);
    rows("constraint_matrix", "G", eom.constraint_matrix, false);
    rows("constraint_gamma", "gamma", eom.gamma, true);
    {
        // constraint_scales: Σ|summand| of each φ_k, then of each velocity constraint
        std::vector<Expr> terms;
        std::vector<std::size_t> count;
        for (const auto* v : {&eom.residual_terms, &eom.velocity_residual_terms})
            for (const auto& ts : *v) {
                terms.insert(terms.end(), ts.begin(), ts.end());
                count.push_back(ts.size());
            }
        const std::string bb = body(names, terms, res, uses_t, uses_p);
        s << head("constraint_scales") << sizes("constraint_scales", {{"q", n}, {"qdot", n}, {"scale", 2 * mc}}) << unused(uses_t, uses_p) << bb;
        std::size_t k = 0;
        for (std::size_t r = 0; r < count.size(); ++r) {
            s << "    scale[" << r << "] = ";
            for (std::size_t j = 0; j < count[r]; ++j) s << (j ? " + " : "") << names.math() << "fabs(" << res[k++] << ")";
            s << ";\n";
        }
        s.close();
        s << "\n";
    }
}

/// Without constraints: accelerations_and_multipliers over accelerations, empty constraint
/// functions.
void FunctionPrinter::constraint_stubs() {
    s << head("accelerations_and_multipliers") << sizes("accelerations_and_multipliers", {{"lambda", 0}}) << "    accelerations(P, t, q, qdot, qddot);\n";
    s.close();
    s << "\n";
    for (const char* fn : {"constraint_residuals", "constraint_velocity_residuals", "constraint_scales", "constraint_gamma"})
        empty(fn);
    empty("constraint_matrix");
}
/// accelerations, event_guards, energy, rk4_step, accelerations_energy_guards and
/// rk4_step_values: one unit of Definitions, closed once at its end (the closing lines before
/// carry a comment saying so), over static inline cores of the arithmetic
/// (accelerations_core, guards_core, energy_core). rk4_step calls accelerations_core for its
/// stages (no std::function, no size checks between them); accelerations_energy_guards calls
/// the three cores, whose sines and cosines the compiler computes once (sincos) when it
/// inlines them. Each output's expression is the public function's own: the same bits.
void FunctionPrinter::cores() {
    // The cores' bodies in generic form (`const auto`, lanes.hpp's math, outputs as<T>) only
    // where they are instantiated for lanes too; elsewhere (constraints, three coordinates or
    // more: T is double alone) in plain form, `const double` and std:: — the same bits, and
    // 7% less C++ for g++ to read on nlink_cart(40).
    const bool generic = has_lane_kernel(m);
    // a core's pointers that its body does not read (a constant force, guards of t only)
    auto unread = [](const std::string& b) {
        return std::string(b.find("q[") == std::string::npos ? "    (void)q;\n" : "") +
               (b.find("qdot[") == std::string::npos ? "    (void)qdot;\n" : "");
    };
    if (mc == 0) {
        // M and f from one CSE pass, then the solve
        std::vector<Expr> all = upper;
        all.insert(all.end(), eom.forcing.begin(), eom.forcing.end());
        const std::string b = body(names, all, res, uses_t, uses_p, generic);
        s << "template <class T, class PT>\n"
          << "[[maybe_unused]] static inline void accelerations_core(const PT& P, T t, const T* q, const T* qdot,\n"
          << "                                                     T* qddot) {\n"
          << unused(uses_t, uses_p) << unread(b) << b;
        auto fi = [&](std::size_t i) { return res[upper.size() + i]; };
        const std::string singular =
            names.raise(Failure::singular_mass_matrix, "\"" + m.name + "::accelerations: the mass matrix is singular\"");
        if (n == 1) {
            s << "    const auto m00 = " << Mij(0, 0) << ";\n"
              << "    if (" << L << "any(m00 == 0)) " << singular << "\n"
              << "    qddot[0] = (" << fi(0) << ")/m00;\n";
        } else if (n == 2) {
            s << "    const auto m00 = " << Mij(0, 0) << ", m01 = " << Mij(0, 1) << ", m11 = " << Mij(1, 1) << ";\n"
              << "    const auto f0 = " << fi(0) << ", f1 = " << fi(1) << ";\n"
              << "    const auto det = m00*m11 - m01*m01;\n"
              << "    if (" << L << "any(" << L << "fabs(det) <= phynjo::runtime::kSingularTolerance*(" << L
              << "fabs(m00*m11) + m01*m01)))\n"
              << "        " << singular << "\n"
              << "    const auto inv = 1.0/det;\n"
              << "    qddot[0] = (m11*f0 - m01*f1)*inv;\n"
              << "    qddot[1] = (m00*f1 - m01*f0)*inv;\n";
        } else if (is_diagonal(eom.mass_matrix, n)) {
            std::vector<std::string> d;
            for (std::size_t i = 0; i < n; ++i) d.push_back(Mij(i, i));
            s << diagonal_mass(names, d, singular);
            for (std::size_t i = 0; i < n; ++i) s << "    qddot[" << i << "] = (" << fi(i) << ")/d[" << i << "];\n";
        } else {
            s << "    double A[" << n * n << "] = {";
            for (std::size_t i = 0; i < n; ++i)
                for (std::size_t j = 0; j < n; ++j) s << (i || j ? ", " : "") << (j <= i ? Mij(i, j) : "0.0");
            s << "};\n    double b[" << n << "] = {";
            for (std::size_t i = 0; i < n; ++i) s << (i ? ", " : "") << fi(i);
            s << "};\n    " << names.solves() << "solve_symmetric<" << n << ">(A, b);\n"
              << "    for (" << z() << " i = 0; i < " << n << "; ++i) qddot[i] = b[i];\n";
        }
        s << "    for (" << z() << " i = 0; i < " << n << "; ++i)\n"
          << "        if (" << L << "not_finite(qddot[i])) "
          << names.raise(Failure::non_finite, "\"" + m.name + "::accelerations: non-finite result at t = \"", L + "first(t)")
          << "\n"
          << "}" << glue << "\n";
    }
    {
        // the guards from one CSE pass
        const std::string b = ne > 0 ? body(names, opt.guards, res, uses_t, uses_p, generic) : std::string();
        if (ne == 0) uses_t = uses_p = false;
        s << "template <class T, class PT>\n"
          << "[[maybe_unused]] static inline void guards_core(const PT& P, T t, const T* q, const T* qdot, T* g) {\n"
          << unused(uses_t, uses_p) << unread(b) << b;
        if (ne == 0) s << "    (void)g;\n";
        for (std::size_t k = 0; k < ne; ++k) s << "    g[" << k << "] = " << res[k] << ";\n";
        s << "}" << glue << "\n";
    }
    {
        const std::string b = body(names, {eom.energy}, res, uses_t, uses_p, generic);
        s << "template <class T, class PT>\n"
          << "[[maybe_unused]] static inline T energy_core(const PT& P, T t, const T* q, const T* qdot) {\n"
          << unused(uses_t, uses_p) << unread(b) << b << "    return " << res[0] << ";\n}" << glue << "\n";
    }
    if (mc == 0)
        s << head("accelerations") << sizes("accelerations", {{"q", n}, {"qdot", n}, {"qddot", n}})
          << "    accelerations_core(P, t, " << names.data("q") << ", " << names.data("qdot") << ", " << names.data("qddot") << ");\n}"
          << glue << "\n";
    s << head("event_guards") << sizes("event_guards", {{"q", n}, {"qdot", n}, {"g", ne}})
      << "    guards_core(P, t, " << names.data("q") << ", " << names.data("qdot") << ", " << names.data("g") << ");\n}" << glue << "\n";
    s << head("energy") << sizes("energy", {{"q", n}, {"qdot", n}}) << "    return energy_core(P, t, " << names.data("q") << ", " << names.data("qdot") << ");\n}" << glue
      << "\n";
    // rk4_step (phynjo extension): the runtime's lagrangian_rk4 rule, the same operations in
    // the same order (the same bits), its first stage's q'' given; the stages in a core that
    // rk4_step_values shares
    s << "template <class T, class PT>\n"
      << "[[maybe_unused]] static inline void rk4_stages(const PT& p, T t, T h, T* q, T* qdot, const T* qddot) {\n"
      << (names.kernel() ? "    T q0[" + std::to_string(n) + "], v0[" + std::to_string(n) + "], aq[" + std::to_string(n) + "], av[" +
                               std::to_string(n) + "], k[" + std::to_string(n) + "];\n"
                         : "    std::array<T, " + std::to_string(n) + "> q0, v0, aq, av, k;\n")
      << "    for (" << z() << " i = 0; i < " << n << "; ++i) {\n"
      << "        q0[i] = q[i];\n        v0[i] = qdot[i];\n        aq[i] = av[i] = T{};\n        k[i] = qddot[i];\n    }\n"
      << "    auto stage = [&](double weight, double next, bool last) {\n"
      << "        for (" << z() << " i = 0; i < " << n << "; ++i) {\n"
      << "            const T kq = qdot[i], kv = k[i];\n"
      << "            aq[i] += weight * kq;\n            av[i] += weight * kv;\n"
      << "            if (last) {\n                q[i] = q0[i] + h * aq[i];\n                qdot[i] = v0[i] + h * av[i];\n"
      << "            } else {\n                q[i] = q0[i] + next * h * kq;\n                qdot[i] = v0[i] + next * h * kv;\n"
      << "            }\n        }\n    };\n";
    auto stage_at = [&](const char* c) {
        if (mc == 0) return "    accelerations_core(p, t + " + std::string(c) + " * h, q, qdot, " + names.data("k") + ");\n";
        if (names.kernel()) return "    accelerations(p, t + " + std::string(c) + " * h, q, qdot, k);\n";
        return "    accelerations(p, t + " + std::string(c) + " * h, std::span<const double>(q, " + std::to_string(n) +
               "), std::span<const double>(qdot, " + std::to_string(n) + "), k);\n";
    };
    s << "    stage(1.0 / 6, 0.5, false);\n" << stage_at("0.5") << "    stage(2.0 / 6, 0.5, false);\n" << stage_at("0.5")
      << "    stage(2.0 / 6, 1.0, false);\n" << stage_at("1.0") << "    stage(1.0 / 6, 0, true);\n}" << glue << "\n";
    // q'', E and the guards at one state: the three cores on a copy of the state, which no
    // store through E, g or qddot can change (so the compiler sees the same arguments of sin
    // and cos in the three)
    s << "template <class T, class PT>\n"
      << "[[maybe_unused]] static inline bool values_core(const PT& P, T t, const T* q, const T* qdot, T* qddot, T& E,\n"
      << "                                              T* g) {\n"
      << (names.kernel() ? "    T x[" + std::to_string(n) + "], v[" + std::to_string(n) + "];\n    for (size_t i = 0; i < " +
                               std::to_string(n) + "; ++i) {\n        x[i] = q[i];\n        v[i] = qdot[i];\n    }\n"
                         : "    std::array<T, " + std::to_string(n) + "> x, v;\n    std::copy_n(q, " + std::to_string(n) +
                               ", x.begin());\n    std::copy_n(qdot, " + std::to_string(n) + ", v.begin());\n")
      << "    E = energy_core(P, t, " << names.data("x") << ", " << names.data("v") << ");\n"
      << "    guards_core(P, t, " << names.data("x") << ", " << names.data("v") << ", g);\n"
      << "    try {\n"
      << (mc == 0            ? "        accelerations_core(P, t, " + names.data("x") + ", " + names.data("v") + ", qddot);\n"
          : names.kernel() ? std::string("        accelerations(P, t, x, v, qddot);\n")
                           : "        accelerations(P, t, x, v, std::span<double>(qddot, " + std::to_string(n) + "));\n")
      << "    } catch (const " << (names.kernel() ? "phynjo::kernel::Failure" : "phynjo::runtime::Error")
      << "&) {\n        return false;\n    }\n    return true;\n}" << glue << "\n";
    s << head("rk4_step") << sizes("rk4_step", {{"q", n}, {"qdot", n}, {"qddot", n}})
      << "    // the parameters in a local, which no store through q or qdot can change: the compiler\n"
      << "    // then computes their products once for all stages\n"
      << "    const Parameters p = P;\n"
      << "    rk4_stages(p, t, h, " << names.data("q") << ", " << names.data("qdot") << ", " << names.data("qddot") << ");\n}" << glue
      << "\n";
    s << head("accelerations_energy_guards") << sizes("accelerations_energy_guards", {{"q", n}, {"qdot", n}, {"qddot", n}, {"g", ne}})
      << "    return values_core(P, t, " << names.data("q") << ", " << names.data("qdot") << ", " << names.data("qddot") << ", E, "
      << names.data("g") << ");\n}" << glue << "\n";
    s << head("rk4_step_values") << sizes("rk4_step_values", {{"q", n}, {"qdot", n}, {"qddot", n}, {"g", ne}})
      << "    const Parameters p = P;\n"
      << "    rk4_stages(p, t, h, " << names.data("q") << ", " << names.data("qdot") << ", " << names.data("qddot") << ");\n"
      << "    return values_core(p, t1, " << names.data("q") << ", " << names.data("qdot") << ", " << names.data("qddot") << ", E, "
      << names.data("g") << ");\n";
    if (has_lane_kernel(m)) { // the lane kernels below share the cores' file
        s << "}" << glue << "\n";
    } else {
        s.close();
        s << "\n";
    }
}

/// rk4_step_values for lanes::kWidth runs at once, each with its own parameters: the same
/// cores instantiated for Lanes and LaneParameters (the preamble's).
void FunctionPrinter::lane_kernels() {
    s << head("rk4_step_values_lanes_each") << "    namespace lanes = phynjo::runtime::lanes;\n"
      << "    constexpr " << z() << " W = lanes::kWidth;\n"
      << (names.kernel() ? "    lanes::Lanes x[" + std::to_string(n) + "], v[" + std::to_string(n) + "], a[" + std::to_string(n) +
                               "];\n    lanes::Lanes gl[" + std::to_string(ne > 0 ? ne : 1) + "];\n"
                         : "    std::array<lanes::Lanes, " + std::to_string(n) + "> x, v, a;\n    std::array<lanes::Lanes, " +
                               std::to_string(ne) + "> gl;\n")
      << "    lanes::Lanes e;\n"
      << "    for (" << z() << " i = 0; i < " << n << "; ++i) {\n"
      << "        x[i] = lanes::load(q + i * W);\n        v[i] = lanes::load(qdot + i * W);\n"
      << "        a[i] = lanes::load(qddot + i * W);\n    }\n"
      << "    const LaneParameters p = lane_parameters(P);\n"
      << "    rk4_stages(p, lanes::load(t), lanes::load(h), " << names.data("x") << ", " << names.data("v") << ", " << names.data("a")
      << ");\n"
      << "    const bool ok = values_core(p, lanes::load(t1), " << names.data("x") << ", " << names.data("v") << ", " << names.data("a")
      << ", e, " << names.data("gl") << ");\n"
      << "    for (" << z() << " i = 0; i < " << n << "; ++i) {\n"
      << "        lanes::store(q + i * W, x[i]);\n        lanes::store(qdot + i * W, v[i]);\n"
      << "        lanes::store(qddot + i * W, a[i]);\n    }\n"
      << "    lanes::store(E, e);\n"
      << (ne > 0 ? "    for (" + z() + " k = 0; k < " + std::to_string(ne) + "; ++k) lanes::store(g + k * W, gl[k]);\n"
                 : std::string("    (void)g;\n"))
      << "    return ok;\n}" << glue << "\n";
    s << head("rk4_step_values_lanes") << "    const void* each[phynjo::runtime::lanes::kWidth];\n"
      << "    for (auto& e : each) e = &P;\n"
      << "    return rk4_step_values_lanes_each(each, t, h, t1, q, qdot, qddot, E, g);\n";
    s.close();
    s << "\n";
}

/// apply_event: one case per event, every right side read from the state before any is
/// stored.
void FunctionPrinter::apply_event() {
    s << head("apply_event") << sizes("apply_event", {{"q", n}, {"qdot", n}}) << "    (void)P;\n    (void)t;\n    switch (k) {\n";
    for (std::size_t k = 0; k < ne; ++k) {
        const Event& e = m.events[k];
        s << "    case " << k << ": { // " << e.name << (e.stop ? ": stop" : "") << "\n";
        if (!e.resets.empty()) {
            std::string b = body(names, opt.reset_values[k], res, uses_t, uses_p);
            // the body's lines, indented into the case
            std::string indented;
            for (std::size_t at = 0; at < b.size();) {
                const std::size_t end = b.find('\n', at);
                indented += "    " + b.substr(at, end - at + 1);
                at = end + 1;
            }
            s << indented;
            // the body loaded every variable it reads first: storing now cannot change a right side
            for (std::size_t r = 0; r < e.resets.size(); ++r)
                s << "        " << (e.resets[r].velocity ? "qdot[" : "q[") << e.resets[r].coordinate << "] = " << res[r]
                  << "; // " << m.coordinates[e.resets[r].coordinate].name << (e.resets[r].velocity ? "'" : "") << "\n";
        }
        s << "        return;\n    }\n";
    }
    s << "    default: break;\n    }\n    "
      << names.raise(Failure::out_of_range, "\"" + m.name + "::apply_event: event \"", "k",
                     "\" (the model has " + std::to_string(ne) + ")\"")
      << "\n";
        s.close();
        s << "\n";
}

/// The shapes' points from one CSE pass; each sphere's ∂(X, Y, Z)/∂q, each capsule's of both
/// ends, each box's of its centre with its angular-velocity Jacobian; the radii and half extents
/// (phynjo extension).
void FunctionPrinter::shapes() {
    // a function of (P, t, q) filling `out` from `exprs` (one CSE pass), or its empty stub
    // With `axes`: each |a|² of opt.box_axis_checks checked before anything is written.
    auto of_q = [&](const char* fn, const char* out, const std::vector<Expr>& exprs, bool axes = false) {
        if (exprs.empty()) return empty(fn);
        std::vector<Expr> all = exprs;
        if (axes)
            for (const auto& c : opt.box_axis_checks) all.push_back(c.length2);
        const std::string b = body(names, all, res, uses_t, uses_p);
        s << head(fn) << sizes(fn, {{"q", n}, {out, exprs.size()}}) << unused(uses_t, uses_p) << b;
        for (std::size_t k = exprs.size(); k < all.size(); ++k) {
            const std::string& what = opt.box_axis_checks[k - exprs.size()].what;
            s << "    if (!(" << res[k] << " > 0) || " << (names.kernel() ? "!__builtin_isfinite(" : "!std::isfinite(") << res[k] << "))\n"
              << "        "
              << names.raise(Failure::invalid_argument,
                             "\"" + m.name + "::" + fn + ": " + what + " has length zero at these parameters (|a|^2 = \"", res[k], "\")\"")
              << "\n";
        }
        for (std::size_t k = 0; k < exprs.size(); ++k) s << "    " << out << "[" << k << "] = " << res[k] << ";\n";
        s.close();
        s << "\n";
    };
    of_q("shape_positions", "X", opt.shape_points, true);
    of_q("sphere_jacobians", "J", opt.sphere_jacobians);
    of_q("capsule_jacobians", "J", opt.capsule_jacobians);
    of_q("box_jacobians", "J", opt.box_jacobians, true);
    struct Sizes {
        const char* fn;
        const char* out;
        const std::vector<Expr>* values;
    };
    for (const auto& [fn, out, values] : {Sizes{"sphere_radii", "r", &opt.sphere_radii}, Sizes{"capsule_radii", "r", &opt.capsule_radii},
                                          Sizes{"box_half_extents", "h", &opt.box_half_extents}}) {
        s << head(fn) << sizes(fn, {{out, values->size()}});
        if (values->empty()) s << "    (void)P;\n";
        else {
            const std::string b = body(names, *values, res, uses_t, uses_p);
            s << unused(uses_t, uses_p, false) << b;
            for (std::size_t k = 0; k < values->size(); ++k) s << "    " << out << "[" << k << "] = " << res[k] << ";\n";
        }
        s.close();
        s << "\n";
    }
}

/// initial_state: the initial values from one CSE pass.
void FunctionPrinter::initial_state() {
    const std::string b = body(names, opt.initial_values, res, uses_t, uses_p);
    s << head("initial_state") << sizes("initial_state", {{"q", n}, {"qdot", n}}) << unused(uses_t, uses_p, false) << b;
    for (std::size_t i = 0; i < n; ++i) s << "    q[" << i << "] = " << res[i] << ";\n";
    for (std::size_t i = 0; i < n; ++i) s << "    qdot[" << i << "] = " << res[n + i] << ";\n";
    s.close();
    s << "\n";
}

} // namespace

void emit_functions(const Model& m, const OptimizedEquations& opt, const Names& names, Definitions& s) {
    FunctionPrinter f(m, opt, names, s);
    f.mass_matrix();
    f.vector_functions();
    if (f.mc > 0) f.constrained();
    else f.constraint_stubs();
    f.cores();
    if (has_lane_kernel(m)) f.lane_kernels();
    f.apply_event();
    f.shapes();
    f.initial_state();
}

} // namespace phynjo::codegen::detail
