// Golden diagnostics: the exact text a user sees for each kind of mistake.
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

namespace {
std::string diagnose(std::string_view text) {
    try {
        (void)phynjo::grammar::parse(text, "in.txt");
    } catch (const phynjo::grammar::ParseError& e) {
        return e.what();
    }
    return "(accepted)";
}
} // namespace

TEST_CASE("golden diagnostics", "[grammar][diagnostics]") {
    const std::pair<std::string_view, std::string_view> cases[] = {
        {"x +", "in.txt:1:4: error: expected an expression\n    x +\n       ^\n"},
        {"x y", "in.txt:1:3: error: unexpected 'y' (missing operator?)\n    x y\n      ^\n"},
        {"2 x1", "in.txt:1:3: error: unexpected 'x1' (missing operator?)\n    2 x1\n      ^~\n"},
        {"(x + 1", "in.txt:1:1: error: '(' is never closed\n    (x + 1\n    ^\n"},
        {"x + 1)", "in.txt:1:6: error: unmatched ')'\n    x + 1)\n         ^\n"},
        {"x * * y", "in.txt:1:5: error: expected an expression, found '*'\n    x * * y\n        ^\n"},
        {"foo(x)",
         "in.txt:1:1: error: unknown function 'foo' (functions: sin, cos, tan, exp, log, sqrt, asin, acos, atan, atan2, sinh, cosh, tanh, abs, sign; missing '*'?)\n"
         "    foo(x)\n    ^~~\n"},
        {"pi(x)", "in.txt:1:1: error: 'pi' is not a function (missing '*'?)\n    pi(x)\n    ^~\n"},
        {"sin + 1", "in.txt:1:1: error: 'sin' is a function: write sin(…)\n    sin + 1\n    ^~~\n"},
        {"m/(a - a)", "in.txt:1:3: error: division by zero\n    m/(a - a)\n      ^~~~~~~\n"},
        {"log(1 - 1)", "in.txt:1:1: error: log(0) is undefined\n    log(1 - 1)\n    ^~~~~~~~~~\n"},
        {"tan(pi/2)", "in.txt:1:1: error: tan is undefined at odd multiples of pi/2\n    tan(pi/2)\n    ^~~~~~~~~\n"},
        {"x @ y", "in.txt:1:3: error: unexpected character '@'\n    x @ y\n      ^\n"},
        {"θ + 1", "in.txt:1:1: error: unexpected character 'θ' (U+03B8): names are ASCII letters, digits and _\n    θ + 1\n    ^\n"},
        {"x + θ", "in.txt:1:5: error: unexpected character 'θ' (U+03B8): names are ASCII letters, digits and _\n    x + θ\n        ^\n"},
        {"", "in.txt:1:1: error: expected an expression\n    \n    ^\n"},
        {"(x +\n  * y)", "in.txt:2:3: error: expected an expression, found '*'\n      * y)\n      ^\n"},
        {"\tx +", "in.txt:1:5: error: expected an expression\n    \tx +\n    \t   ^\n"},
        {"sin(x, y)", "in.txt:1:1: error: 'sin' takes one argument, not 2\n    sin(x, y)\n    ^~~~~~~~~\n"},
        {"atan2(y)", "in.txt:1:1: error: 'atan2' takes two arguments (atan2(y, x)), not 1\n    atan2(y)\n    ^~~~~~~~\n"},
        {"atan2(y, x, 1)", "in.txt:1:1: error: 'atan2' takes two arguments (atan2(y, x)), not 3\n    atan2(y, x, 1)\n    ^~~~~~~~~~~~~~\n"},
        {"atan2(y,)", "in.txt:1:9: error: unexpected ')'\n    atan2(y,)\n            ^\n"},
        {"atan2(0, 0)", "in.txt:1:1: error: atan2(0, 0) is undefined\n    atan2(0, 0)\n    ^~~~~~~~~~~\n"},
        {"1e5000000", "in.txt:1:1: error: number too large (at most 31000 significant digits, a "
                      "decimal exponent within ±31000 and 100000 bits)\n    1e5000000\n    ^~~~~~~~~\n"},
    };
    for (const auto& [input, expected] : cases) {
        INFO("input: " << input);
        CHECK(diagnose(input) == expected);
    }
}

TEST_CASE("diagnostic sink locates lines and columns", "[grammar][diagnostics]") {
    const std::string_view text = "ab\ncé d\n";
    phynjo::grammar::DiagnosticSink sink("f", text, 10);
    CHECK(sink.locate(0).line == 10);
    CHECK(sink.locate(3).line == 11);
    CHECK(sink.locate(6).column == 3); // after the two-byte 'é': code points, not bytes
    sink.error(6, 1, "here");
    CHECK(sink.format_all() == "f:11:3: error: here\n    cé d\n      ^\n");
}
