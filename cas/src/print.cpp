// The three printers share one skeleton: a sum prints its terms with signs pulled out, a
// product splits into numerator and denominator, and parentheses follow precedence.
#include "phynjo/cas/print.hpp"

#include "number_ops.hpp"
#include "phynjo/cas/errors.hpp"
#include "phynjo/cas/rational.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

namespace phynjo::cas {

namespace {

enum class Prec : int { Add = 1, Mul = 2, Neg = 3, Pow = 4, Atom = 5 };
enum class Mode { Infix, Cpp, Latex };

struct Out {
    std::string s;
    Prec p = Prec::Atom;
};

bool is_fn(Expr x, Function f) { return x.kind() == Kind::Function && static_cast<Function>(x->sub) == f; }

class Printer {
public:
    Printer(Mode mode, const CppOptions* cpp, std::size_t max_chars = limits::max_printed_chars)
        : mode_(mode), cpp_(cpp), max_chars_(max_chars) {}

    Out print(Expr x) {
        Out o = print_node(x);
        // The result must fit the limit, and so must the work: a DAG printed as a tree builds
        // its shared parts again and again, so all text built by one call counts too (at
        // most 4× the limit), which keeps the time linear in the limit.
        produced_ += o.s.size();
        if (o.s.size() > max_chars_ || produced_ > 4 * max_chars_)
            throw LimitError("printed expression too long (more than " + std::to_string(max_chars_) + " characters)");
        return o;
    }

private:
    Out print_node(Expr x) {
        switch (x.kind()) {
        case Kind::Number: return number(x.value());
        case Kind::Constant:
            if (mode_ == Mode::Cpp) return {"3.141592653589793", Prec::Atom};
            return {mode_ == Mode::Latex ? "\\pi" : "pi", Prec::Atom};
        case Kind::Symbol:
        case Kind::TimeDerivative: return {variable(x), Prec::Atom};
        case Kind::Function: return function(x);
        case Kind::Pow: {
            const Expr e = x.args()[1];
            if (e.kind() == Kind::Number && detail::num_sign(e) < 0) {
                const Expr one[1] = {x};
                return product(Expr(1), one);
            }
            return power(x.args()[0], e);
        }
        case Kind::Mul: return product(x->number, x.args());
        case Kind::Add: return sum(x);
        }
        return {"?", Prec::Atom};
    }

    Mode mode_;
    const CppOptions* cpp_;
    std::size_t max_chars_;
    std::size_t produced_ = 0;

    static std::string wrap(const Out& o, Prec need, bool latex = false) {
        if (static_cast<int>(o.p) >= static_cast<int>(need)) return o.s;
        return latex ? "\\left(" + o.s + "\\right)" : "(" + o.s + ")";
    }

    Out number(const mpq_class& q) {
        const bool neg = sgn(q) < 0;
        if (mode_ == Mode::Cpp) {
            std::string s = double_literal(to_double(q));
            return {s, neg ? Prec::Neg : Prec::Atom};
        }
        const mpq_class a = abs(q);
        std::string s;
        if (a.get_den() == 1) s = a.get_num().get_str();
        else if (mode_ == Mode::Latex) s = "\\frac{" + a.get_num().get_str() + "}{" + a.get_den().get_str() + "}";
        else s = a.get_num().get_str() + "/" + a.get_den().get_str();
        const Prec p = a.get_den() == 1 || mode_ == Mode::Latex ? Prec::Atom : Prec::Mul;
        if (neg) return {"-" + s, Prec::Neg};
        return {s, p};
    }

    std::string variable(Expr x) {
        if (mode_ == Mode::Cpp) return cpp_ && cpp_->variable_name ? cpp_->variable_name(x) : default_cpp_name(x);
        if (mode_ == Mode::Latex) return latex_variable(x);
        std::string s(symbol_name(x));
        s.append(static_cast<std::size_t>(derivative_order(x)), '\'');
        return s;
    }

