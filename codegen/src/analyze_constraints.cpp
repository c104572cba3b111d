// The constraint statement: holonomic or nonholonomic (linear in the velocities), its units. (analyzer.hpp)
#include "analyzer.hpp"

namespace phynjo::codegen::detail {

void Analyzer::visit(const grammar::ast::ConstraintStmt& s) {
    const SourceSpan at = span(s.name);
    if (!first_of_its_name(model_.constraints, s.name, "constraint")) return;
    auto a = expression(s.lhs);
    auto b = expression(s.rhs);
    if (!a || !b) return;
    if (units_) {
        auto da = dim(s.lhs), db = dim(s.rhs);
        if (da && db && !da->any)
            units_->expect(s.rhs, *db, *da, "the sides of constraint '" + s.name.text + "' differ in dimension");
    }
    const Expr phi = *a - *b;
    const auto vars = cas::free_variables(phi);
    bool has_velocity = false, has_coordinate = false;
    for (Expr v : vars) {
        if (v.kind() == cas::Kind::TimeDerivative) has_velocity = true;
        else if (is_coordinate(v)) has_coordinate = true;
        else if (const Parameter* p = parameter(v); p && p->input) {
            error(at, "constraint '" + s.name.text + "' depends on the input " + p->name +
                          ": a constraint may use t, coordinates, velocities and parameters, not inputs (their "
                          "time derivatives are unknown)");
            return;
        }
    }
    if (!has_velocity && !has_coordinate) {
        error(at, "constraint '" + s.name.text + "' involves no coordinate or velocity");
        return;
    }
    if (has_velocity) {
        // linear in the velocities: every ∂φ/∂q_i' free of velocities
        for (Expr v : vars) {
            if (v.kind() != cas::Kind::TimeDerivative) continue;
            Expr a_i;
            try {
                a_i = cas::diff(phi, v);
            } catch (const cas::Error& e) {
                error(at, "constraint '" + s.name.text + "': " + e.what());
                return;
            }
            for (Expr w : cas::free_variables(a_i))
                if (w.kind() == cas::Kind::TimeDerivative) {
                    error(at, "constraint '" + s.name.text + "' is not linear in the velocities: " + cas::to_string(v) +
                                  " enters nonlinearly (a nonholonomic constraint must be a(q, t)*q' + b(q, t) = 0)");
                    return;
                }
        }
    }
    model_.constraints.push_back({s.name.text, phi, !has_velocity, at});
}

} // namespace phynjo::codegen::detail
