#pragma once
// Internals of the C++ emitter, shared by its parts (one per output): emit_header.cpp (the
// declarations), emit_functions.cpp (the model's functions), emit_glue.cpp (the runtime
// glue), emit_main.cpp (main); emit_cpp.cpp assembles them. Here: how model variables are
// named in generated code, and straight-line bodies from one CSE pass.
#include "phynjo/codegen/emit.hpp"
#include "phynjo/codegen/optimize.hpp"

#include "phynjo/cas/cas.hpp"

#include <algorithm>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace phynjo::codegen::detail {

using cas::Expr;

/// The C++ expression of a parameter's current value inside generated functions: `P.m`, or
/// for a parameter defined from others `param_I(P)` (emit_derived_parameters).
inline std::string parameter_value(const Parameter& p) {
    return p.derived() ? "param_" + p.name + "(P)" : "P." + p.name;
}

/// What printed code is for: a source of phynjo_add_model (std::span arguments with their
/// sizes checked, the runtime's solves and typed exceptions), or a model kernel
/// (runtime/system/kernel_support.hpp: no standard header, pointer arguments whose sizes the
/// C table guarantees, phynjo::kernel's solves, failures thrown as phynjo::kernel::Failure and
/// returned as status codes). The arithmetic is printed the same in both: the same bits.
enum class Flavor { source, kernel };

/// What generated code throws (Names::raise).
enum class Failure { singular_mass_matrix, non_finite, invalid_argument, out_of_range };

class Names {
public:
    explicit Names(const Model& m) {
        for (std::size_t i = 0; i < m.dof(); ++i) {
            local_.emplace(m.coordinates[i].symbol, "q" + std::to_string(i));
            local_.emplace(cas::velocity(m.coordinates[i].symbol), "qd" + std::to_string(i));
            load_.emplace(m.coordinates[i].symbol, "q[" + std::to_string(i) + "]");
            load_.emplace(cas::velocity(m.coordinates[i].symbol), "qdot[" + std::to_string(i) + "]");
        }
        for (std::size_t j = 0; j < m.parameters.size(); ++j) {
            local_.emplace(m.parameters[j].symbol, "k" + std::to_string(j));
            load_.emplace(m.parameters[j].symbol, parameter_value(m.parameters[j]));
        }
        local_.emplace(cas::time_symbol(), "t");
        // CSE temporaries are symbols named PREFIX<n>: a prefix no user name continues with
        // digits (a coordinate `x1` must not become temporary x1 of some function).
        auto clashes = [&] {
            for (const auto& [v, local] : local_) {
                if (v.kind() != cas::Kind::Symbol) continue;
                const std::string_view n = cas::symbol_name(v);
                if (n.size() > temp_prefix_.size() && n.substr(0, temp_prefix_.size()) == temp_prefix_ &&
                    n.find_first_not_of("0123456789", temp_prefix_.size()) == std::string_view::npos)
                    return true;
            }
            return false;
        };
        while (clashes()) temp_prefix_ += "_";
    }
    /// The prefix of CSE temporaries: never a user name followed by digits.
    const std::string& temp_prefix() const noexcept { return temp_prefix_; }
    std::string local(Expr v) const {
        if (auto it = local_.find(v); it != local_.end()) return it->second;
        return std::string(cas::symbol_name(v)); // a CSE temporary
    }
    /// `const double q0 = q[0];` for a user variable, nothing for t and temporaries.
    std::string load(Expr v, bool generic = false) const {
        if (auto it = load_.find(v); it != load_.end())
            return std::string(generic ? "    const auto " : "    const double ") + local(v) + " = " + it->second + ";\n";
        return {};
    }
    bool is_user(Expr v) const { return local_.count(v) > 0; }
    /// Names `v` in generated code as the C++ expression `local` (read where it is used, no
    /// load): the symbols of the Jacobians (acc[i], lambda[k], …).
    void add_variable(Expr v, std::string local) { local_.emplace(v, std::move(local)); }
    /// Bodies of this many statements or more are computed in pieces (EmitOptions).
    std::size_t piece_threshold = kPieceThreshold;
    Flavor flavor = Flavor::source;
    [[nodiscard]] bool kernel() const noexcept { return flavor == Flavor::kernel; }
    /// The prefix of plain bodies' math: std:: in a source, lanes.hpp's (the same functions,
    /// no header) in a kernel.
    [[nodiscard]] const char* math() const noexcept;
    /// The namespace of the solves (KktFactor, solve_symmetric, solve_constrained).
    [[nodiscard]] const char* solves() const noexcept { return kernel() ? "phynjo::kernel::" : "phynjo::runtime::"; }
    /// std::size_t, or size_t (kernel_abi.h's <stddef.h>).
    [[nodiscard]] const char* size_type() const noexcept { return kernel() ? "size_t" : "std::size_t"; }
    /// `a.data()` of a std::span argument; the pointer itself in a kernel.
    [[nodiscard]] std::string data(const std::string& a) const { return kernel() ? a : a + ".data()"; }
    /// `throw …;` of a failure of `kind`: `text` (a C++ string literal, quotes included), then
    /// the value of the C++ expression `value` as std::to_string prints it (none when empty),
    /// then `after` (a literal). In a source the runtime's exception or std::invalid_argument,
    /// std::out_of_range; in a kernel a phynjo::kernel::Failure of the matching status.
    [[nodiscard]] std::string raise(Failure kind, const std::string& text, const std::string& value = {},
                                    const std::string& after = {}) const;

private:
    std::unordered_map<Expr, std::string> local_, load_;
    std::string temp_prefix_ = "x";
};

