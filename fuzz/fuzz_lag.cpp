// libFuzzer target: the whole .lag front end, the derivation and every emitter.
#include "fuzz_budget.hpp"
#include "phynjo/cas/errors.hpp"
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
            try {
                (void)phynjo::codegen::emit_cpp(*model, phynjo::codegen::optimize(*model, *eom), {.header_name = "fuzz.hpp", .main = true});
                (void)phynjo::codegen::emit_eom(*model, *eom);
                (void)phynjo::codegen::emit_latex(*model, *eom);
            } catch (const phynjo::cas::LimitError&) {
                // the budget above, far below the documented limits (phynjo-lagc reports a
                // LimitError as an error of the model, exit status 1)
            }
        }
    }
    (void)sink.format_all();
    return 0;
}
