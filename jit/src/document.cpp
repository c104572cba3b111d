// A model's equations as text (jit/document.hpp).
#include "phynjo/jit/document.hpp"

#include "phynjo/cas/pool.hpp"
#include "phynjo/codegen/emit.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"
#include "phynjo/grammar/diagnostics.hpp"
#include "phynjo/jit/compile.hpp"

#include <optional>

namespace phynjo::jit {

std::string model_document(std::string_view text, const std::string& source_name, ModelDocument kind) {
    cas::Pool pool; // the model's own expressions, gone with it
    const cas::PoolScope scope(pool);
    grammar::DiagnosticSink sink(source_name, text);
    const auto model = codegen::read_model(text, source_name, sink);
    std::optional<codegen::EquationsOfMotion> eom;
    if (model) eom = codegen::derive(*model, sink);
    if (!model || !eom) throw ModelError(sink.format_all());
    switch (kind) {
    case ModelDocument::latex: return codegen::emit_latex(*model, *eom);
    case ModelDocument::equations: return codegen::emit_eom(*model, *eom);
    }
    return {};
}

} // namespace phynjo::jit
