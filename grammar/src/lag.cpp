// .lag files: a lexical pass (UTF-8, size, comments, parentheses, statement boundaries),
// then the X3 statement rules on each statement. This translation unit and expression.cpp
// are the only ones that instantiate X3 templates.
#include "phynjo/grammar/lag.hpp"

#include "lag_def.hpp"
#include "lexical.hpp"

#include <algorithm>
#include <array>
#include <cctype>

namespace phynjo::grammar {

namespace {

constexpr std::array<std::string_view, 12> keywords{"model",       "coordinates", "parameters", "let",
                                                      "lagrangian",  "dissipation", "force",      "initial",
                                                      "constraint",  "event",       "input",      "shape"};

/// Offset of the first byte that is not valid UTF-8, or npos.
std::size_t invalid_utf8(std::string_view s) {
    std::size_t i = 0;
    while (i < s.size()) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        std::size_t n = c < 0x80 ? 1 : (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 0;
        if (n == 0 || (n == 2 && c < 0xC2) || i + n > s.size()) return i;
        for (std::size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return i;
        if (c == 0) return i; // NUL: not text
        i += n;
    }
    return std::string_view::npos;
}

struct Range {
    std::size_t begin, end;
    bool bad = false; ///< unbalanced or too deep parentheses, reported: not parsed
};

/// Splits the file into statements: a newline ends a statement unless a '(' is open.
/// Reports unbalanced parentheses and too deep nesting; a statement with such an error is
/// marked bad (its keyword and names are still recorded, not parsed).
std::vector<Range> split_statements(std::string_view text, DiagnosticSink& sink, const Limits& limits) {
    std::vector<Range> out;
    std::vector<std::size_t> open;
    std::size_t start = 0;
    bool bad = false, blank = true;
    auto finish = [&](std::size_t end) {
        if (!open.empty()) {
            sink.error(open.back(), 1, "'(' is never closed");
            bad = true;
        }
        if (!blank) out.push_back({start, end, bad});
        open.clear();
        bad = false;
        blank = true;
        start = end + 1;
    };
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '#') {
            while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        } else if (c == '(') {
            open.push_back(i);
            if (open.size() == limits.max_depth + 1 && !bad) {
                sink.error(i, 1, "parentheses nested deeper than " + std::to_string(limits.max_depth) + " levels");
                bad = true;
            }
            blank = false;
        } else if (c == ')') {
            if (open.empty()) {
                if (!bad) sink.error(i, 1, "unmatched ')'");
                bad = true;
            } else open.pop_back();
            blank = false;
        } else if (c == '\n') {
            if (open.empty()) finish(i);
        } else if (c != ' ' && c != '\t' && c != '\r' && c != '\f' && c != '\v') blank = false;
    }
    if (!open.empty()) {
        // an unclosed '(' swallowed the rest of the file: report it once
        sink.error(open.front(), 1, "'(' is never closed");
        open.clear();
        bad = true;
    }
    finish(text.size());
    return out;
}

/// The keyword a misspelt first word most likely means (edit distance at most 2, the word at
/// least 4 letters), or nothing.
std::string_view closest_keyword(std::string_view word) {
    if (word.size() < 4) return {};
    std::string_view best;
    std::size_t best_d = 3;
    for (std::string_view k : keywords) {
        std::vector<std::size_t> row(k.size() + 1);
        for (std::size_t j = 0; j <= k.size(); ++j) row[j] = j;
        for (std::size_t i = 1; i <= word.size(); ++i) {
            std::size_t diag = row[0];
            row[0] = i;
            for (std::size_t j = 1; j <= k.size(); ++j) {
                const std::size_t up = row[j];
                row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (word[i - 1] == k[j - 1] ? 0 : 1)});
                diag = up;
            }
        }
        if (row[k.size()] < best_d) {
            best_d = row[k.size()];
            best = k;
        }
    }
    return best;
}

/// The names a coordinates, parameters or let statement declares: the name at its start
/// and (not for let) after every comma outside parentheses.
void declared_names(std::string_view text, std::size_t i, std::size_t end, std::string_view keyword,
                    std::vector<std::string>& out) {
    if (keyword != "coordinates" && keyword != "parameters" && keyword != "let" && keyword != "input") return;
    auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    bool head = true;
    int depth = 0;
    while (i < end) {
        if (head) {
            i = lexical::skip_blank(text, i, end);
            const std::size_t b = i;
            while (i < end && word_char(text[i])) ++i;
            if (i > b) out.emplace_back(text.substr(b, i - b));
            head = false;
            if (keyword == "let") return;
            continue;
        }
        const char c = text[i++];
        if (c == '(') ++depth;
        else if (c == ')') --depth;
        else if (c == ',' && depth == 0) head = true;
    }
}

} // namespace

bool is_keyword(std::string_view name) {
    for (auto k : keywords)
        if (k == name) return true;
    return false;
}

