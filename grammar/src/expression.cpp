// Instantiates the expression grammar (the only translation unit with X3 templates for it)
// and runs it with the diagnostics this project promises.
#include "phynjo/grammar/expression.hpp"

#include "expression_def.hpp"

#include <cstdio>

namespace phynjo::grammar {

Positions::Span Positions::of(const boost::spirit::x3::position_tagged& node) const {
    if (node.id_first < 0) return {0, 1};
    const auto range = cache_.position_of(node);
    const auto offset = static_cast<std::size_t>(range.begin() - text_.begin());
    const auto length = static_cast<std::size_t>(range.end() - range.begin());
    return {offset, length == 0 ? 1 : length};
}

namespace {

std::size_t skip_blank(std::string_view text, std::size_t i) {
    while (i < text.size()) {
        const char c = text[i];
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') ++i;
        else if (c == '#') {
            while (i < text.size() && text[i] != '\n') ++i;
        } else break;
    }
    return i;
}

/// Balanced parentheses and nesting depth, checked before parsing so that the messages name
/// the parenthesis at fault.
bool check_parentheses(std::string_view text, DiagnosticSink& sink, const Limits& limits) {
    std::vector<std::size_t> open;
    bool ok = true;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '#') {
            while (i < text.size() && text[i] != '\n') ++i;
        } else if (c == '(') {
            open.push_back(i);
            if (open.size() == limits.max_depth + 1) {
                sink.error(i, 1, "parentheses nested deeper than " + std::to_string(limits.max_depth) + " levels");
                return false;
            }
        } else if (c == ')') {
            if (open.empty()) {
                sink.error(i, 1, "unmatched ')'");
                ok = false;
            } else open.pop_back();
        }
    }
    if (!open.empty()) {
        sink.error(open.back(), 1, "'(' is never closed");
        ok = false;
    }
    return ok;
}

/// What stands at `i`, for messages.
struct Token {
    enum class Kind { End, Word, Open, Invalid, Other } kind;
    std::string shown; // quoted text, or a description of a bad byte
    std::size_t length = 1;
};

Token token_at(std::string_view text, std::size_t i) {
    if (i >= text.size()) return {Token::Kind::End, "end of input", 1};
    const unsigned char c = static_cast<unsigned char>(text[i]);
    auto word_char = [](unsigned char x) { return std::isalnum(x) || x == '_' || x == '.'; };
    if (word_char(c)) {
        std::size_t j = i;
        while (j < text.size() && word_char(static_cast<unsigned char>(text[j]))) ++j;
        return {Token::Kind::Word, "'" + std::string(text.substr(i, j - i)) + "'", j - i};
    }
    if (c == '(') return {Token::Kind::Open, "'('", 1};
    char buf[8];
    if (c >= 0x80) {
        const std::size_t n = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 1;
        bool valid = n > 1 && i + n <= text.size();
        for (std::size_t k = 1; valid && k < n; ++k) valid = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
        if (valid) return {Token::Kind::Invalid, "character '" + std::string(text.substr(i, n)) + "'", n};
        std::snprintf(buf, sizeof buf, "0x%02X", c);
        return {Token::Kind::Invalid, std::string("byte ") + buf + " (not UTF-8 text)", 1};
    }
    if (c < 0x20 || c == 0x7F) {
        std::snprintf(buf, sizeof buf, "0x%02X", c);
        return {Token::Kind::Invalid, std::string("control character ") + buf, 1};
    }
    if (c == '\'' || c == '*' || c == '/' || c == '+' || c == '-' || c == '^' || c == ')' || c == ',')
        return {Token::Kind::Other, "'" + std::string(1, static_cast<char>(c)) + "'", 1};
    return {Token::Kind::Invalid, "character '" + std::string(1, static_cast<char>(c)) + "'", 1};
}

void expected_expression(std::string_view text, std::size_t at, DiagnosticSink& sink) {
    const Token t = token_at(text, at);
    if (t.kind == Token::Kind::End) sink.error(at, 1, "expected an expression");
    else if (t.kind == Token::Kind::Invalid) sink.error(at, t.length, "unexpected " + t.shown);
    else sink.error(at, t.length, "expected an expression, found " + t.shown);
}

} // namespace

std::optional<ast::Expression> parse_expression(std::string_view text, Positions& positions, DiagnosticSink& sink,
                                                const Limits& limits) {
    namespace x3 = boost::spirit::x3;
    if (!check_parentheses(text, sink, limits)) return std::nullopt;
    parser::DepthCounter depth{0, limits.max_depth};
    auto first = text.begin();
    const auto last = text.end();
    ast::Expression tree;
    const auto p = x3::with<parser::position_cache_tag>(std::ref(positions.cache()))
        [x3::with<parser::depth_tag>(std::ref(depth))[parser::expression]];
    try {
        const bool ok = x3::phrase_parse(first, last, p, parser::skipper, tree);
        const std::size_t at = skip_blank(text, static_cast<std::size_t>(first - text.begin()));
        if (!ok) {
            expected_expression(text, at, sink);
            return std::nullopt;
        }
        if (at != text.size()) {
            const Token t = token_at(text, at);
            const bool operand = t.kind == Token::Kind::Word || t.kind == Token::Kind::Open;
            sink.error(at, t.length, "unexpected " + t.shown + (operand ? " (missing operator?)" : ""));
            return std::nullopt;
        }
    } catch (const x3::expectation_failure<std::string_view::const_iterator>& e) {
        const std::size_t at = skip_blank(text, static_cast<std::size_t>(e.where() - text.begin()));
        if (e.which() == "operand" || e.which() == "expression") expected_expression(text, at, sink);
        else {
            const Token t = token_at(text, at);
            sink.error(at, t.length, "expected " + e.which() + ", found " + t.shown);
        }
        return std::nullopt;
    } catch (const parser::DepthExceeded& e) {
        sink.error(static_cast<std::size_t>(e.where - text.data()), 1,
                   "expression nested deeper than " + std::to_string(limits.max_depth) + " levels");
        return std::nullopt;
    }
    return tree;
}

} // namespace phynjo::grammar
