// The front end: scope, `'`, constants, statement counts.
#include "phynjo/codegen/frontend.hpp"

#include "phynjo/cas/cas.hpp"

#include "units.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <array>
#include <map>

namespace phynjo::codegen {

namespace {

using cas::Expr;
using grammar::ast::Statement;

constexpr std::string_view cpp_keywords[] = {
    "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break", "case", "catch", "char",
    "char8_t", "char16_t", "char32_t", "class", "compl", "concept", "const", "consteval", "constexpr", "constinit",
    "const_cast", "continue", "co_await", "co_return", "co_yield", "decltype", "default", "delete", "do", "double",
    "dynamic_cast", "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto", "if",
    "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq", "nullptr", "operator", "or",
    "or_eq", "private", "protected", "public", "register", "reinterpret_cast", "requires", "return", "short", "signed",
    "sizeof", "static", "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local", "throw",
    "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using", "virtual", "void", "volatile",
    "wchar_t", "while", "xor", "xor_eq", "std", "phynjo", "final", "override", "import", "module"};

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

    std::optional<Model> run(const grammar::ParsedModel& parsed, std::string_view default_name) {
        model_.name = std::string(default_name);
        model_.dissipation = Expr(0);
        failed_names_ = parsed.failed_names;
        if (parsed.has_units)
            units_.emplace(pos_, sink_, [this](std::string_view name) -> std::optional<units::Dim> {
                if (auto it = dims_.find(name); it != dims_.end()) return it->second;
                return std::nullopt;
            });
        for (const Statement& st : parsed.statements) boost::apply_visitor([this](const auto& s) { visit(s); }, st);
        // one mistake, one error: a statement with a syntax error is not also missing
        auto failed = [&](std::string_view kw) {
            return std::find(parsed.failed_keywords.begin(), parsed.failed_keywords.end(), kw) != parsed.failed_keywords.end();
        };
        if (!coordinates_seen_ && !failed("coordinates")) error({0, 1}, "the model has no 'coordinates' statement");
        if (!lagrangian_seen_ && !failed("lagrangian")) error({0, 1}, "the model has no 'lagrangian' statement");
        if (sink_.error_count() > 0) return std::nullopt;
        const std::size_t n = model_.dof();
        model_.forces.resize(n, Expr(0));
        model_.initial_q.resize(n, Expr(0));
        model_.initial_qdot.resize(n, Expr(0));
        for (std::size_t i = 0; i < n; ++i) {
            if (!forces_[i].is_null()) model_.forces[i] = forces_[i];
            if (!init_q_[i].is_null()) model_.initial_q[i] = init_q_[i];
            if (!init_qd_[i].is_null()) model_.initial_qdot[i] = init_qd_[i];
        }
        return model_;
    }

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

    bool declare(const grammar::ast::Name& name, NameKind kind, Expr value) {
        const SourceSpan at = span(name);
        if (grammar::is_keyword(name.text)) {
            const bool v2 = name.text == "constraint" || name.text == "event" || name.text == "input" || name.text == "shape";
            error(at, "'" + name.text + "' is a keyword" + (v2 ? " (since contract v2 of the model format)" : "") +
                          " and cannot be declared");
            return false;
        }
        if (grammar::is_builtin(name.text)) {
            error(at, "'" + name.text + "' is a built-in name and cannot be declared");
            return false;
        }
        if (auto it = scope_.find(name.text); it != scope_.end()) {
            error(at, "'" + name.text + "' is already declared");
            note(it->second.where, "the first declaration of '" + name.text + "' is here");
            return false;
        }
        std::size_t index = 0;
        if (kind == NameKind::Coordinate) index = model_.coordinates.size();
        if (kind == NameKind::Parameter) index = model_.parameters.size();
        scope_.emplace(name.text, Declared{kind, value, at, index});
        return true;
    }

    bool is_coordinate(Expr e) const {
        return e.kind() == cas::Kind::Symbol &&
               std::any_of(model_.coordinates.begin(), model_.coordinates.end(), [&](const auto& c) { return c.symbol == e; });
    }

    const Parameter* parameter(Expr e) const {
        for (const Parameter& p : model_.parameters)
            if (p.symbol == e) return &p;
        return nullptr;
    }

    /// Every parameter declared so far → its exact value.
    std::unordered_map<Expr, Expr> parameter_values() const {
        std::unordered_map<Expr, Expr> values;
        for (const Parameter& p : model_.parameters) values.emplace(p.symbol, p.value);
        return values;
    }

