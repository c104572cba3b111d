#pragma once
/// \file
/// Emission: the generated C++ (docs/generated-code.md), LaTeX, and M and f in the input syntax.
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/model.hpp"
#include "phynjo/codegen/optimize.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace phynjo::codegen {

/// The default EmitOptions::piece_threshold.
inline constexpr std::size_t kPieceThreshold = 1500;

/// Below this much text of the model's functions (bytes) nothing is split: one file
/// compiles about as fast as several would.
inline constexpr std::size_t kSplitThreshold = 256 * 1024;

struct EmitOptions {
    /// The header's file name as the source includes it (`pendulum.hpp`).
    std::string header_name;
    /// Add a main() that simulates from the initial state and writes CSV.
    bool main = false;
    /// Source files in all (phynjo extension, `--parts K`): with K > 1 the model's largest
    /// functions (the Jacobians, M, f of a big model) may go to K − 1 more files, so a build
    /// compiles them in parallel; the source keeps the rest, the glue and main(). A model
    /// whose functions are small (kSplitThreshold) stays in the source, the part files then
    /// hold a comment only. Every file compiles on its own against the header.
    std::size_t parts = 1;
    /// With parts > 1: the size of the model's functions (bytes of C++) from which they are
    /// spread over the part files (`--split-above BYTES`).
    std::size_t split_threshold = kSplitThreshold;
    /// A function body of this many statements or more (temporaries and outputs) is computed
    /// in pieces the C++ compiler optimizes one at a time (`--pieces-above N`): the same
    /// arithmetic, the same results bit for bit, a compile time linear in the body's size.
    std::size_t piece_threshold = kPieceThreshold;
};

struct EmittedCpp {
    std::string header, source;
    /// The part files 2 … K of EmitOptions::parts (empty when parts = 1).
    std::vector<std::string> parts;
};

/// The generated pair, printed from the optimize step's forms (optimize.hpp). Deterministic:
/// the same model gives byte-identical text.
EmittedCpp emit_cpp(const Model& model, const OptimizedEquations& equations, const EmitOptions& options);
/// A model kernel (docs/command-line.md, *Kernels*): one translation unit with the header's
/// declarations, the model's functions and the C table of phynjo/runtime/system/kernel_abi.h
/// (entry point `phynjo_kernel_v1`), built as a shared object the runtime loads. `version`
/// is phynjo's, recorded in the table.
std::string emit_kernel(const Model& model, const OptimizedEquations& equations, const EmitOptions& options,
                        const std::string& version);
/// A LaTeX document of L and the equations of motion M q'' = f.
std::string emit_latex(const Model& model, const EquationsOfMotion& eom);
/// `M(i,j) = …` and `f(i) = …` lines in the input syntax (1-based, coordinate order).
std::string emit_eom(const Model& model, const EquationsOfMotion& eom);

} // namespace phynjo::codegen