    /// A name as LaTeX: its base (Greek letter names, and th and ph, as Greek letters; one
    /// letter as is; longer names upright) and its subscript (trailing digits, or what follows
    /// a '_'): th1 → \theta, 1; q_2 → q, 2; omega → \omega.
    static std::pair<std::string, std::string> latex_parts(std::string_view name) {
        static constexpr std::array<std::string_view, 35> greek = {
            "alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta", "theta", "iota", "kappa", "lambda",
            "mu", "nu", "xi", "rho", "sigma", "tau", "upsilon", "phi", "chi", "psi", "omega", "Gamma",
            "Delta", "Theta", "Lambda", "Xi", "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega", "varphi", "vartheta"};
        std::size_t cut = name.size();
        while (cut > 1 && (std::isdigit(static_cast<unsigned char>(name[cut - 1])))) --cut;
        std::string_view base = name.substr(0, cut), sub = name.substr(cut);
        if (!sub.empty() && base.size() > 1 && base.back() == '_') base.remove_suffix(1); // q_2
        if (auto u = base.find('_'); u != std::string_view::npos && u > 0 && sub.empty()) {
            sub = base.substr(u + 1);
            base = base.substr(0, u);
        }
        if (base == "th") base = "theta";
        else if (base == "ph") base = "phi";
        std::string b;
        if (std::find(greek.begin(), greek.end(), base) != greek.end()) b = "\\" + std::string(base);
        else if (base.size() == 1) b = std::string(base);
        else b = "\\mathrm{" + escape(base) + "}";
        return {b, sub.empty() ? std::string() : "_{" + escape(sub) + "}"};
    }
    static std::string latex_name(std::string_view name) {
        const auto [b, sub] = latex_parts(name);
        return b + sub;
    }
    static std::string escape(std::string_view s) {
        std::string r;
        for (char c : s) {
            if (c == '_') r += "\\_";
            else r += c;
        }
        return r;
    }
    static std::string latex_variable(Expr x) {
        const auto [n, sub] = latex_parts(symbol_name(x)); // the dot goes on the letter: \dot{\theta}_{1}
        switch (derivative_order(x)) {
        case 0: return n + sub;
        case 1: return "\\dot{" + n + "}" + sub;
        case 2: return "\\ddot{" + n + "}" + sub;
        case 3: return "\\dddot{" + n + "}" + sub;
        default: return n + sub + "^{(" + std::to_string(derivative_order(x)) + ")}";
        }
    }

    /// The LaTeX command of a function: \sin, \arcsin, \operatorname{sign}.
    static std::string latex_function(Function f) {
        switch (f) {
        case Function::Asin: return "\\arcsin";
        case Function::Acos: return "\\arccos";
        case Function::Atan: return "\\arctan";
        case Function::Sign: return "\\operatorname{sign}";
        case Function::Abs: return "\\operatorname{abs}";
        case Function::Atan2: return "\\operatorname{atan2}";
        default: return "\\" + std::string(function_name(f));
        }
    }

    Out function(Expr x) {
        const Function f = static_cast<Function>(x->sub);
        if (f == Function::Atan2) { // atan2(y, x)
            const Out y = print(x.args()[0]), xx = print(x.args()[1]);
            if (mode_ == Mode::Cpp) return {math() + "atan2(" + y.s + ", " + xx.s + ")", Prec::Atom};
            if (mode_ == Mode::Latex) return {latex_function(f) + "{\\left(" + y.s + ", " + xx.s + " \\right)}", Prec::Atom};
            return {"atan2(" + y.s + ", " + xx.s + ")", Prec::Atom};
        }
        Out a = print(x.args()[0]);
        if (mode_ == Mode::Cpp) {
            if (f == Function::Sign) {
                if (math() != "std::") return {math() + "sign(" + a.s + ")", Prec::Atom};
                return {"(" + a.s + " > 0 ? 1.0 : " + a.s + " < 0 ? -1.0 : 0.0)", Prec::Atom};
            }
            return {math() + std::string(f == Function::Abs ? "fabs" : function_name(f)) + "(" + a.s + ")", Prec::Atom};
        }
        if (mode_ == Mode::Latex) {
            if (f == Function::Exp) return {"e^{" + a.s + "}", Prec::Pow};
            if (f == Function::Abs) return {"\\left|" + a.s + "\\right|", Prec::Atom};
            return {latex_function(f) + "{\\left(" + a.s + " \\right)}", Prec::Atom};
        }
        return {std::string(function_name(f)) + "(" + a.s + ")", Prec::Atom};
    }

