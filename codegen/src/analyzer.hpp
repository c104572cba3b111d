#pragma once
// The front end's analyzer (internal): the statements of a parsed model, one visit per
// statement kind, into a checked Model — scope, the meaning of `'`, constants, units,
// statement counts. frontend.cpp holds the scope and the expressions; analyze_*.cpp one
// statement kind each (declarations, constraints, events, shapes, dynamics).
#include "phynjo/codegen/frontend.hpp"

#include "phynjo/cas/cas.hpp"

#include "units.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace phynjo::codegen::detail {

using cas::Expr;
using grammar::ast::Statement;

enum class NameKind { Coordinate, Parameter, Let };
struct Declared {
    NameKind kind;
    Expr value; // symbol (coordinate, parameter) or the let's value
    SourceSpan where;
    std::size_t index = 0;
};

class Analyzer {
public:
    Analyzer(const grammar::Positions& positions, grammar::DiagnosticSink& sink) : pos_(positions), sink_(sink) {}

    std::optional<Model> run(const grammar::ParsedModel& parsed, std::string_view default_name);

private:
    const grammar::Positions& pos_;
    grammar::DiagnosticSink& sink_;
    Model model_;
    std::map<std::string, Declared, std::less<>> scope_;
    bool coordinates_seen_ = false, lagrangian_seen_ = false, dissipation_seen_ = false, model_seen_ = false;
    std::vector<std::string> failed_names_; ///< names declared in statements with syntax errors
    SourceSpan coordinates_at_, lagrangian_at_, dissipation_at_, model_at_;
    std::vector<Expr> forces_, init_q_, init_qd_;
    /// Dimensions, when the file carries units: the checker and every declared name's.
    std::optional<units::Checker> units_;
    std::map<std::string, units::Dim, std::less<>> dims_;

    /// The dimension of `e` (nothing after an error, or without units).
    std::optional<units::Dim> dim(const grammar::ast::Expression& e) { return units_ ? units_->of(e) : std::nullopt; }
    /// Records the dimension of a declared name; after an error, one that fits anything (no cascade).
    std::string record_dim(const std::string& name, std::optional<units::Dim> d) {
        if (!d) {
            d = units::Dim{};
            d->any = true;
        }
        dims_[name] = *d;
        return d->any || d->dimensionless() ? std::string() : units::to_string(*d);
    }
    /// A unit's text as the file writes it, without its blanks (`N / m` → "N/m").
    static std::string as_written(const grammar::ast::Unit& u) {
        std::string out;
        for (char c : u.text)
            if (!std::isspace(static_cast<unsigned char>(c))) out += c;
        return out;
    }
    /// Checks that every term of a sum has dimension `expected`.
    void check_terms(const grammar::ast::Expression& e, const units::Dim& expected, const std::string& what) {
        if (!units_) return;
        if (auto d = units_->of(e.first)) units_->expect(e.first, *d, expected, what);
        for (const auto& op : e.rest)
            if (auto d = units_->of(op.operand)) units_->expect(op.operand, *d, expected, what);
    }
    /// Checks that `e` has the dimension of coordinate i (its velocity when `velocity`).
    void check_like(const grammar::ast::Expression& e, std::size_t i, bool velocity, const std::string& what) {
        if (!units_) return;
        units::Dim target = dims_.at(model_.coordinates[i].name);
        if (velocity) target = target / units::seconds();
        if (auto d = units_->of(e)) units_->expect(e, *d, target, what);
    }

    SourceSpan span(const boost::spirit::x3::position_tagged& node) const {
        const auto s = pos_.of(node);
        return {s.offset, s.length};
    }
    void error(SourceSpan at, std::string message) { sink_.error(at.offset, at.length, std::move(message)); }
    void note(SourceSpan at, std::string message) { sink_.note(at.offset, at.length, std::move(message)); }

    /// A statement that may appear once: reports a second one.
    bool once(bool& seen, SourceSpan& first, SourceSpan here, const char* what) {
        if (seen) {
            error(here, std::string("a second '") + what + "' statement");
            note(first, std::string("the first '") + what + "' statement is here");
            return false;
        }
        seen = true;
        first = here;
        return true;
    }

    bool declare(const grammar::ast::Name& name, NameKind kind, Expr value);

    bool is_coordinate(Expr e) const;

    const Parameter* parameter(Expr e) const;

    /// Every parameter declared so far → its exact value.
    std::unordered_map<Expr, Expr> parameter_values() const;

    /// An expression in the current scope, with the spec's meaning of `'`.
    std::optional<Expr> expression(const grammar::ast::Expression& tree);

    /// A constant: no coordinate, velocity or t. Parameters are allowed when `allow_parameters`.
    bool constant(Expr e, const grammar::ast::Expression& tree, const std::string& what, bool allow_parameters);

    void visit(const grammar::ast::ModelStmt& s);

    void visit(const grammar::ast::CoordinatesStmt& s);

    void visit(const grammar::ast::ParametersStmt& s) { declare_parameters(s.items, false); }
    void visit(const grammar::ast::InputStmt& s) { declare_parameters(s.items, true); }

    /// `parameters` (input = false) or `input` bindings: constant defaults, exact.
    void declare_parameters(const std::vector<grammar::ast::Binding>& items, bool input);

    /// False, after an error with a note to the first, when `items` (constraints, events)
    /// already hold one named like `name`.
    template <typename Items>
    bool first_of_its_name(const Items& items, const grammar::ast::Name& name, const char* what) {
        for (const auto& item : items)
            if (item.name == name.text) {
                error(span(name), std::string("a second ") + what + " named '" + name.text + "'");
                note(item.where, std::string("the first ") + what + " '" + name.text + "' is here");
                return false;
            }
        return true;
    }

    void visit(const grammar::ast::ConstraintStmt& s);

    void visit(const grammar::ast::EventStmt& s);

    /// A shape: its points may depend on q, t, parameters and inputs (not velocities);
    /// a sphere's radius is a positive constant (numbers and parameters). A shape that
    /// depends on no coordinate is allowed: a fixed (or moved by t) obstacle.
    void visit(const grammar::ast::ShapeStmt& s);

    void visit(const grammar::ast::LetStmt& s);

    void visit(const grammar::ast::LagrangianStmt& s);

    void visit(const grammar::ast::DissipationStmt& s);

    /// The index of coordinate `name`, or nothing after reporting why not.
    std::optional<std::size_t> coordinate_index(const grammar::ast::Name& name, const char* context);

    void visit(const grammar::ast::ForceStmt& s);

    void visit(const grammar::ast::InitialStmt& s);
};


} // namespace phynjo::codegen::detail
