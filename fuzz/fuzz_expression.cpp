// libFuzzer target: the expression parser and the conversion to CAS expressions.
// Property checked besides "no crash": a parsed expression prints to text that parses back
// to the same expression.
#include "fuzz_budget.hpp"
#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 8192) return 0;
    const std::string_view text = phynjo::fuzz::as_text(data, size);
    const phynjo::fuzz::BoundedPool pool; // memory and work bounded per input
    phynjo::grammar::DiagnosticSink sink("<fuzz>", text);
    phynjo::grammar::Positions positions(text);
    if (auto tree = phynjo::grammar::parse_expression(text, positions, sink)) {
        if (auto e = phynjo::grammar::to_expr(*tree, positions, sink)) {
            std::string printed;
            try {
                printed = phynjo::cas::to_string(*e, 100'000); // a documented limit, smaller here
            } catch (const phynjo::cas::LimitError&) {
                return 0;
            }
            if (phynjo::grammar::parse(printed) != *e) std::abort(); // round trip broken
        }
    }
    (void)sink.format_all();
    return 0;
}
