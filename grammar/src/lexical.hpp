#pragma once
// The lexical helpers both parsers share (expression.cpp and lag.cpp): white space and
// comments, what stands at a position (for messages), and the one wording of "expected …"
// for what the X3 error handler records (expression_def.hpp).
#include "phynjo/grammar/diagnostics.hpp"

#include <cstddef>
#include <string>
#include <string_view>

namespace phynjo::grammar::lexical {

/// The first offset at or after `i` (and before `end`) that is neither white space nor inside
/// a `#` comment.
std::size_t skip_blank(std::string_view text, std::size_t i, std::size_t end);

/// What stands at an offset, for messages.
struct Token {
    enum class Kind { End, Word, Open, Invalid, Other } kind;
    std::string shown; ///< quoted text, or a description of a bad character or byte
    std::size_t length = 1;
};

/// The token at `i` (before `end`): a word (letters, digits, '_', '.'), '(', an operator, or an
/// invalid character named by itself and its code point, or a byte that is not UTF-8 text.
Token token_at(std::string_view text, std::size_t i, std::size_t end);

/// Reports at `at` that `which` (X3's name of the rule or literal expected there) was
/// expected: "expected an expression, found 'x'"; an invalid character is reported as
/// unexpected. `end_name` names the end of the text in messages ("end of line"); empty:
/// just "expected …" there. `hint` is appended to the message.
void report_expected(std::string_view text, std::size_t at, std::size_t end, std::string_view which,
                     std::string_view end_name, DiagnosticSink& sink, std::string_view hint = {});

} // namespace phynjo::grammar::lexical
