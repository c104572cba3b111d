#pragma once
// A model text read and its equations derived, in a pool of expressions of its own
// (compile.cpp, document.cpp): what both do before they emit.
#include "phynjo/cas/pool.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"
#include "phynjo/grammar/diagnostics.hpp"
#include "phynjo/jit/compile.hpp"

#include <optional>
#include <string>
#include <string_view>

namespace phynjo::jit::detail {

/// `emit(model, equations)` on the model in `text`, inside the model's own pool (its
/// expressions gone when this returns); ModelError with every diagnostic when it has errors.
template <class Emit>
std::string with_derived_model(std::string_view text, const std::string& source_name, Emit emit) {
    cas::Pool pool;
    const cas::PoolScope scope(pool);
    grammar::DiagnosticSink sink(source_name, text);
    const auto model = codegen::read_model(text, source_name, sink);
    std::optional<codegen::EquationsOfMotion> eom;
    if (model) eom = codegen::derive(*model, sink);
    if (!model || !eom) throw ModelError(sink.format_all());
    return emit(*model, *eom);
}

} // namespace phynjo::jit::detail
