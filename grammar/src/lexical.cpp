#include "lexical.hpp"

#include <cctype>
#include <cstdint>
#include <cstdio>

namespace phynjo::grammar::lexical {

std::size_t skip_blank(std::string_view text, std::size_t i, std::size_t end) {
    while (i < end) {
        const char c = text[i];
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v') ++i;
        else if (c == '#') {
            while (i < end && text[i] != '\n') ++i;
        } else break;
    }
    return i;
}

Token token_at(std::string_view text, std::size_t i, std::size_t end) {
    if (i >= end) return {Token::Kind::End, "end of input", 1};
    const unsigned char c = static_cast<unsigned char>(text[i]);
    auto word_char = [](unsigned char x) { return std::isalnum(x) || x == '_' || x == '.'; };
    if (word_char(c)) {
        std::size_t j = i;
        while (j < end && word_char(static_cast<unsigned char>(text[j]))) ++j;
        return {Token::Kind::Word, "'" + std::string(text.substr(i, j - i)) + "'", j - i};
    }
    if (c == '(') return {Token::Kind::Open, "'('", 1};
    char buf[8];
    if (c >= 0x80) {
        const std::size_t n = (c & 0xE0) == 0xC0 ? 2 : (c & 0xF0) == 0xE0 ? 3 : (c & 0xF8) == 0xF0 ? 4 : 1;
        bool valid = n > 1 && i + n <= end;
        for (std::size_t k = 1; valid && k < n; ++k) valid = (static_cast<unsigned char>(text[i + k]) & 0xC0) == 0x80;
        if (valid) {
            std::uint32_t cp = c & (n == 2 ? 0x1F : n == 3 ? 0x0F : 0x07);
            for (std::size_t k = 1; k < n; ++k) cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3F);
            char code[16];
            std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned>(cp));
            return {Token::Kind::Invalid,
                    "character '" + std::string(text.substr(i, n)) + "' (" + code + "): names are ASCII letters, digits and _",
                    n};
        }
        std::snprintf(buf, sizeof buf, "0x%02X", c);
        return {Token::Kind::Invalid, std::string("byte ") + buf + " (not UTF-8 text)", 1};
    }
    if (c < 0x20 || c == 0x7F) {
        std::snprintf(buf, sizeof buf, "0x%02X", c);
        return {Token::Kind::Invalid, std::string("control character ") + buf, 1};
    }
    if (c == '\'' || c == '*' || c == '/' || c == '+' || c == '-' || c == '^' || c == ')' || c == ',' || c == '=')
        return {Token::Kind::Other, "'" + std::string(1, static_cast<char>(c)) + "'", 1};
    return {Token::Kind::Invalid, "character '" + std::string(1, static_cast<char>(c)) + "'", 1};
}

namespace {
/// X3's names of rules and literals, as the messages say them.
std::string expected_thing(std::string_view which) {
    if (which == "operand" || which == "expression") return "an expression";
    if (which == "name") return "a name";
    if (which == "binding") return "NAME = VALUE";
    return std::string(which); // a literal: "')'", "'='"
}
} // namespace

void report_expected(std::string_view text, std::size_t at, std::size_t end, std::string_view which,
                     std::string_view end_name, DiagnosticSink& sink, std::string_view hint) {
    const Token t = token_at(text, at, end);
    // X3 names an unnamed parser by its C++ type: never show that
    if (which.find("boost") != std::string_view::npos) {
        if (t.kind == Token::Kind::End) sink.error(at, 1, "unexpected " + std::string(end_name.empty() ? "end of input" : end_name));
        else sink.error(at, t.length, "unexpected " + t.shown);
        return;
    }
    const std::string what = expected_thing(which);
    if (t.kind == Token::Kind::End)
        sink.error(at, 1, "expected " + what + (end_name.empty() ? "" : ", found " + std::string(end_name)) + std::string(hint));
    else if (t.kind == Token::Kind::Invalid) sink.error(at, t.length, "unexpected " + t.shown + std::string(hint));
    else sink.error(at, t.length, "expected " + what + ", found " + t.shown + std::string(hint));
}

} // namespace phynjo::grammar::lexical