    // b^e with e not a negative number.
    Out power(Expr b, Expr e) {
        if (e == rational(1, 2)) {
            Out a = print(b);
            if (mode_ == Mode::Cpp) return {math() + "sqrt(" + a.s + ")", Prec::Atom};
            if (mode_ == Mode::Latex) return {"\\sqrt{" + a.s + "}", Prec::Atom};
            return {"sqrt(" + a.s + ")", Prec::Atom};
        }
        Out base = print(b);
        if (mode_ == Mode::Cpp) {
            if (e.is_integer() && abs(e.value()) <= cpp_max_power()) {
                const long n = e.value().get_num().get_si();
                const bool simple = base.p == Prec::Atom;
                if (simple || n <= 3) {
                    std::string s = wrap(base, Prec::Atom);
                    std::string r = s;
                    for (long k = 1; k < n; ++k) r += "*" + s;
                    return {r, n == 1 ? base.p : Prec::Mul};
                }
            }
            return {math() + "pow(" + base.s + ", " + print(e).s + ")", Prec::Atom};
        }
        if (mode_ == Mode::Latex) {
            Out ex = print(e);
            if (b.kind() == Kind::Function && e.is_integer() && !is_fn(b, Function::Exp) && !is_fn(b, Function::Abs) &&
                !is_fn(b, Function::Atan2)) {
                // \sin^{2}{\left(x \right)}
                const std::string name = latex_function(static_cast<Function>(b->sub));
                return {name + "^{" + ex.s + "}{\\left(" + print(b.args()[0]).s + " \\right)}", Prec::Atom};
            }
            return {wrap(base, Prec::Atom, true) + "^{" + ex.s + "}", Prec::Pow};
        }
        Out ex = print(e);
        // ^ is right associative: a power in the exponent needs no parentheses (x^y^z is
        // x^(y^z)), which keeps printed nesting no deeper than the parsed input
        return {wrap(base, Prec::Atom) + "^" + wrap(ex, Prec::Pow), Prec::Pow};
    }

    int cpp_max_power() const { return cpp_ ? cpp_->max_multiply_power : 8; }
    std::string math() const { return cpp_ ? cpp_->math_prefix : std::string("std::"); }

    // Display order of factors: numbers, constants, variables, functions, sums; then text.
    static int rank(Expr f) {
        Expr b = f.kind() == Kind::Pow ? f.args()[0] : f;
        switch (b.kind()) {
        case Kind::Number: return 0;
        case Kind::Constant: return 1;
        case Kind::Symbol:
        case Kind::TimeDerivative: return 2;
        case Kind::Function: return 3;
        case Kind::Pow:
        case Kind::Mul: return 4;
        case Kind::Add: return 5;
        }
        return 6;
    }
    /// A short key for the display order, computed without printing subtrees: names for
    /// variables, the function name and its argument's key for functions, the structural
    /// hash for anything deeper (deterministic, cheap).
    static std::string key(Expr x, int depth = 0) {
        switch (x.kind()) {
        case Kind::Number: return x.value().get_str();
        case Kind::Constant: return "pi";
        case Kind::Symbol: return std::string(x->name);
        case Kind::TimeDerivative: return std::string(symbol_name(x)) + std::string(static_cast<std::size_t>(x->sub), '\'');
        case Kind::Function:
            return std::string(function_name(static_cast<Function>(x->sub))) + "(" + (depth < 2 ? key(x.args()[0], depth + 1) : "") + ")";
        case Kind::Pow: return key(x.args()[0], depth + 1) + "^" + (depth < 2 ? key(x.args()[1], depth + 1) : "");
        case Kind::Mul: {
            if (depth >= 2) break;
            std::vector<std::string> parts;
            for (Expr f : x.args()) parts.push_back(key(f, depth + 1));
            std::sort(parts.begin(), parts.end());
            std::string s;
            for (const auto& p : parts) s += (s.empty() ? "" : "*") + p;
            return s;
        }
        case Kind::Add: break;
        }
        char buf[24];
        std::snprintf(buf, sizeof buf, "~%016llx", static_cast<unsigned long long>(x.hash()));
        return buf;
    }

    std::vector<Expr> display_order(std::span<const Expr> fs) {
        std::vector<std::pair<std::pair<int, std::string>, Expr>> keyed;
        for (Expr f : fs) {
            const Expr b = f.kind() == Kind::Pow ? f.args()[0] : f; // key on the base
            keyed.push_back({{rank(f), key(b)}, f});
        }
        std::stable_sort(keyed.begin(), keyed.end(), [](auto& a, auto& b) { return a.first < b.first; });
        std::vector<Expr> out;
        for (auto& k : keyed) out.push_back(k.second);
        return out;
    }