ParsedModel parse_model(std::string_view text, Positions& positions, DiagnosticSink& sink, const FileLimits& limits) {
    namespace x3 = boost::spirit::x3;
    ParsedModel model;
    if (text.size() > limits.max_bytes) {
        sink.error(0, 1, "file too large (" + std::to_string(text.size()) + " bytes; the limit is " +
                             std::to_string(limits.max_bytes) + ")");
        model.readable = false;
        return model;
    }
    if (const std::size_t bad = invalid_utf8(text); bad != std::string_view::npos) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "0x%02X", static_cast<unsigned char>(text[bad]));
        sink.error(bad, 1, std::string("not UTF-8 text: invalid byte ") + buf);
        model.readable = false;
        return model;
    }
    bool continuation_pending = false; // the last statement ended in mid-expression at a line end
    for (std::size_t i = 0; i < text.size() && !model.has_units; ++i) {
        if (text[i] == '#')
            while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
        else if (text[i] == '[') model.has_units = true;
    }
    for (const Range& r : split_statements(text, sink, limits.expression)) {
        auto first = text.begin() + static_cast<std::ptrdiff_t>(r.begin);
        const auto last = text.begin() + static_cast<std::ptrdiff_t>(r.end);
        parser::DepthCounter depth{0, limits.expression.max_depth};
        parser::ExpectationReport report;
        const auto p = x3::with<parser::error_report_tag>(std::ref(report))[x3::with<parser::position_cache_tag>(
            std::ref(positions.cache()))[x3::with<parser::depth_tag>(std::ref(depth))[parser::statement]]];
        ast::Statement st;
        // the statement's first word, for "one mistake, one error" (failed_keywords)
        const std::size_t w0 = lexical::skip_blank(text, r.begin, r.end);
        std::size_t w1 = w0;
        while (w1 < r.end && (std::isalnum(static_cast<unsigned char>(text[w1])) || text[w1] == '_')) ++w1;
        const std::string keyword(text.substr(w0, w1 - w0));
        if (r.bad) {
            model.failed_keywords.push_back(keyword);
            declared_names(text, w1, r.end, keyword, model.failed_names);
            continuation_pending = false;
            continue;
        }
        const bool after_break = continuation_pending;
        continuation_pending = false;
        bool failed = false;
        try {
            const bool ok = x3::phrase_parse(first, last, p, parser::skipper, st);
            if (report.where) {
                const std::size_t at =
                    lexical::skip_blank(text, static_cast<std::size_t>(report.where - text.data()), r.end);
                const lexical::Token t = lexical::token_at(text, at, r.end);
                if (report.which == "'='" && t.kind != lexical::Token::Kind::Invalid) {
                    // `parameters m, k = 2`: say which name lacks its value
                    std::size_t e = at;
                    while (e > r.begin && std::isspace(static_cast<unsigned char>(text[e - 1]))) --e;
                    while (e > r.begin && text[e - 1] == '\'') --e;
                    std::size_t b = e;
                    while (b > r.begin && (std::isalnum(static_cast<unsigned char>(text[b - 1])) || text[b - 1] == '_')) --b;
                    const std::string what = keyword == "parameters" ? "parameter"
                                             : keyword == "input"    ? "input"
                                             : keyword == "initial"  ? "initial value of"
                                                                     : "name";
                    sink.error(at, t.length, "expected '=' and a value after " + what + " '" +
                                                 std::string(text.substr(b, e - b)) + "'" +
                                                 (t.kind == lexical::Token::Kind::End ? "" : ", found " + t.shown));
                } else if ((report.which == "expression" || report.which == "operand") &&
                           t.kind == lexical::Token::Kind::End && lexical::skip_blank(text, r.end, text.size()) < text.size()) {
                    // `lagrangian a +` with `   b` on the next line: a newline ends a statement
                    lexical::report_expected(text, at, r.end, report.which, "end of line", sink,
                                             " (a statement goes on to the next line only inside parentheses: "
                                             "wrap it in ( ) )");
                    continuation_pending = true;
                } else if ((report.which == "expression" || report.which == "operand") && at > r.begin &&
                           text[at] == '=' && (text[at - 1] == '<' || text[at - 1] == '>')) {
                    // `event e: y <= 0 -> …`: a guard crosses, it has no equality
                    sink.error(at - 1, 2,
                               "'" + std::string(text.substr(at - 1, 2)) + "' is not an operator here: an event's guard "
                               "is written with '<' or '>' (it fires when the sides cross, so equality adds nothing): "
                               "write '" + std::string(1, text[at - 1]) + "'");
                } else lexical::report_expected(text, at, r.end, report.which, "end of line", sink);
                failed = true;
            } else {
                const std::size_t at = lexical::skip_blank(text, static_cast<std::size_t>(first - text.begin()), r.end);
                if (!ok) {
                    // the rest of a statement broken over two lines is no statement: one error is enough
                    const std::string_view meant = closest_keyword(keyword);
                    if (!after_break)
                        lexical::report_expected(text, at, r.end,
                                                 "a statement (model, coordinates, parameters, let, lagrangian, "
                                                 "dissipation, force, initial, input, constraint, event or shape)",
                                                 "end of line", sink,
                                                 meant.empty() ? std::string() : " (did you mean '" + std::string(meant) + "'?)");
                    if (!meant.empty()) {
                        model.failed_keywords.emplace_back(meant);
                        declared_names(text, w1, r.end, meant, model.failed_names);
                    }
                    failed = true;
                } else if (at != r.end) {
                    const lexical::Token t = lexical::token_at(text, at, r.end);
                    const bool operand = t.kind == lexical::Token::Kind::Word || t.kind == lexical::Token::Kind::Open;
                    sink.error(at, t.length, "unexpected " + t.shown + (operand ? " (missing operator or ','?)" : ""));
                    failed = true;
                }
            }
            if (failed) {
                model.failed_keywords.push_back(keyword);
                declared_names(text, w1, r.end, keyword, model.failed_names);
                continue;
            }
            model.statements.push_back(std::move(st));
        } catch (const parser::DepthExceeded& e) {
            sink.error(static_cast<std::size_t>(e.where - text.data()), 1,
                       "expression nested deeper than " + std::to_string(limits.expression.max_depth) + " levels");
            model.failed_keywords.push_back(keyword);
        }
    }
    return model;
}

} // namespace phynjo::grammar
