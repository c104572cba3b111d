// The statements of the dynamics: lagrangian, dissipation, force, initial. (analyzer.hpp)
#include "analyzer.hpp"

namespace phynjo::codegen::detail {

void Analyzer::visit(const grammar::ast::LagrangianStmt& s) {
    if (!once(lagrangian_seen_, lagrangian_at_, span(s), "lagrangian")) return;
    model_.lagrangian_where = span(s);
    if (auto v = expression(s.value)) model_.lagrangian = *v;
    check_terms(s.value, units::energy(), "a term of the Lagrangian is not an energy");
}

void Analyzer::visit(const grammar::ast::DissipationStmt& s) {
    if (!once(dissipation_seen_, dissipation_at_, span(s), "dissipation")) return;
    if (auto v = expression(s.value)) model_.dissipation = *v;
    check_terms(s.value, units::power(), "a term of the dissipation function is not a power");
}

std::optional<std::size_t> Analyzer::coordinate_index(const grammar::ast::Name& name, const char* context) {
    auto it = scope_.find(name.text);
    if (it == scope_.end()) {
        error(span(name), "unknown name '" + name.text + "'");
        return std::nullopt;
    }
    if (it->second.kind != NameKind::Coordinate) {
        error(span(name), std::string(context) + " '" + name.text + "', which is not a coordinate");
        return std::nullopt;
    }
    return it->second.index;
}

void Analyzer::visit(const grammar::ast::ForceStmt& s) {
    auto i = coordinate_index(s.coordinate, "force on");
    auto v = expression(s.value);
    if (!i || !v) return;
    if (!forces_[*i].is_null()) {
        error(span(s.coordinate), "a second force on '" + s.coordinate.text + "'");
        return;
    }
    forces_[*i] = *v;
    if (units_)
        if (auto d = dim(s.value))
            units_->expect(s.value, *d, units::energy() / dims_.at(s.coordinate.text),
                           "the force on " + s.coordinate.text + " is not an energy per unit of " + s.coordinate.text);
}

void Analyzer::visit(const grammar::ast::InitialStmt& s) {
    for (const auto& b : s.items) {
        auto i = coordinate_index(b.name, "initial value of");
        auto v = expression(b.value);
        if (!i || !v) continue;
        if (b.primes.size() > 1) {
            error(span(b.name), "an initial value is given for a coordinate (" + b.name.text + ") or its velocity (" +
                                    b.name.text + "'), not for higher derivatives");
            continue;
        }
        const std::string what = "the initial value of " + b.name.text + b.primes;
        if (!constant(*v, b.value, what, true)) continue;
        // a real number at the parameters' defaults (sqrt(-1) must not start a run at NaN)
        {
            const auto values = parameter_values();
            bool real = true;
            try {
                real = std::isfinite(cas::evaluate(cas::subs(*v, values), {}));
            } catch (const cas::Error&) {
                real = false;
            }
            if (!real) {
                error(span(b.value), what + " is not a finite real number (at the parameters' defaults)");
                continue;
            }
        }
        check_like(b.value, *i, !b.primes.empty(), what);
        auto& slot = b.primes.empty() ? init_q_[*i] : init_qd_[*i];
        if (!slot.is_null()) {
            error(span(b.name), "a second initial value for " + b.name.text + b.primes);
            continue;
        }
        slot = *v;
    }
}

} // namespace phynjo::codegen::detail
