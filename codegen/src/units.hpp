#pragma once
// Physical dimensions of .lag files (docs/language.md, *Units*): parsing `[unit]` texts and
// checking the dimensions of expressions on the position-tagged AST, so that an error
// points at the offending term. Internal to the front end (frontend.cpp).
#include "phynjo/grammar/ast.hpp"
#include "phynjo/grammar/diagnostics.hpp"
#include "phynjo/grammar/expression.hpp"

#include <gmpxx.h>

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace phynjo::codegen::units {

/// A dimension: rational exponents of kg, m, s, A, K, mol, cd (rad is dimensionless).
/// `any`: the bare number 0, which fits every dimension.
struct Dim {
    std::array<mpq_class, 7> e{};
    bool any = false;
    [[nodiscard]] bool dimensionless() const;
    friend bool operator==(const Dim& a, const Dim& b) { return a.e == b.e; }
};
Dim operator*(const Dim& a, const Dim& b);
Dim operator/(const Dim& a, const Dim& b);
Dim pow(const Dim& d, const mpq_class& k);

/// "kg*m^2/s^2"; "1" when dimensionless.
std::string to_string(const Dim& d);
/// to_string, prefixed by the named unit it equals: "J = kg*m^2/s^2".
std::string describe(const Dim& d);

Dim energy();  ///< J
Dim power();   ///< W
Dim seconds(); ///< s
Dim metres();  ///< m

/// A unit's text (`m/s^2`, `kg*m^2`, `1/s`, `N*m`): its dimension, or where (offset in
/// `text`) and what is wrong.
struct ParsedUnit {
    std::optional<Dim> dim;
    std::size_t where = 0, length = 1;
    std::string error;
};
ParsedUnit parse_unit(std::string_view text);

/// The dimensions of expressions, reported to the sink at the offending node.
class Checker {
public:
    /// `lookup`: the dimension of a declared name (nothing for an unknown one: reported
    /// elsewhere); `t` is seconds, `pi` dimensionless.
    Checker(const grammar::Positions& positions, grammar::DiagnosticSink& sink,
            std::function<std::optional<Dim>(std::string_view)> lookup)
        : pos_(positions), sink_(sink), lookup_(std::move(lookup)) {}

    /// The dimension of `e`, every `+`, `-`, function argument and power checked; nothing
    /// after an error (reported once).
    std::optional<Dim> of(const grammar::ast::Expression& e);
    std::optional<Dim> of(const grammar::ast::Product& p);
    /// The dimension of a `[unit]` (reported when unknown).
    std::optional<Dim> of(const grammar::ast::Unit& u);
    /// Reports `what` at `node` unless `found` is `expected` (or any).
    bool expect(const boost::spirit::x3::position_tagged& node, const Dim& found, const Dim& expected, const std::string& what);

private:
    std::optional<Dim> of(const grammar::ast::Unary& u);
    std::optional<Dim> of(const grammar::ast::Power& p);
    std::optional<Dim> of(const grammar::ast::Postfix& p);
    std::optional<Dim> of(const grammar::ast::Call& c);
    void error(const boost::spirit::x3::position_tagged& node, const std::string& message);

    const grammar::Positions& pos_;
    grammar::DiagnosticSink& sink_;
    std::function<std::optional<Dim>(std::string_view)> lookup_;
};

/// The exact value of an expression made of numbers only (`2`, `-1/2`, `(3)`), or nothing.
std::optional<mpq_class> numeric_value(const grammar::ast::Expression& e);

} // namespace phynjo::codegen::units