/// Straight-line code computing `outputs`: returns the statements, and the C++ expression of
/// each output in `results`. `outputs` are already in Horner form (the optimize step,
/// optimize.hpp). `generic`: for a function template over the number type T (double, or
/// lanes of runs): temporaries `const auto`, math through lanes.hpp, outputs of type T.
std::string body(const Names& names, const std::vector<Expr>& outputs, std::vector<std::string>& results,
                 bool& uses_t, bool& uses_params, bool generic = false);
/// True when generated code has rk4_step_values_lanes (phynjo extension): no constraints, and
/// M solved in closed form (one or two coordinates).
inline bool has_lane_kernel(const Model& m) { return m.constraints.empty() && m.dof() <= 2; }
/// The C++ namespace of generic bodies' math functions (runtime/system/detail/lanes.hpp).
inline constexpr const char* kLanes = "phynjo::runtime::lanes::";

/// The same, split in two: `early` computes what does not depend on any of `late_variables`
/// (the temporaries in their order), `late` the rest; late outputs may use early temporaries.
void body_split(const Names& names, const std::vector<Expr>& outputs, const std::vector<Expr>& late_variables,
                std::vector<std::string>& results, std::string& early, std::string& late, bool& uses_t, bool& uses_params);

/// `name` as an array of `entries` (C++ expressions) for code that reads it through a
/// pointer: `const double* name = &xv[a];` when the entries are consecutive elements of one
/// array (the outputs of a chunked body), `const double name[n] = {…};` when few, else
/// `double name[n];` filled in pieces (one huge initializer is as slow to optimize as one
/// huge function).
std::string array_of(const Names& names, const std::string& name, const std::vector<std::string>& entries);
/// `target[k] = entries[k];` for each k (target a std::span argument, or a local array when not
/// `span`): one copy when the entries are consecutive elements of one array, in pieces when
/// there are many.
std::string store_all(const Names& names, const std::string& target, const std::vector<std::string>& entries, bool span = true);

/// Index of M_ij (either triangle) among the upper triangle of an n×n matrix listed row by row.
inline std::size_t upper_index(std::size_t i, std::size_t j, std::size_t n) {
    const std::size_t a = std::min(i, j), b = std::max(i, j);
    return a * n - a * (a - 1) / 2 + (b - a); // row a of the upper triangle starts there
}

