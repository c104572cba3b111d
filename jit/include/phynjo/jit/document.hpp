#pragma once
/// \file
/// A model's equations as text, for programs that show them (the Python package's
/// `Model.latex()`, `Model.equations()`): what `phynjo-lagc --emit=latex` and `--emit=eom` write.
#include <string>
#include <string_view>

namespace phynjo::jit {

enum class ModelDocument {
    latex,     ///< a LaTeX document: coordinates, parameters, L, M q'' = f, E (--emit=latex)
    equations, ///< M and f in the input syntax, one entry a line (--emit=eom)
};

/// The document of `text` (its diagnostics naming `source_name`). Throws ModelError
/// (compile.hpp) when the model has errors.
std::string model_document(std::string_view text, const std::string& source_name, ModelDocument kind);

} // namespace phynjo::jit
