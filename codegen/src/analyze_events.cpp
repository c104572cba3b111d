// The event statement: its guard, direction, resets and stop. (analyzer.hpp)
#include "analyzer.hpp"

namespace phynjo::codegen::detail {

void Analyzer::visit(const grammar::ast::EventStmt& s) {
    const SourceSpan at = span(s.name);
    const std::string ev = "event '" + s.name.text + "'";
    if (!first_of_its_name(model_.events, s.name, "event")) return;
    auto a = expression(s.lhs);
    auto b = expression(s.rhs);
    Event event{s.name.text, Expr{}, s.relation == '>' ? 1 : -1, {}, false, at};
    if (units_ && a && b) {
        auto da = dim(s.lhs), db = dim(s.rhs);
        if (da && db && !da->any)
            units_->expect(s.rhs, *db, *da, "the sides of the guard of " + ev + " differ in dimension");
    }
    bool ok = a && b;
    if (ok) {
        event.guard = *a - *b;
        // a guard with no t, coordinate, velocity or input never changes during a run
        bool varies = false;
        for (Expr v : cas::free_variables(event.guard)) {
            const Parameter* p = v.kind() == cas::Kind::Symbol ? parameter(v) : nullptr;
            if (!p || p->input) varies = true;
        }
        if (!varies) {
            error(span(s.lhs), "the guard of " + ev + " is constant: " + cas::to_string(event.guard) +
                                   " depends on no coordinate, velocity, input or t, so it never crosses zero");
            ok = false;
        }
    }
    const grammar::ast::EventAction* stop_at = nullptr;
    for (const auto& act : s.actions) {
        if (!act.value) {
            if (act.name.text == "stop" && act.primes.empty()) {
                if (event.stop) {
                    error(span(act), ev + " says 'stop' twice");
                    ok = false;
                }
                event.stop = true;
                stop_at = &act;
            } else {
                error(span(act), "expected '=' and a value after '" + act.name.text + act.primes +
                                     "' (an action is Q = EXPR, Q' = EXPR or stop)");
                ok = false;
            }
            continue;
        }
        auto i = coordinate_index(act.name, (ev + " resets").c_str());
        auto v = expression(*act.value);
        if (!i || !v) {
            ok = false;
            continue;
        }
        if (act.primes.size() > 1) {
            error(span(act.name), ev + " resets " + act.name.text + act.primes +
                                      ": an action resets a coordinate (Q = …) or its velocity (Q' = …)");
            ok = false;
            continue;
        }
        const bool velocity = act.primes.size() == 1;
        check_like(*act.value, *i, velocity, "the reset of " + act.name.text + act.primes + " by " + ev);
        for (const EventReset& r : event.resets)
            if (r.coordinate == *i && r.velocity == velocity) {
                error(span(act.name), ev + " resets " + act.name.text + act.primes + " twice");
                note(r.where, "the first reset of " + act.name.text + act.primes + " is here");
                ok = false;
            }
        event.resets.push_back({*i, velocity, *v, span(act.name)});
    }
    if (event.stop && !event.resets.empty()) {
        error(span(*stop_at), ev + " mixes 'stop' with resets: a run that stops at the event never uses the "
                                   "reset state (write two events, or drop the resets)");
        ok = false;
    }
    if (ok) model_.events.push_back(std::move(event));
}

} // namespace phynjo::codegen::detail
