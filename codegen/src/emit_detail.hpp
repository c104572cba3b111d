#pragma once
// Internals of the C++ emitter, shared by its parts (one per output): emit_header.cpp (the
// declarations), emit_functions.cpp (the model's functions), emit_glue.cpp (the runtime
// glue), emit_main.cpp (main); emit_cpp.cpp assembles them. Here: how model variables are
// named in generated code, and straight-line bodies from one CSE pass.
#include "phynjo/codegen/emit.hpp"

#include "phynjo/cas/cas.hpp"

#include <string>
#include <unordered_map>
#include <vector>

namespace phynjo::codegen::detail {

using cas::Expr;

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
            load_.emplace(m.parameters[j].symbol, "P." + m.parameters[j].name);
        }
        local_.emplace(cas::time_symbol(), "t");
    }
    std::string local(Expr v) const {
        if (auto it = local_.find(v); it != local_.end()) return it->second;
        return std::string(cas::symbol_name(v)); // a CSE temporary
    }
    /// `const double q0 = q[0];` for a user variable, nothing for t and temporaries.
    std::string load(Expr v) const {
        if (auto it = load_.find(v); it != load_.end()) return "    const double " + local(v) + " = " + it->second + ";\n";
        return {};
    }
    bool is_user(Expr v) const { return local_.count(v) > 0; }

private:
    std::unordered_map<Expr, std::string> local_, load_;
};

/// Straight-line code computing `outputs`: returns the statements, and the C++ expression of
/// each output in `results`. `outputs` are already in Horner form (emit_cpp converts every
/// expression once).
std::string body(const Names& names, const std::vector<Expr>& outputs, std::vector<std::string>& results,
                 bool& uses_t, bool& uses_params);

/// `(void)t;` and `(void)P;` for what a body does not use.
std::string unused(bool uses_t, bool uses_params, bool has_t = true);

/// The generated header: parameters, every declaration of generated-api.md.
std::string emit_header(const Model& m);
/// The model's functions (mass_matrix, forcing, momenta, generalized_forces, accelerations,
/// energy, initial_state), from `eom` in Horner form.
std::string emit_functions(const Model& m, const EquationsOfMotion& eom, const Names& names);
/// The runtime glue: system(), make_world(), workflow().
std::string emit_glue(const Model& m);
/// main(): the runtime's command-line driver with the model's parameters.
std::string emit_main(const Model& m);

} // namespace phynjo::codegen::detail
