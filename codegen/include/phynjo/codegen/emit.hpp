#pragma once
/// \file
/// Emission: the generated C++ (generated-api.md), LaTeX, and M and f in the input syntax.
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/model.hpp"

#include <string>

namespace phynjo::codegen {

struct EmitOptions {
    /// The header's file name as the source includes it (`pendulum.hpp`).
    std::string header_name;
    /// Add a main() that simulates from the initial state and writes CSV.
    bool main = false;
};

struct EmittedCpp {
    std::string header, source;
};

/// The generated pair. Deterministic: the same model gives byte-identical text.
EmittedCpp emit_cpp(const Model& model, const EquationsOfMotion& eom, const EmitOptions& options);
/// A LaTeX document of L and the equations of motion M q'' = f.
std::string emit_latex(const Model& model, const EquationsOfMotion& eom);
/// `M(i,j) = …` and `f(i) = …` lines in the input syntax (1-based, coordinate order).
std::string emit_eom(const Model& model, const EquationsOfMotion& eom);

} // namespace phynjo::codegen