    /// An expression in the current scope, with the spec's meaning of `'`.
    std::optional<Expr> expression(const grammar::ast::Expression& tree) {
        grammar::ConvertOptions options;
        options.resolve = [this](std::string_view name) -> std::optional<Expr> {
            if (auto it = scope_.find(name); it != scope_.end()) return it->second.value;
            // declared in a statement that had a syntax error (reported): not unknown as well
            if (std::find(failed_names_.begin(), failed_names_.end(), name) != failed_names_.end())
                return cas::symbol(name);
            return std::nullopt;
        };
        const auto coords = model_.coordinate_symbols();
        options.derivative = [this, coords](Expr operand, const grammar::ast::Postfix& node, grammar::DiagnosticSink& sink,
                                            const grammar::Positions& positions) -> std::optional<Expr> {
            const auto s = positions.of(node);
            if (is_coordinate(operand)) return cas::velocity(operand);
            if (operand.kind() == cas::Kind::TimeDerivative) {
                sink.error(s.offset, s.length,
                           "second derivative: " + std::string(cas::symbol_name(operand)) +
                               "'' is not allowed in a model (the equations of motion are derived from L)");
                return std::nullopt;
            }
            for (Expr v : cas::free_variables(operand))
                if (v.kind() == cas::Kind::TimeDerivative) {
                    sink.error(s.offset, s.length,
                               "second derivative: ' applied to an expression that contains the velocity " +
                                   cas::to_string(v));
                    return std::nullopt;
                }
            try {
                return cas::total_time_derivative(operand, coords);
            } catch (const cas::Error& e) {
                sink.error(s.offset, s.length, e.what());
                return std::nullopt;
            }
        };
        return grammar::to_expr(tree, pos_, sink_, options);
    }

    /// A constant: no coordinate, velocity or t. Parameters are allowed when `allow_parameters`.
    bool constant(Expr e, const grammar::ast::Expression& tree, const std::string& what, bool allow_parameters) {
        for (Expr v : cas::free_variables(e)) {
            const Parameter* p = v.kind() == cas::Kind::Symbol ? parameter(v) : nullptr;
            if (p && !p->input && allow_parameters) continue;
            std::string why = v == cas::time_symbol()                 ? "time t"
                              : v.kind() == cas::Kind::TimeDerivative ? "the velocity " + cas::to_string(v)
                              : p && p->input ? "the input " + cas::to_string(v) + " (inputs change during a run)"
                              : p             ? "the parameter " + cas::to_string(v)
                                              : "the coordinate " + cas::to_string(v);
            error(span(tree), what + " is not constant: it depends on " + why);
            return false;
        }
        return true;
    }

    void visit(const grammar::ast::ModelStmt& s) {
        if (!once(model_seen_, model_at_, span(s), "model")) return;
        if (grammar::is_keyword(s.name.text) || grammar::is_builtin(s.name.text) || is_cpp_keyword(s.name.text)) {
            error(span(s.name), "'" + s.name.text + "' cannot name a model (it is a reserved word)");
            return;
        }
        model_.name = s.name.text;
    }

