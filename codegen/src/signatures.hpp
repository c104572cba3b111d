#pragma once
// The signatures of generated functions (internal): one table, printed as the header's
// declarations (emit_header.cpp) and as the source's definitions (emit_functions.cpp,
// emit_jacobians.cpp, emit_glue.cpp), so that the two cannot disagree.
#include "phynjo/codegen/model.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace phynjo::codegen::detail {

struct Signature {
    struct Parameter {
        std::string declaration; ///< "std::span<double> M"
        std::string fallback;    ///< the header's default argument ("" for none)
    };
    std::string returns, name;
    std::vector<Parameter> parameters;
    /// The last parameter's name: the output of most functions ("M", "phi", …).
    [[nodiscard]] std::string output() const;
};

/// The signature of generated function `name` (mass_matrix takes q' when M depends on the
/// velocities). Asserts that `name` is in the table.
Signature signature(bool mass_depends_on_velocities, std::string_view name);
/// `RET NAME(P, …)`, the parameters wrapped at 110 columns under the opening parenthesis;
/// the header's default arguments with `defaults`.
std::string spelled(const Signature& s, bool defaults);
/// The declaration: spelled(s, true) and ";\n".
std::string declaration(const Signature& s);
/// The head of the definition: spelled(s, false) and " {\n".
std::string definition(const Signature& s);
/// `s` as a model kernel defines it: pointers for std::span (the C table passes arrays of the
/// right sizes), size_t for std::size_t (no standard header).
Signature in_kernel(Signature s);

} // namespace phynjo::codegen::detail
