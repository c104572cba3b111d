// The front end: the analyzer's scope and expressions, and the entry points (frontend.hpp).
#include "analyzer.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace phynjo::codegen {

namespace {

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

} // namespace

namespace detail {

std::optional<Model> Analyzer::run(const grammar::ParsedModel& parsed, std::string_view default_name) {
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

bool Analyzer::declare(const grammar::ast::Name& name, NameKind kind, Expr value) {
    const SourceSpan at = span(name);
    if (grammar::is_keyword(name.text)) {
        error(at, "'" + name.text + "' is a keyword and cannot be declared");
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

bool Analyzer::is_coordinate(Expr e) const {
    return e.kind() == cas::Kind::Symbol &&
           std::any_of(model_.coordinates.begin(), model_.coordinates.end(), [&](const auto& c) { return c.symbol == e; });
}

const Parameter* Analyzer::parameter(Expr e) const {
    for (const Parameter& p : model_.parameters)
        if (p.symbol == e) return &p;
    return nullptr;
}

std::unordered_map<Expr, Expr> Analyzer::parameter_values() const {
    std::unordered_map<Expr, Expr> values;
    for (const Parameter& p : model_.parameters) values.emplace(p.symbol, p.value);
    return values;
}

std::optional<Expr> Analyzer::expression(const grammar::ast::Expression& tree) {
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

bool Analyzer::constant(Expr e, const grammar::ast::Expression& tree, const std::string& what, bool allow_parameters) {
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

} // namespace detail

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
    detail::Analyzer a(positions, sink);
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
