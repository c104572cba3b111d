// phynjo-cas: the CAS on the command line.
//   phynjo-cas simplify EXPR | diff VAR EXPR | latex EXPR | cpp EXPR | eval EXPR name=value…
//   phynjo-cas euler-lagrange q1,q2,… LAGRANGIAN
// EXPR `-` reads one expression per line from standard input and writes exactly one line per
// input line (an empty line for a rejected input, whose error goes to standard error).
// Exit status: 0 all inputs accepted, 1 some input rejected, 2 usage error.
#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#ifndef PHYNJO_VERSION
#define PHYNJO_VERSION "unknown"
#endif

namespace {

using namespace phynjo;
using cas::Expr;

constexpr const char* usage_text = R"(usage: phynjo-cas COMMAND ARGS…

commands:
  simplify EXPR                 canonical form, sin^2+cos^2 = 1, expansion when smaller
  diff VAR EXPR                 partial derivative by VAR (a name, or a velocity like q')
  latex EXPR                    LaTeX of EXPR
  cpp EXPR                      C++ expression of EXPR (std::sin, x*x, correctly rounded literals)
  eval EXPR NAME=VALUE…         numeric value (VALUEs are constant expressions; NAME may be q')
  euler-lagrange Q1,Q2,… L      dL/dq', dL/dq, d/dt dL/dq' and the Euler-Lagrange expression
                                d/dt(dL/dq') - dL/dq for each coordinate (only the coordinates
                                depend on time: (l*sin(q))' is l*cos(q)*q')

EXPR (or L) may be '-': then one expression per line of standard input, one result line per
input line (empty for a rejected input; its error goes to standard error).
Expressions use the syntax of .lag files: + - * / ^, unary -, x' (time derivative),
sin cos tan exp log sqrt asin acos atan atan2(y, x) sinh cosh tanh abs sign, pi, t (time),
exact numbers (9.81 is 981/100).

options: --help, --version
exit status: 0 ok, 1 an input was rejected, 2 usage error
)";

int usage_error(const std::string& message) {
    std::cerr << "phynjo-cas: " << message << "\n" << "try 'phynjo-cas --help'\n";
    return 2;
}

/// Parses `text`; reports to stderr as SOURCE:LINE:COL and returns nothing on failure.
std::optional<Expr> parse_reporting(std::string_view text, const std::string& source, std::size_t line) {
    grammar::DiagnosticSink sink(source, text, line);
    grammar::Positions positions(text);
    std::optional<Expr> e;
    if (auto tree = grammar::parse_expression(text, positions, sink)) e = grammar::to_expr(*tree, positions, sink);
    if (!e) std::cerr << sink.format_all();
    return e;
}

/// One command applied to one expression: the result line, or nothing after reporting an
/// error to stderr (with `where` as its location prefix).
using Action = std::function<std::optional<std::string>(Expr, const std::string& where)>;

int run(const std::string& expr_arg, const Action& action) {
    if (expr_arg != "-") {
        auto e = parse_reporting(expr_arg, "<argument>", 1);
        if (!e) return 1;
        auto r = action(*e, "<argument>");
        if (!r) return 1;
        std::cout << *r << "\n";
        return 0;
    }
    int status = 0;
    std::string line;
    for (std::size_t n = 1; std::getline(std::cin, line); ++n) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::optional<std::string> r;
        if (auto e = parse_reporting(line, "<stdin>", n)) r = action(*e, "<stdin>:" + std::to_string(n));
        if (!r) status = 1;
        std::cout << r.value_or("") << "\n";
    }
    return status;
}

/// Wraps a CAS computation: a cas::Error becomes `WHERE: error: …` on stderr.
template <typename F>
Action guarded(F f) {
    return [f](Expr e, const std::string& where) -> std::optional<std::string> {
        try {
            return f(e);
        } catch (const cas::Error& ex) {
            std::cerr << where << ": error: " << ex.what() << "\n";
            return std::nullopt;
        }
    };
}

std::optional<Expr> parse_variable(const std::string& text) {
    auto v = parse_reporting(text, "<variable>", 1);
    if (!v) return std::nullopt;
    if (!v->is_atom_variable()) {
        std::cerr << "phynjo-cas: '" << text << "' is not a variable (a name, or a name followed by ')\n";
        return std::nullopt;
    }
    return v;
}

int cmd_eval(const std::string& expr_arg, const std::vector<std::string>& assignments) {
    std::unordered_map<Expr, Expr> values;
    for (const std::string& a : assignments) {
        const auto eq = a.find('=');
        if (eq == std::string::npos) return usage_error("expected NAME=VALUE, got '" + a + "'");
        auto var = parse_variable(a.substr(0, eq));
        if (!var) return 2;
        auto value = parse_reporting(std::string_view(a).substr(eq + 1), "<value of " + a.substr(0, eq) + ">", 1);
        if (!value) return 2;
        values[*var] = *value;
    }
    return run(expr_arg, guarded([&](Expr e) {
                   // substitute exactly, then evaluate what is left (pi, functions) in double
                   const Expr s = cas::subs(e, values);
                   if (auto fv = cas::free_variables(s); !fv.empty())
                       throw cas::EvaluationError("no value for '" + cas::to_string(fv.front()) + "'");
                   return cas::double_literal(cas::evaluate(s, {}));
               }));
}

int cmd_euler_lagrange(const std::string& coords_arg, const std::string& expr_arg) {
    std::vector<Expr> coords;
    std::size_t start = 0;
    while (start <= coords_arg.size()) {
        const auto comma = coords_arg.find(',', start);
        const std::string name =
            coords_arg.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        auto q = parse_variable(name);
        if (!q || q->kind() != cas::Kind::Symbol) return usage_error("bad coordinate '" + name + "'");
        coords.push_back(*q);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return run(expr_arg, guarded([&](Expr L_in) {
                   // Mechanics: only the coordinates depend on time; a parameter's p' is 0.
                   std::unordered_map<Expr, Expr> constants;
                   for (Expr v : cas::free_variables(L_in))
                       if (cas::derivative_order(v) > 0 &&
                           std::find(coords.begin(), coords.end(), cas::symbol(cas::symbol_name(v))) == coords.end())
                           constants.emplace(v, Expr(0));
                   const Expr L = cas::subs(L_in, constants);
                   std::string out;
                   for (Expr q : coords) {
                       const std::string n = cas::to_string(q);
                       const Expr qd = cas::velocity(q);
                       const Expr p = cas::diff(L, qd);
                       const Expr dLdq = cas::diff(L, q);
                       const Expr dpdt = cas::total_time_derivative(p, coords);
                       const Expr el = cas::simplify(dpdt - dLdq);
                       if (!out.empty()) out += "; ";
                       out += "dL/d" + n + "' = " + cas::to_string(cas::simplify(p)) + "; dL/d" + n + " = " +
                              cas::to_string(cas::simplify(dLdq)) + "; d/dt(dL/d" + n +
                              "') = " + cas::to_string(cas::simplify(dpdt)) + "; EL[" + n + "] = " + cas::to_string(el);
                   }
                   return out;
               }));
}

} // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty()) return usage_error("missing command");
    const std::string& cmd = args[0];
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
        std::cout << usage_text;
        return 0;
    }
    if (cmd == "--version") {
        std::cout << "phynjo-cas " << PHYNJO_VERSION << "\n";
        return 0;
    }
    auto need = [&](std::size_t n) { return args.size() == n + 1; };
    try {
        if (cmd == "simplify" && need(1))
            return run(args[1], guarded([](Expr e) { return cas::to_string(cas::simplify(e)); }));
        if (cmd == "latex" && need(1)) return run(args[1], guarded([](Expr e) { return cas::to_latex(e); }));
        if (cmd == "cpp" && need(1)) return run(args[1], guarded([](Expr e) { return cas::to_cpp(e); }));
        if (cmd == "diff" && need(2)) {
            auto var = parse_variable(args[1]);
            if (!var) return 2;
            return run(args[2], guarded([v = *var](Expr e) { return cas::to_string(cas::diff(e, v)); }));
        }
        if (cmd == "eval" && args.size() >= 2)
            return cmd_eval(args[1], std::vector<std::string>(args.begin() + 2, args.end()));
        if (cmd == "euler-lagrange" && need(2)) return cmd_euler_lagrange(args[1], args[2]);
    } catch (const std::exception& ex) {
        std::cerr << "phynjo-cas: internal error: " << ex.what() << "\n";
        return 1;
    }
    if (cmd == "simplify" || cmd == "latex" || cmd == "cpp" || cmd == "diff" || cmd == "eval" ||
        cmd == "euler-lagrange")
        return usage_error("wrong number of arguments for '" + cmd + "'");
    return usage_error("unknown command '" + cmd + "'");
}
