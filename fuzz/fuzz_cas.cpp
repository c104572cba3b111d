// libFuzzer target: what `phynjo-cas simplify` and `diff` do with a parsed expression, and
// the other passes (expand, cse, printers, evaluation). Mathematical errors must come out as
// typed exceptions (cas::Error), never as crashes, hangs or silent NaN.
#include "fuzz_budget.hpp"
#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > 4096) return 0;
    using namespace phynjo;
    const std::string_view text = phynjo::fuzz::as_text(data, size);
    const phynjo::fuzz::BoundedPool pool; // memory and work bounded per input
    grammar::DiagnosticSink sink("<fuzz>", text);
    grammar::Positions positions(text);
    auto tree = grammar::parse_expression(text, positions, sink);
    if (!tree) return 0;
    auto e = grammar::to_expr(*tree, positions, sink);
    if (!e) return 0;
    try {
        const cas::Expr s = cas::simplify(*e);
        if (cas::simplify(s) != s) std::abort(); // idempotent
        for (cas::Expr v : cas::free_variables(*e)) {
            const cas::Expr d = cas::diff(*e, v);
            (void)cas::to_string(d);
        }
        (void)cas::to_cpp(s);
        (void)cas::to_latex(s);
        const auto r = cas::cse(std::vector<cas::Expr>{*e, s});
        (void)r;
        cas::Bindings<double> at;
        for (cas::Expr v : cas::free_variables(*e)) at[v] = 0.5;
        const double x = cas::evaluate(*e, at);
        if (!std::isfinite(x)) std::abort(); // evaluate reports non-finite values by exception
    } catch (const cas::Error&) {
        // typed: a domain error, a limit, a failed evaluation
    }
    return 0;
}
