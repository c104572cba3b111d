// From the syntax tree to exact CAS expressions. Every failure is reported at the source
// range of the node where it happened.
#include "phynjo/cas/diff.hpp"
#include "phynjo/cas/errors.hpp"
#include "phynjo/cas/rational.hpp"
#include "phynjo/grammar/builtins.hpp"
#include "phynjo/grammar/expression.hpp"

#include <array>

namespace phynjo::grammar {

namespace {

using cas::Expr;
using Opt = std::optional<Expr>;

class Converter {
public:
    Converter(const Positions& positions, DiagnosticSink& sink, const ConvertOptions& options)
        : positions_(positions), sink_(sink), options_(options) {}

    Opt expression(const ast::Expression& e) {
        std::vector<Expr> terms;
        Opt first = product(e.first);
        if (!first) return std::nullopt;
        terms.push_back(*first);
        for (const ast::SumOp& op : e.rest) {
            Opt t = product(op.operand);
            if (!t) return std::nullopt;
            terms.push_back(op.op == '-' ? guarded(op, [&] { return -*t; }) : *t);
            if (failed_) return std::nullopt;
        }
        return guarded(e, [&] { return cas::add(terms); });
    }

private:
    const Positions& positions_;
    DiagnosticSink& sink_;
    const ConvertOptions& options_;
    bool failed_ = false;

    void error(const boost::spirit::x3::position_tagged& node, std::string message) {
        const auto span = positions_.of(node);
        sink_.error(span.offset, span.length, std::move(message));
        failed_ = true;
    }

    /// Runs a CAS factory; a mathematical error is reported at `node`.
    template <typename F>
    Expr guarded(const boost::spirit::x3::position_tagged& node, F&& f) {
        try {
            return f();
        } catch (const cas::Error& ex) {
            error(node, ex.what());
            return Expr(0);
        }
    }

    Opt product(const ast::Product& p) {
        Opt first = unary(p.first);
        if (!first) return std::nullopt;
        std::vector<Expr> factors{*first};
        for (const auto* ops : {&p.rest, &p.after})
            for (const ast::ProductOp& op : *ops) {
                Opt u = unary(op.operand);
                if (!u) return std::nullopt;
                if (op.op == '/') {
                    if (u->is_zero()) {
                        error(op.operand, "division by zero");
                        return std::nullopt;
                    }
                    factors.push_back(guarded(op.operand, [&] { return cas::pow(*u, Expr(-1)); }));
                } else factors.push_back(*u);
                if (failed_) return std::nullopt;
            }
        Expr r = guarded(p, [&] { return cas::mul(factors); });
        return failed_ ? Opt{} : Opt{r};
    }

    Opt unary(const ast::Unary& u) {
        Opt x = power(u.power);
        if (!x) return std::nullopt;
        if (u.signs.size() % 2 == 0) return x;
        Expr r = guarded(u, [&] { return -*x; });
        return failed_ ? Opt{} : Opt{r};
    }

    Opt power(const ast::Power& p) {
        Opt b = postfix(p.base);
        if (!b) return std::nullopt;
        if (!p.exponent) return b;
        Opt e = unary(p.exponent->get());
        if (!e) return std::nullopt;
        Expr r = guarded(p, [&] { return cas::pow(*b, *e); });
        return failed_ ? Opt{} : Opt{r};
    }

    Opt postfix(const ast::Postfix& p) {
        Opt x = primary(p.primary);
        if (!x) return std::nullopt;
        for (std::size_t k = 0; k < p.primes.size(); ++k) {
            if (options_.derivative) {
                x = options_.derivative(*x, p, sink_, positions_);
                if (!x) {
                    failed_ = true;
                    return std::nullopt;
                }
            } else {
                Expr r = guarded(p, [&] { return cas::time_derivative(*x); });
                if (failed_) return std::nullopt;
                x = r;
            }
        }
        return x;
    }

    Opt primary(const ast::Primary& p) {
        struct Visitor {
            Converter& c;
            Opt operator()(const ast::Number& n) const { return c.number(n); }
            Opt operator()(const ast::Name& n) const { return c.name(n); }
            Opt operator()(const ast::Call& call) const { return c.call(call); }
            Opt operator()(const ast::Paren& paren) const { return c.expression(paren.inner.get()); }
        };
        return boost::apply_visitor(Visitor{*this}, p);
    }

    Opt number(const ast::Number& n) {
        auto q = cas::parse_decimal(n.text);
        if (!q) {
            error(n, "number too large (at most 31000 significant digits, a decimal exponent within ±31000 and 100000 bits)");
            return std::nullopt;
        }
        return cas::number(*q);
    }

    Opt name(const ast::Name& n) {
        if (n.text == "pi") return cas::pi();         // the two builtin_constants
        if (n.text == "t") return cas::time_symbol();
        if (find_builtin_function(n.text)) {
            error(n, "'" + n.text + "' is a function: write " + n.text + "(…)");
            return std::nullopt;
        }
        if (!options_.resolve) return cas::symbol(n.text);
        Opt r = options_.resolve(n.text);
        if (!r) error(n, "unknown name '" + n.text + "'");
        return r;
    }

    Opt call(const ast::Call& c) {
        const BuiltinFunction* f = find_builtin_function(c.function.text);
        if (!f) {
            if (is_builtin(c.function.text) ||
                (options_.resolve && options_.resolve(c.function.text)))
                error(c.function, "'" + c.function.text + "' is not a function (missing '*'?)");
            else if (!options_.resolve)
                error(c.function, "unknown function '" + c.function.text + "' (functions: " + builtin_function_list() +
                                      "; missing '*'?)");
            else error(c.function, "unknown function '" + c.function.text + "'");
            return std::nullopt;
        }
        const std::size_t given = 1 + c.more.size();
        if (given != f->arity()) {
            error(c, "'" + c.function.text + "' takes " + (f->arity() == 1 ? std::string("one argument") : "two arguments") +
                         (f->arity() == 2 ? " (" + c.function.text + "(y, x))" : std::string()) + ", not " +
                         std::to_string(given));
            return std::nullopt;
        }
        Opt a = expression(c.arg.get());
        if (!a) return std::nullopt;
        Opt b;
        if (f->arity() == 2) {
            b = expression(c.more[0].get());
            if (!b) return std::nullopt;
        }
        Expr r = guarded(c, [&] { return f->arity() == 2 ? f->apply2(*a, *b) : f->apply(*a); });
        return failed_ ? Opt{} : Opt{r};
    }
};

} // namespace

std::optional<cas::Expr> to_expr(const ast::Expression& tree, const Positions& positions, DiagnosticSink& sink,
                                 const ConvertOptions& options) {
    return Converter(positions, sink, options).expression(tree);
}

cas::Expr parse(std::string_view text, std::string_view source_name) {
    DiagnosticSink sink(std::string(source_name), text);
    Positions positions(text);
    auto tree = parse_expression(text, positions, sink);
    if (tree)
        if (auto e = to_expr(*tree, positions, sink)) return *e;
    throw ParseError(sink.format_all());
}

} // namespace phynjo::grammar