    void visit(const grammar::ast::CoordinatesStmt& s) {
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

    void visit(const grammar::ast::ParametersStmt& s) { declare_parameters(s.items, false); }
    void visit(const grammar::ast::InputStmt& s) { declare_parameters(s.items, true); }

    /// `parameters` (input = false) or `input` bindings: constant defaults, exact.
    void declare_parameters(const std::vector<grammar::ast::Binding>& items, bool input) {
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

    void visit(const grammar::ast::ConstraintStmt& s) {
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

    void visit(const grammar::ast::EventStmt& s) {
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

    /// A shape: its points may depend on q, t, parameters and inputs (not velocities);
    /// a sphere's radius is a positive constant (numbers and parameters). A shape that
    /// depends on no coordinate is allowed: a fixed (or moved by t) obstacle.
    void visit(const grammar::ast::ShapeStmt& s) {
        const std::string what = "shape '" + s.name.text + "'";
        if (!first_of_its_name(model_.shapes, s.name, "shape")) return;
        Shape shape{s.name.text, Shape::Kind::Sphere, Expr{}, {}, span(s.name)};
        bool ok = true;
        auto point = [&](const grammar::ast::Point& p, const char* which) {
            for (const grammar::ast::Expression* e : {&p.x, &p.y, &p.z}) {
                auto v = expression(*e);
                if (!v) {
                    ok = false;
                    continue;
                }
                if (units_)
                    if (auto d = units_->of(*e)) units_->expect(*e, *d, units::metres(), std::string("the ") + which + " of " + what);
                for (Expr x : cas::free_variables(*v))
                    if (x.kind() == cas::Kind::TimeDerivative) {
                        error(span(*e), std::string("the ") + which + " of " + what + " depends on the velocity " + cas::to_string(x) +
                                            ": a shape's position may depend on t, coordinates, parameters and inputs");
                        ok = false;
                        break;
                    }
                shape.points.push_back(*v);
            }
        };
        if (const auto* sphere = boost::get<grammar::ast::Sphere>(&s.geometry)) {
            shape.kind = Shape::Kind::Sphere;
            if (auto r = expression(sphere->radius)) {
                if (units_)
                    if (auto d = units_->of(sphere->radius)) units_->expect(sphere->radius, *d, units::metres(), "the radius of " + what);
                if (!constant(*r, sphere->radius, "the radius of " + what, true)) ok = false;
                else {
                    double value = 0;
                    Expr exact = *r;
                    try {
                        exact = cas::subs(*r, parameter_values());
                        value = cas::evaluate(exact, {});
                    } catch (const cas::Error&) {
                        value = std::nan("");
                    }
                    if (!(value > 0) || !std::isfinite(value)) {
                        error(span(sphere->radius), "the radius of " + what + " is " + cas::to_string(*r) +
                                                        (exact == *r ? "" : " = " + cas::to_string(exact) + " at the parameters' defaults") +
                                                        ": a radius must be a positive finite length");
                        ok = false;
                    }
                    shape.radius = *r;
                }
            } else ok = false;
            point(sphere->centre, "centre");
        } else {
            const auto& segment = boost::get<grammar::ast::Segment>(s.geometry);
            shape.kind = Shape::Kind::Segment;
            point(segment.from, "first end");
            point(segment.to, "second end");
        }
        if (ok) model_.shapes.push_back(std::move(shape));
    }

    void visit(const grammar::ast::LetStmt& s) {
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

    void visit(const grammar::ast::LagrangianStmt& s) {
        if (!once(lagrangian_seen_, lagrangian_at_, span(s), "lagrangian")) return;
        model_.lagrangian_where = span(s);
        if (auto v = expression(s.value)) model_.lagrangian = *v;
        check_terms(s.value, units::energy(), "a term of the Lagrangian is not an energy");
    }

    void visit(const grammar::ast::DissipationStmt& s) {
        if (!once(dissipation_seen_, dissipation_at_, span(s), "dissipation")) return;
        if (auto v = expression(s.value)) model_.dissipation = *v;
        check_terms(s.value, units::power(), "a term of the dissipation function is not a power");
    }

    /// The index of coordinate `name`, or nothing after reporting why not.
    std::optional<std::size_t> coordinate_index(const grammar::ast::Name& name, const char* context) {
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

    void visit(const grammar::ast::ForceStmt& s) {
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

    void visit(const grammar::ast::InitialStmt& s) {
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
};

} // namespace

bool is_cpp_keyword(std::string_view name) {
    return std::find(std::begin(cpp_keywords), std::end(cpp_keywords), name) != std::end(cpp_keywords);
}

std::string model_name_from_path(std::string_view path) {
    std::string_view stem = path;
    if (auto slash = stem.find_last_of('/'); slash != std::string_view::npos) stem = stem.substr(slash + 1);
    if (auto dot = stem.rfind('.'); dot != std::string_view::npos && dot > 0) stem = stem.substr(0, dot);
    std::string out;
    for (char c : stem) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '_') ? c : '_';
    if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0]))) out = "model_" + out;
    if (is_cpp_keyword(out) || grammar::is_keyword(out) || grammar::is_builtin(out)) out += "_model";
    return out;
}

std::optional<Model> analyze(const grammar::ParsedModel& parsed, const grammar::Positions& positions,
                             grammar::DiagnosticSink& sink, std::string_view default_name) {
    Analyzer a(positions, sink);
    auto m = a.run(parsed, default_name);
    if (m) m->source_name = sink.source_name();
    return m;
}

std::optional<Model> read_model(std::string_view text, std::string_view source_name, grammar::DiagnosticSink& sink) {
    const grammar::FileLimits limits;
    if (text.size() <= limits.max_bytes && text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
        sink.error(0, 1, "the model file is empty");
        return std::nullopt;
    }
    grammar::Positions positions(text);
    const auto parsed = grammar::parse_model(text, positions, sink, limits);
    if (!parsed.readable) return std::nullopt;
    auto m = analyze(parsed, positions, sink, model_name_from_path(source_name));
    if (sink.error_count() > 0) return std::nullopt;
    return m;
}

} // namespace phynjo::codegen
