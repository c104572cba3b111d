// The declaring statements: model, coordinates, parameters and inputs, let. (analyzer.hpp)
#include "analyzer.hpp"

namespace phynjo::codegen::detail {

void Analyzer::visit(const grammar::ast::ModelStmt& s) {
    if (!once(model_seen_, model_at_, span(s), "model")) return;
    if (grammar::is_keyword(s.name.text) || grammar::is_builtin(s.name.text) || is_cpp_keyword(s.name.text)) {
        error(span(s.name), "'" + s.name.text + "' cannot name a model (it is a reserved word)");
        return;
    }
    model_.name = s.name.text;
}

void Analyzer::visit(const grammar::ast::CoordinatesStmt& s) {
    if (!once(coordinates_seen_, coordinates_at_, span(s), "coordinates")) return;
    for (const auto& decl : s.names) {
        const auto& n = decl.name;
        const Expr sym = cas::symbol(n.text);
        if (declare(n, NameKind::Coordinate, sym)) {
            model_.coordinates.push_back({n.text, sym, span(n), {}});
            if (units_) {
                model_.coordinates.back().unit = record_dim(n.text, decl.unit ? units_->of(*decl.unit) : units::Dim{});
                if (decl.unit && !dims_.at(n.text).any) model_.coordinates.back().unit = as_written(*decl.unit);
            }
        }
    }
    forces_.assign(model_.coordinates.size(), Expr{});
    init_q_.assign(model_.coordinates.size(), Expr{});
    init_qd_.assign(model_.coordinates.size(), Expr{});
}

void Analyzer::declare_parameters(const std::vector<grammar::ast::Binding>& items, bool input) {
    const std::string kind = input ? "input" : "parameter";
    for (const auto& b : items) {
        if (!b.primes.empty()) {
            error(span(b.name), input ? "an input name cannot carry ' (inputs are not coordinates)"
                                      : "a parameter name cannot carry ' (parameters are constants)");
            continue;
        }
        // a binding whose value is rejected (reported) still declares its name: its uses
        // are not also reported unknown (one mistake, one error)
        auto failed = [&] { failed_names_.push_back(b.name.text); };
        auto v = expression(b.value);
        if (!v) {
            failed();
            continue;
        }
        const std::string what = (input ? "the default of input '" : "the value of parameter '") + b.name.text + "'";
        if (!constant(*v, b.value, what, true)) {
            failed();
            continue;
        }
        // exact value: earlier parameters replaced by their values
        const auto values = parameter_values();
        Expr exact;
        double dflt = 0;
        try {
            exact = cas::subs(*v, values);
            dflt = cas::evaluate(exact, {});
        } catch (const cas::Error& e) {
            error(span(b.value), what + " is not a finite real number");
            failed();
            continue;
        }
        if (is_cpp_keyword(b.name.text)) {
            error(span(b.name), "'" + b.name.text + "' cannot name a" + (input ? "n " : " ") + kind +
                                    ": it is a C++ keyword, and " + kind +
                                    "s become fields of the generated Parameters struct");
            failed();
            continue;
        }
        const Expr sym = cas::symbol(b.name.text);
        // an input's default is a number: the input itself is what changes
        const bool derived = !input && !cas::free_symbols(*v).empty();
        if (declare(b.name, NameKind::Parameter, sym)) {
            model_.parameters.push_back({b.name.text, sym, exact, dflt, span(b.name), derived ? *v : Expr{}, input, {}});
            if (units_) {
                model_.parameters.back().unit = record_dim(b.name.text, dim(b.value));
                // a value that is one quantity (`k = 1/2 [N/m]`) keeps its unit as written
                const auto& top = b.value;
                if (top.rest.empty() && top.first.unit && top.first.after.empty() && !dims_.at(b.name.text).any)
                    model_.parameters.back().unit = as_written(*top.first.unit);
            }
        }
    }
}

void Analyzer::visit(const grammar::ast::LetStmt& s) {
    if (s.unit)
        error(span(*s.unit), "a let takes its dimension from its value: no unit on '" + s.name.text +
                                 "' (write units on the numbers of its value, or on parameters and coordinates)");
    if (units_) record_dim(s.name.text, dim(s.value));
    auto v = expression(s.value);
    if (!v) {
        // declare anyway (as unknown-valued) to avoid cascades of "unknown name"
        declare(s.name, NameKind::Let, cas::symbol(s.name.text));
        return;
    }
    declare(s.name, NameKind::Let, *v);
}

} // namespace phynjo::codegen::detail
