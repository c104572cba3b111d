// Instantiates the expression grammar (the only translation unit with its X3 definitions:
// the statement grammar in lag.cpp calls the rules instantiated here) and runs it with the
// diagnostics this project promises.
#include "phynjo/grammar/expression.hpp"

#include "expression_def.hpp"
#include "lexical.hpp"

#include <cstdio>

namespace phynjo::grammar {

namespace parser {
BOOST_SPIRIT_INSTANTIATE(name_type, iterator_type, context_type)
BOOST_SPIRIT_INSTANTIATE(unit_type, iterator_type, context_type)
BOOST_SPIRIT_INSTANTIATE(expression_type, iterator_type, context_type)
} // namespace parser

Positions::Span Positions::of(const boost::spirit::x3::position_tagged& node) const {
    if (node.id_first < 0) return {0, 1};
    const auto range = cache_.position_of(node);
    const auto offset = static_cast<std::size_t>(range.begin() - text_.begin());
    const auto length = static_cast<std::size_t>(range.end() - range.begin());
    return {offset, length == 0 ? 1 : length};
}

namespace {

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

} // namespace

std::optional<ast::Expression> parse_expression(std::string_view text, Positions& positions, DiagnosticSink& sink,
                                                const Limits& limits) {
    namespace x3 = boost::spirit::x3;
    if (!check_parentheses(text, sink, limits)) return std::nullopt;
    parser::DepthCounter depth{0, limits.max_depth};
    auto first = text.begin();
    const auto last = text.end();
    ast::Expression tree;
    parser::ExpectationReport report;
    const auto p = x3::with<parser::error_report_tag>(std::ref(report))[x3::with<parser::position_cache_tag>(
        std::ref(positions.cache()))[x3::with<parser::depth_tag>(std::ref(depth))[parser::input]]];
    const std::size_t end = text.size();
    try {
        const bool ok = x3::phrase_parse(first, last, p, parser::skipper, tree);
        if (report.where) {
            const std::size_t at = lexical::skip_blank(text, static_cast<std::size_t>(report.where - text.data()), end);
            lexical::report_expected(text, at, end, report.which, "", sink);
            return std::nullopt;
        }
        const std::size_t at = lexical::skip_blank(text, static_cast<std::size_t>(first - text.begin()), end);
        if (!ok) {
            lexical::report_expected(text, at, end, "expression", "", sink);
            return std::nullopt;
        }
        if (at != end) {
            const lexical::Token t = lexical::token_at(text, at, end);
            const bool operand = t.kind == lexical::Token::Kind::Word || t.kind == lexical::Token::Kind::Open;
            sink.error(at, t.length, "unexpected " + t.shown + (operand ? " (missing operator?)" : ""));
            return std::nullopt;
        }
    } catch (const parser::DepthExceeded& e) {
        sink.error(static_cast<std::size_t>(e.where - text.data()), 1,
                   "expression nested deeper than " + std::to_string(limits.max_depth) + " levels");
        return std::nullopt;
    }
    return tree;
}

} // namespace phynjo::grammar
