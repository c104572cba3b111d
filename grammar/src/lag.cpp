// .lag files: a lexical pass (UTF-8, size, comments, parentheses, statement boundaries),
// then the X3 statement rules on each statement. This translation unit and expression.cpp
// are the only ones that instantiate X3 templates.
#include "phynjo/grammar/lag.hpp"

#include "lag_def.hpp"

#include <array>

namespace phynjo::grammar {

namespace {

constexpr std::array<std::string_view, 8> keywords{"model", "coordinates", "parameters", "let",
                                                     "lagrangian", "dissipation", "force", "initial"};
constexpr std::array<std::string_view, 8> builtins{"t", "pi", "sin", "cos", "tan", "exp", "log", "sqrt"};

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
};

/// Splits the file into statements: a newline ends a statement unless a '(' is open.
/// Reports unbalanced parentheses and too deep nesting; a statement with such an error is
/// left out.
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
        if (!bad && !blank) out.push_back({start, end});
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

std::string describe_word_at(std::string_view text, std::size_t at, std::size_t end, std::size_t& length) {
    std::size_t j = at;
    while (j < end && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_')) ++j;
    length = std::max<std::size_t>(j - at, 1);
    if (j == at) return at < end ? "'" + std::string(1, text[at]) + "'" : "end of line";
    return "'" + std::string(text.substr(at, j - at)) + "'";
}

} // namespace

bool is_keyword(std::string_view name) {
    for (auto k : keywords)
        if (k == name) return true;
    return false;
}
bool is_builtin(std::string_view name) {
    for (auto b : builtins)
        if (b == name) return true;
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
    for (const Range& r : split_statements(text, sink, limits.expression)) {
        auto first = text.begin() + static_cast<std::ptrdiff_t>(r.begin);
        const auto last = text.begin() + static_cast<std::ptrdiff_t>(r.end);
        parser::DepthCounter depth{0, limits.expression.max_depth};
        const auto p = x3::with<parser::position_cache_tag>(std::ref(positions.cache()))
            [x3::with<parser::depth_tag>(std::ref(depth))[parser::statement]];
        ast::Statement st;
        auto skip_blank = [&](std::size_t i) {
            while (i < r.end) {
                const char c = text[i];
                if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') ++i;
                else if (c == '#') {
                    while (i < r.end && text[i] != '\n') ++i;
                } else break;
            }
            return i;
        };
        try {
            const bool ok = x3::phrase_parse(first, last, p, parser::skipper, st);
            const std::size_t at = skip_blank(static_cast<std::size_t>(first - text.begin()));
            if (!ok) {
                std::size_t len;
                const std::string found = describe_word_at(text, at, r.end, len);
                sink.error(at, len, "expected a statement (model, coordinates, parameters, let, lagrangian, "
                                    "dissipation, force or initial), found " + found);
                continue;
            }
            if (at != r.end) {
                std::size_t len;
                const std::string found = describe_word_at(text, at, r.end, len);
                const bool operand = std::isalnum(static_cast<unsigned char>(text[at])) || text[at] == '_' || text[at] == '(';
                sink.error(at, len, "unexpected " + found + (operand ? " (missing operator or ','?)" : ""));
                continue;
            }
            model.statements.push_back(std::move(st));
        } catch (const x3::expectation_failure<std::string_view::const_iterator>& e) {
            const std::size_t at = skip_blank(static_cast<std::size_t>(e.where() - text.begin()));
            std::size_t len;
            const std::string found = describe_word_at(text, at, r.end, len);
            std::string what = e.which();
            if (what == "operand" || what == "expression") what = "an expression";
            else if (what == "name") what = "a name";
            else if (what == "binding") what = "NAME = VALUE";
            sink.error(at, len, "expected " + what + ", found " + found);
        } catch (const parser::DepthExceeded& e) {
            sink.error(static_cast<std::size_t>(e.where - text.data()), 1,
                       "expression nested deeper than " + std::to_string(limits.expression.max_depth) + " levels");
        }
    }
    return model;
}

} // namespace phynjo::grammar