/// True when the mass matrix (row-major n×n) is diagonal as an expression (every
/// off-diagonal entry the literal 0): particles in Cartesian coordinates.
bool is_diagonal(const std::vector<Expr>& mass_matrix, std::size_t n);
/// `double d[n] = {…};` of the diagonal entries (C++ expressions) and the check that none is
/// zero or below kSingularTolerance times the largest: else the statement `failure` (a throw of
/// SingularMassMatrix, or a return).
/// (Dividing by d[i] gives the bits of LDLᵀ on a diagonal matrix, without its O(n³) work.)
std::string diagonal_mass(const Names& names, const std::vector<std::string>& diagonal, const std::string& failure);


/// The generated functions as the units `--parts` may place in different files: a unit ends
/// with the closing line "}" of a function, or of the last of a group that must share a file
/// (those before it close with "} // (one file with …)"); the blank line after it begins the
/// next unit.
class Definitions {
public:
    template <class T>
    Definitions& operator<<(const T& text) {
        current_ << text;
        return *this;
    }
    /// Closes the function being written with the line "}" and ends its unit.
    void close() {
        current_ << "}\n";
        units_.push_back(current_.str());
        current_.str("");
    }
    /// The units in order (text after the last close() is the last unit).
    std::vector<std::string> take() {
        if (!current_.str().empty()) units_.push_back(current_.str());
        current_.str("");
        return std::move(units_);
    }

private:
    std::ostringstream current_;
    std::vector<std::string> units_;
};

/// `(void)t;` and `(void)P;` for what a body does not use.
std::string unused(bool uses_t, bool uses_params, bool has_t = true);

/// rhs_jacobian, input_jacobian and canonical_jacobian (docs/generated-code.md) from the
/// Jacobian part of `eom`, appended to `out`.
void emit_jacobians(const Model& m, const EquationsOfMotion& eom, Names names, Definitions& out);

/// The generated header: parameters, every declaration of docs/generated-code.md.
std::string emit_header(const Model& m, bool mass_depends_on_velocities);
/// `struct Parameters {…};` with the defaults of the model file (the header's, a kernel's).
std::string parameters_struct(const Model& m);
/// The model's functions (mass_matrix, forcing, momenta, generalized_forces, accelerations,
/// energy, the constrained ones, events, shapes, initial_state), printed from the optimize
/// step's forms.
void emit_functions(const Model& m, const OptimizedEquations& opt, const Names& names, Definitions& out);
/// `param_NAME(P)` for each parameter defined from others: its assigned value, or its
/// definition at the current values of the parameters it is defined from.
std::string emit_derived_parameters(const Model& m, const Names& names);
/// For a model with lane kernels: `LaneParameters` (each parameter as lanes::Lanes, a lane per
/// run), `lane_parameters(P)` gathering it from kWidth Parameters (a derived parameter's value
/// as param_NAME gives it, lane by lane), and param_NAME(const LaneParameters&) for the loads
/// of generic bodies; empty otherwise.
std::string emit_lane_parameters(const Model& m, const Names& names);
/// The runtime glue: system(), make_world(), workflow().
std::string emit_glue(const Model& m, bool mass_depends_on_velocities);
/// main(): the runtime's command-line driver with the model's parameters.
std::string emit_main(const Model& m);
/// What every source file starts with: the comment, the header's include (none when
/// `header_name` is empty; functions only unless `with_glue`), the standard includes (and
/// model_main's with `with_main`), and the helpers every function may use (size checks,
/// derived parameters, lane parameters), in the model's namespace left open.
std::string source_preamble(const Model& m, const std::string& header_name, bool with_glue, bool with_main);
/// The kernel's C table (kernel_abi.h) over the functions above it: emit_kernel's tail.
std::string emit_kernel_table(const Model& m, bool mass_depends_on_velocities, const std::string& version);

} // namespace phynjo::codegen::detail
