// libFuzzer target: the whole .lag front end, the derivation and every emitter.
#include "fuzz_budget.hpp"
#include "phynjo/codegen/emit.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"

#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 8192) return 0;
    const std::string_view text = phynjo::fuzz::as_text(data, size);
    const phynjo::fuzz::BoundedPool pool; // memory and work bounded per input
    phynjo::grammar::DiagnosticSink sink("fuzz.lag", text);
    auto model = phynjo::codegen::read_model(text, "fuzz.lag", sink);
    if (model) {
        if (auto eom = phynjo::codegen::derive(*model, sink)) {
            (void)phynjo::codegen::emit_cpp(*model, *eom, {.header_name = "fuzz.hpp", .main = true});
            (void)phynjo::codegen::emit_eom(*model, *eom);
            (void)phynjo::codegen::emit_latex(*model, *eom);
        }
    }
    (void)sink.format_all();
    return 0;
}
