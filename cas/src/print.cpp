// The three printers share one skeleton: a sum prints its terms with signs pulled out, a
// product splits into numerator and denominator, and parentheses follow precedence.
#include "phynjo/cas/print.hpp"

#include "number_ops.hpp"
#include "phynjo/cas/errors.hpp"
#include "phynjo/cas/rational.hpp"

#include <boost/container/small_vector.hpp>

#include <algorithm>
#include <array>
#include <charconv>
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

/// Prints into one buffer: each pass appends its text and returns its precedence; a
/// subexpression that needs parentheses gets them around its text in place. (Building a
/// string per node and concatenating them cost phynjo-lagc a fifth of its time.)
class Printer {
public:
    Printer(Mode mode, const CppOptions* cpp, std::size_t max_chars = limits::max_printed_chars)
        : mode_(mode), cpp_(cpp), max_chars_(max_chars) {}

    /// The whole text of `x`.
    std::string run(Expr x) {
        print(x);
        return std::move(buf_);
    }

private:
    /// Appends x's text; its precedence.
    Prec print(Expr x) {
        const std::size_t start = buf_.size();
        const Prec p = print_node(x);
        // The result must fit the limit, and so must the work: a DAG printed as a tree builds
        // its shared parts again and again, so all text built by one call counts too (at
        // most 4× the limit), which keeps the time linear in the limit.
        const std::size_t n = buf_.size() - start;
        produced_ += n;
        if (n > max_chars_ || produced_ > 4 * max_chars_)
            throw LimitError("printed expression too long (more than " + std::to_string(max_chars_) + " characters)");
        return p;
    }
    /// x's text as a string of its own (for the rarer forms that rearrange their parts).
    Out sub(Expr x) {
        const std::size_t start = buf_.size();
        const Prec p = print(x);
        Out o{buf_.substr(start), p};
        buf_.resize(start);
        return o;
    }
    /// Appends a finished piece of text.
    Prec put(const Out& o) {
        buf_ += o.s;
        return o.p;
    }
    /// Parentheses around the text from `start` on when its precedence `p` is below `need`.
    void wrap_from(std::size_t start, Prec p, Prec need, bool latex = false) {
        if (static_cast<int>(p) >= static_cast<int>(need)) return;
        buf_.insert(start, latex ? "\\left(" : "(");
        buf_ += latex ? "\\right)" : ")";
    }

    Prec print_node(Expr x) {
        switch (x.kind()) {
        case Kind::Number: return number(x.value());
        case Kind::Constant:
            if (mode_ == Mode::Cpp) buf_ += "3.141592653589793";
            else buf_ += mode_ == Mode::Latex ? "\\pi" : "pi";
            return Prec::Atom;
        case Kind::Symbol:
        case Kind::TimeDerivative:
            if (mode_ == Mode::Cpp && cpp_ && cpp_->variable_table)
                if (const std::string* s = cpp_->variable_table->find(x)) {
                    buf_ += *s;
                    return Prec::Atom;
                }
            buf_ += variable(x);
            return Prec::Atom;
        case Kind::Function: return function(x);
        case Kind::Pow: {
            if (in_denominator(x)) {
                const Expr one[1] = {x};
                return product(Expr(1), one);
            }
            return power(x.args()[0], x.args()[1]);
        }
        case Kind::Mul: return product(x->number, x.args());
        case Kind::Add: return sum(x);
        }
        buf_ += "?";
        return Prec::Atom;
    }

    Mode mode_;
    const CppOptions* cpp_;
    std::size_t max_chars_;
    std::size_t produced_ = 0;
    std::string buf_;

    static std::string wrap(const Out& o, Prec need, bool latex = false) {
        if (static_cast<int>(o.p) >= static_cast<int>(need)) return o.s;
        return latex ? "\\left(" + o.s + "\\right)" : "(" + o.s + ")";
    }