    // c · Π factors, with factors of negative numeric exponent in a denominator.
    Out product(Expr c, std::span<const Expr> factors) {
        const bool neg = detail::num_sign(c) < 0;
        const mpq_class a = abs(c.value());
        std::vector<std::string> num, den;
        const std::string sep = mode_ == Mode::Latex ? " " : "*";
        const bool latex = mode_ == Mode::Latex;
        if (mode_ == Mode::Cpp) {
            if (a != 1) num.push_back(double_literal(to_double(a)));
        } else {
            if (a.get_num() != 1) num.push_back(a.get_num().get_str());
            if (a.get_den() != 1) den.push_back(a.get_den().get_str());
        }
        Out lone; // the printed form of a single numerator factor (printed once only)
        for (Expr f : display_order(factors)) {
            if (f.kind() == Kind::Pow && f.args()[1].kind() == Kind::Number && detail::num_sign(f.args()[1]) < 0) {
                Out o = print(pow(f.args()[0], detail::num_neg(f.args()[1])));
                den.push_back(latex ? wrap(o, Prec::Mul, true) : wrap(o, Prec::Pow));
            } else {
                Out o = print(f);
                num.push_back(wrap(o, Prec::Mul, latex));
                lone = std::move(o);
            }
        }
        auto join = [&](const std::vector<std::string>& v) {
            std::string s;
            for (std::size_t i = 0; i < v.size(); ++i) {
                if (i) s += sep;
                s += v[i];
            }
            return s;
        };
        std::string s;
        Prec p = Prec::Mul;
        if (latex && !den.empty()) {
            s = "\\frac{" + (num.empty() ? std::string("1") : join(num)) + "}{" + join(den) + "}";
            p = Prec::Atom;
        } else {
            s = num.empty() ? (mode_ == Mode::Cpp ? "1.0" : "1") : join(num);
            if (!den.empty()) {
                s += "/";
                s += den.size() == 1 ? den[0] : "(" + join(den) + ")";
            }
        }
        if (num.size() == 1 && den.empty() && factors.size() == 1 && a == 1) {
            // c = ±1 times one factor: the factor's own form and precedence (x^2 stays a Pow)
            s = std::move(lone.s);
            p = lone.p;
        }
        if (neg) return {"-" + s, Prec::Neg};
        return {s, p};
    }

    Out sum(Expr x) {
        // terms in display order, the constant last
        std::vector<std::pair<std::string, std::size_t>> order;
        for (std::uint32_t i = 0; i < x->nargs; ++i) order.push_back({key(x.args()[i]), i});
        std::stable_sort(order.begin(), order.end());
        // readability: a positive term leads (sqrt(x) - exp(y), not -exp(y) + sqrt(x))
        auto positive = std::find_if(order.begin(), order.end(),
                                     [&](auto& o) { return detail::num_sign(x->coefs[o.second]) > 0; });
        if (positive != order.end()) std::rotate(order.begin(), positive, positive + 1);
        std::string s;
        bool first = true;
        auto emit = [&](Out o) {
            const bool neg = o.p == Prec::Neg && !o.s.empty() && o.s[0] == '-';
            if (first) s = o.s;
            else if (neg) s += " - " + o.s.substr(1);
            else s += " + " + o.s;
            first = false;
        };
        for (auto& [key, i] : order) {
            const Expr rest = x.args()[i], c = x->coefs[i];
            if (rest.kind() == Kind::Mul) emit(product(c, rest.args()));
            else {
                const Expr one[1] = {rest};
                emit(product(c, one));
            }
        }
        if (!x->number.is_zero()) emit(number(x->number.value()));
        return {s, Prec::Add};
    }
};

} // namespace

std::string default_cpp_name(Expr v) {
    std::string s(symbol_name(v));
    switch (derivative_order(v)) {
    case 0: return s;
    case 1: return s + "_dot";
    case 2: return s + "_ddot";
    default: return s + "_d" + std::to_string(derivative_order(v));
    }
}

std::string to_string(Expr e) { return Printer(Mode::Infix, nullptr).print(e).s; }
std::string to_string(Expr e, std::size_t max_chars) { return Printer(Mode::Infix, nullptr, max_chars).print(e).s; }
std::string to_cpp(Expr e, const CppOptions& options) { return Printer(Mode::Cpp, &options).print(e).s; }
std::string to_latex(Expr e) { return Printer(Mode::Latex, nullptr).print(e).s; }

} // namespace phynjo::cas
