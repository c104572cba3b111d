// A model's equations as text (jit/document.hpp).
#include "phynjo/jit/document.hpp"

#include "phynjo/codegen/emit.hpp"

#include "derived_model.hpp"

namespace phynjo::jit {

std::string model_document(std::string_view text, const std::string& source_name, ModelDocument kind) {
    return detail::with_derived_model(text, source_name, [kind](const auto& model, const auto& eom) {
        return kind == ModelDocument::latex ? codegen::emit_latex(model, eom) : codegen::emit_eom(model, eom);
    });
}

} // namespace phynjo::jit