    Prec number(const mpq_class& q) { return put(number_text(q)); }
    Out number_text(const mpq_class& q) {
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

    Prec function(Expr x) {
        const Function f = static_cast<Function>(x->sub);
        if (f == Function::Atan2) { // atan2(y, x)
            const Out y = sub(x.args()[0]), xx = sub(x.args()[1]);
            if (mode_ == Mode::Cpp) return put({math() + "atan2(" + y.s + ", " + xx.s + ")", Prec::Atom});
            if (mode_ == Mode::Latex) return put({latex_function(f) + "{\\left(" + y.s + ", " + xx.s + " \\right)}", Prec::Atom});
            return put({"atan2(" + y.s + ", " + xx.s + ")", Prec::Atom});
        }
        if (mode_ == Mode::Cpp && f != Function::Sign) { // the common case, appended in place
            buf_ += math();
            buf_ += f == Function::Abs ? std::string_view("fabs") : function_name(f);
            buf_ += '(';
            print(x.args()[0]);
            buf_ += ')';
            return Prec::Atom;
        }
        const Out a = sub(x.args()[0]);
        if (mode_ == Mode::Cpp) { // sign
            if (math() != "std::") return put({math() + "sign(" + a.s + ")", Prec::Atom});
            return put({"(" + a.s + " > 0 ? 1.0 : " + a.s + " < 0 ? -1.0 : 0.0)", Prec::Atom});
        }
        if (mode_ == Mode::Latex) {
            if (f == Function::Exp) return put({"e^{" + a.s + "}", Prec::Pow});
            if (f == Function::Abs) return put({"\\left|" + a.s + "\\right|", Prec::Atom});
            return put({latex_function(f) + "{\\left(" + a.s + " \\right)}", Prec::Atom});
        }
        return put({std::string(function_name(f)) + "(" + a.s + ")", Prec::Atom});
    }

    // b^e with e not a negative number.
    Prec power(Expr b, Expr e) {
        if (e == rational(1, 2)) {
            const Out a = sub(b);
            if (mode_ == Mode::Cpp) return put({math() + "sqrt(" + a.s + ")", Prec::Atom});
            if (mode_ == Mode::Latex) return put({"\\sqrt{" + a.s + "}", Prec::Atom});
            return put({"sqrt(" + a.s + ")", Prec::Atom});
        }
        if (mode_ == Mode::Cpp) {
            const std::size_t start = buf_.size();
            const Prec base = print(b);
            if (e.is_integer() && abs(e.value()) <= cpp_max_power()) {
                const long n = e.value().get_num().get_si();
                const bool simple = base == Prec::Atom;
                if (simple || n <= 3) {
                    wrap_from(start, base, Prec::Atom);
                    const std::size_t len = buf_.size() - start;
                    buf_.reserve(buf_.size() + static_cast<std::size_t>(n - 1) * (len + 1)); // no reallocation below
                    for (long k = 1; k < n; ++k) {
                        buf_ += '*';
                        buf_.append(buf_, start, len);
                    }
                    return n == 1 ? base : Prec::Mul;
                }
            }
            buf_.insert(start, math() + "pow(");
            buf_ += ", ";
            print(e);
            buf_ += ')';
            return Prec::Atom;
        }
        const Out base = sub(b);
        if (mode_ == Mode::Latex) {
            const Out ex = sub(e);
            if (b.kind() == Kind::Function && e.is_integer() && !is_fn(b, Function::Exp) && !is_fn(b, Function::Abs) &&
                !is_fn(b, Function::Atan2)) {
                // \sin^{2}{\left(x \right)}
                const std::string name = latex_function(static_cast<Function>(b->sub));
                return put({name + "^{" + ex.s + "}{\\left(" + sub(b.args()[0]).s + " \\right)}", Prec::Atom});
            }
            return put({wrap(base, Prec::Atom, true) + "^{" + ex.s + "}", Prec::Pow});
        }
        const Out ex = sub(e);
        // ^ is right associative: a power in the exponent needs no parentheses (x^y^z is
        // x^(y^z)), which keeps printed nesting no deeper than the parsed input
        return put({wrap(base, Prec::Atom) + "^" + wrap(ex, Prec::Pow), Prec::Pow});
    }

    int cpp_max_power() const { return cpp_ ? cpp_->max_multiply_power : 8; }
    std::string math() const { return cpp_ ? cpp_->math_prefix : std::string("std::"); }

    // Display order of factors: numbers, constants, variables, functions, sums; then text.
    static int rank(Expr f) {
        switch (detail::base_of(f).kind()) {
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
    static std::string key(Expr x) {
        std::string k;
        key_into(k, x, 0);
        return k;
    }
    static void key_into(std::string& k, Expr x, int depth) {
        switch (x.kind()) {
        case Kind::Number:
            if (x->small) {
                char buf[24];
                const auto r = std::to_chars(buf, buf + sizeof buf, x->small_value);
                k.append(buf, r.ptr);
            } else k += x.value().get_str();
            return;
        case Kind::Constant: k += "pi"; return;
        case Kind::Symbol: k += x->name; return;
        case Kind::TimeDerivative:
            k += symbol_name(x);
            k.append(static_cast<std::size_t>(x->sub), '\'');
            return;
        case Kind::Function:
            k += function_name(static_cast<Function>(x->sub));
            k += '(';
            if (depth < 2) key_into(k, x.args()[0], depth + 1);
            k += ')';
            return;
        case Kind::Pow:
            key_into(k, x.args()[0], depth + 1);
            k += '^';
            if (depth < 2) key_into(k, x.args()[1], depth + 1);
            return;
        case Kind::Mul: {
            if (depth >= 2) break;
            boost::container::small_vector<std::string, 8> parts(x->nargs);
            for (std::uint32_t i = 0; i < x->nargs; ++i) key_into(parts[i], x.args()[i], depth + 1);
            std::sort(parts.begin(), parts.end());
            for (std::size_t i = 0; i < parts.size(); ++i) {
                if (i) k += '*';
                k += parts[i];
            }
            return;
        }
        case Kind::Add: break;
        }
        char buf[24];
        std::snprintf(buf, sizeof buf, "~%016llx", static_cast<unsigned long long>(x.hash()));
        k += buf;
    }

    /// key(x) of the outermost call, memoized in the pool (a node's key never changes).
    static const std::string& top_key(Expr x) {
        auto& memo = detail::pool().print_keys;
        if (const std::string* k = memo.find(x)) return *k;
        return *memo.try_emplace(x, key(x)).first;
    }

    /// Factors in display order: (rank, key of the base), ties in canonical order.
    static boost::container::small_vector<Expr, 8> display_order(std::span<const Expr> fs) {
        boost::container::small_vector<Expr, 8> out(fs.begin(), fs.end());
        if (fs.size() < 2) return out;
        for (Expr f : fs) top_key(detail::base_of(f)); // every key in the memo first: no insertion below moves them
        boost::container::small_vector<std::pair<std::pair<int, const std::string*>, Expr>, 8> keyed;
        for (Expr f : fs) keyed.push_back({{rank(f), &top_key(detail::base_of(f))}, f});
        std::stable_sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) {
            if (x.first.first != y.first.first) return x.first.first < y.first.first;
            return *x.first.second < *y.first.second;
        });
        for (std::size_t i = 0; i < fs.size(); ++i) out[i] = keyed[i].second;
        return out;
    }

    /// The correctly rounded double literal of |c|, memoized in the pool.
    static const std::string& cpp_abs_literal(Expr c) {
        auto& memo = detail::pool().cpp_abs_literals;
        if (const std::string* s = memo.find(c)) return *s;
        return *memo.try_emplace(c, double_literal(to_double(abs(c.value())))).first;
    }

    static bool in_denominator(Expr f) {
        return f.kind() == Kind::Pow && f.args()[1].kind() == Kind::Number && detail::num_sign(f.args()[1]) < 0;
    }

    // c · Π factors, with factors of negative numeric exponent in a denominator:
    // [-]num*num/den or [-]num/(den*den) (\frac{num}{den} in LaTeX).
    Prec product(Expr c, std::span<const Expr> factors) {
        const bool neg = detail::num_sign(c) < 0;
        const bool unit = c->small && (c->small_value == 1 || c->small_value == -1);
        const bool latex = mode_ == Mode::Latex;
        const char* sep = latex ? " " : "*";
        std::string num_c, den_c; // |c| as the first numerator (and denominator) entry
        if (!unit) {
            if (mode_ == Mode::Cpp) num_c = cpp_abs_literal(c);
            else {
                const mpq_class a = abs(c.value());
                if (a.get_num() != 1) num_c = a.get_num().get_str();
                if (a.get_den() != 1) den_c = a.get_den().get_str();
            }
        }
        if (neg) buf_ += '-';
        if (unit && factors.size() == 1 && !in_denominator(factors[0])) {
            // ±1 times one factor: the factor's own form and precedence (x^2 stays a Pow)
            const Prec p = print(factors[0]);
            return neg ? Prec::Neg : p;
        }
        const auto order = display_order(factors);
        std::size_t n_den = den_c.empty() ? 0 : 1;
        for (Expr f : order) n_den += in_denominator(f) ? 1 : 0;
        const bool frac = latex && n_den > 0;
        if (frac) buf_ += "\\frac{";
        // the numerator
        bool any = !num_c.empty();
        buf_ += num_c;
        for (Expr f : order) {
            if (in_denominator(f)) continue;
            if (any) buf_ += sep;
            any = true;
            const std::size_t at = buf_.size();
            wrap_from(at, print(f), Prec::Mul, latex);
        }
        if (!any) buf_ += mode_ == Mode::Cpp ? "1.0" : "1";
        // the denominator
        if (n_den > 0) {
            const bool parens = !frac && n_den > 1;
            buf_ += frac ? "}{" : parens ? "/(" : "/";
            bool first = den_c.empty();
            buf_ += den_c;
            for (Expr f : order) {
                if (!in_denominator(f)) continue;
                if (!first) buf_ += sep;
                first = false;
                const std::size_t at = buf_.size();
                const Prec p = print(pow(f.args()[0], detail::num_neg(f.args()[1])));
                if (latex) wrap_from(at, p, Prec::Mul, true);
                else wrap_from(at, p, Prec::Pow);
            }
            if (frac) buf_ += "}";
            else if (parens) buf_ += ")";
        }
        if (neg) return Prec::Neg;
        return frac ? Prec::Atom : Prec::Mul;
    }

    Prec sum(Expr x) {
        // terms in display order, the constant last
        for (std::uint32_t i = 0; i < x->nargs; ++i) top_key(x.args()[i]); // all in the memo first (see display_order)
        std::vector<std::pair<const std::string*, std::size_t>> order;
        order.reserve(x->nargs);
        for (std::uint32_t i = 0; i < x->nargs; ++i) order.push_back({&top_key(x.args()[i]), i});
        std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
            if (*a.first != *b.first) return *a.first < *b.first;
            return a.second < b.second;
        });
        // readability: a positive term leads (sqrt(x) - exp(y), not -exp(y) + sqrt(x))
        auto positive = std::find_if(order.begin(), order.end(),
                                     [&](auto& o) { return detail::num_sign(x->coefs[o.second]) > 0; });
        if (positive != order.end()) std::rotate(order.begin(), positive, positive + 1);
        bool first = true;
        // a term appended after " + "; " + -" becomes " - "
        auto term = [&](auto&& print_term) {
            if (first) {
                print_term();
                first = false;
                return;
            }
            const std::size_t at = buf_.size();
            buf_ += " + ";
            const Prec p = print_term();
            if (p == Prec::Neg && buf_.size() > at + 3 && buf_[at + 3] == '-') buf_.replace(at, 4, " - ");
        };
        for (auto& [key, i] : order) {
            const Expr rest = x.args()[i], c = x->coefs[i];
            term([&] {
                if (rest.kind() == Kind::Mul) return product(c, rest.args());
                const Expr one[1] = {rest};
                return product(c, one);
            });
        }
        if (!x->number.is_zero()) term([&] { return number(x->number.value()); });
        return Prec::Add;
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

std::string to_string(Expr e) { return Printer(Mode::Infix, nullptr).run(e); }
std::string to_string(Expr e, std::size_t max_chars) { return Printer(Mode::Infix, nullptr, max_chars).run(e); }
std::string to_cpp(Expr e, const CppOptions& options) { return Printer(Mode::Cpp, &options).run(e); }
std::string to_latex(Expr e) { return Printer(Mode::Latex, nullptr).run(e); }

} // namespace phynjo::cas
