#pragma once
/// \file
/// Parsing the expression language into a position-tagged tree, and the tree into exact
/// CAS expressions.
#include "phynjo/cas/expr.hpp"
#include "phynjo/grammar/ast.hpp"
#include "phynjo/grammar/diagnostics.hpp"

#include <boost/spirit/home/x3/support/ast/position_tagged.hpp>

#include <functional>
#include <optional>
#include <string_view>
#include <vector>

namespace phynjo::grammar {

/// Documented limits that turn hostile input into a diagnostic (not a stack overflow).
struct Limits {
    /// Deepest nesting of parentheses, function calls and exponents (`a^b^c…`).
    std::size_t max_depth = 200;
};

/// Where each tagged node of a parsed tree came from.
class Positions {
public:
    explicit Positions(std::string_view text) : text_(text), cache_(text.begin(), text.end()) {}
    struct Span {
        std::size_t offset = 0;
        std::size_t length = 1;
    };
    [[nodiscard]] Span of(const boost::spirit::x3::position_tagged& node) const;
    [[nodiscard]] std::string_view text() const noexcept { return text_; }
    using Cache = boost::spirit::x3::position_cache<std::vector<std::string_view::const_iterator>>;
    Cache& cache() noexcept { return cache_; }

private:
    std::string_view text_;
    Cache cache_;
};

/// Parses `text` (all of it) as one expression. White space, and `#` comments to the end of
/// a line, may stand between tokens. Reports problems to `sink` and returns nothing then.
std::optional<ast::Expression> parse_expression(std::string_view text, Positions& positions, DiagnosticSink& sink,
                                                const Limits& limits = {});

/// How the conversion to CAS expressions treats names and `'`.
struct ConvertOptions {
    /// The expression a name stands for; nothing means "unknown name" (an error).
    /// Default: the symbol of that name. `t` (time) and `pi` never reach it.
    std::function<std::optional<cas::Expr>(std::string_view name)> resolve;
    /// `operand'`: the time derivative of `operand` written at `node`; report to the sink
    /// and return nothing to reject it. Default: cas::time_derivative.
    std::function<std::optional<cas::Expr>(cas::Expr operand, const ast::Postfix& node, DiagnosticSink& sink,
                                           const Positions& positions)>
        derivative;
};

/// The exact expression of a parsed tree. Numbers are read exactly (`9.81` is 981/100);
/// mathematical errors (`1/0`, `log(0)`) and unknown names or functions are reported at
/// their place.
std::optional<cas::Expr> to_expr(const ast::Expression& tree, const Positions& positions, DiagnosticSink& sink,
                                 const ConvertOptions& options = {});

/// Parses and converts one expression in which every name is a symbol, `t` is time and
/// `pi` is π. Throws ParseError carrying the formatted diagnostics.
cas::Expr parse(std::string_view text, std::string_view source_name = "<input>");

} // namespace phynjo::grammar
