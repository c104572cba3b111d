// The canonicalizing factories: every node is made here, in canonical form (see expr.hpp).
#include "number_ops.hpp"
#include "phynjo/cas/node_map.hpp"
#include "phynjo/cas/evaluate.hpp"

#include <boost/container/small_vector.hpp>

#include <algorithm>
#include <cmath>
#include <cassert>
#include <cstring>
#include <stdexcept>
#include <string>
#include <numeric>

namespace phynjo::cas {

using detail::as_span;
using detail::base_of;
using detail::make_int;
using detail::make_number;
using detail::NodeKey;
using detail::num_add;
using detail::num_mul;
using detail::pool;

std::string_view function_name(Function f) {
    switch (f) {
    case Function::Sin: return "sin";
    case Function::Cos: return "cos";
    case Function::Tan: return "tan";
    case Function::Exp: return "exp";
    case Function::Log: return "log";
    case Function::Asin: return "asin";
    case Function::Acos: return "acos";
    case Function::Atan: return "atan";
    case Function::Sinh: return "sinh";
    case Function::Cosh: return "cosh";
    case Function::Tanh: return "tanh";
    case Function::Abs: return "abs";
    case Function::Sign: return "sign";
    case Function::Atan2: return "atan2";
    }
    return "?";
}

std::size_t function_arity(Function f) { return f == Function::Atan2 ? 2 : 1; }

Expr::Expr(int v) : Expr(make_int(v)) {}
Expr::Expr(long v) : Expr(make_int(v)) {}
Expr::Expr(long long v) : Expr(make_int(v)) {}
Expr::Expr(const mpq_class& v) : Expr(make_number(v)) {}

bool Expr::is_integer() const noexcept { return kind() == Kind::Number && detail::num_is_integer(*this); }

Expr integer(long long v) { return make_int(v); }
Expr integer(const mpz_class& v) { return make_number(mpq_class(v)); }
Expr rational(long long p, long long q) {
    if (q == 0) throw DomainError("division by zero");
    mpq_class r{mpz_class(std::to_string(p)), mpz_class(std::to_string(q))};
    r.canonicalize();
    return make_number(r);
}
Expr number(const mpq_class& v) {
    mpq_class r = v;
    r.canonicalize();
    return make_number(r);
}

Expr pi() {
    auto& p = pool();
    if (p.pi.is_null()) {
        NodeKey k{Kind::Constant};
        k.sub = static_cast<std::uint8_t>(Constant::Pi);
        p.pi = Expr(p.intern(k));
    }
    return p.pi;
}

Expr symbol(std::string_view name) {
    if (name.empty()) throw Error("a symbol needs a name");
    NodeKey k{Kind::Symbol};
    k.name = name;
    return Expr(pool().intern(k));
}

Expr time_symbol() {
    auto& p = pool();
    if (p.time.is_null()) p.time = symbol("t");
    return p.time;
}

// ---- order ------------------------------------------------------------------------------

int compare(Expr a, Expr b) noexcept {
    if (a == b) return 0;
    if (a.hash() != b.hash()) return a.hash() < b.hash() ? -1 : 1;
    // Equal hashes of different structures: compare structurally (rare).
    if (a.kind() != b.kind()) return a.kind() < b.kind() ? -1 : 1;
    if (a->sub != b->sub) return a->sub < b->sub ? -1 : 1;
    switch (a.kind()) {
    case Kind::Number: return detail::num_cmp(a, b);
    case Kind::Symbol: return a->name.compare(b->name) < 0 ? -1 : 1;
    case Kind::Constant: return 0;
    case Kind::TimeDerivative:
    case Kind::Function:
    case Kind::Pow:
    case Kind::Mul:
    case Kind::Add: {
        if (a->nargs != b->nargs) return a->nargs < b->nargs ? -1 : 1;
        if (a->number != b->number) return compare(a->number, b->number);
        for (std::uint32_t i = 0; i < a->nargs; ++i)
            if (int c = compare(a.args()[i], b.args()[i])) return c;
        if (a.kind() == Kind::Add)
            for (std::uint32_t i = 0; i < a->nargs; ++i)
                if (int c = compare(a->coefs[i], b->coefs[i])) return c;
        return 0;
    }
    }
    return 0;
}

namespace {

bool less(Expr a, Expr b) noexcept { return compare(a, b) < 0; }

// The canonical-form invariants of expr.hpp (the ones tests/cas/test_canonical.cpp checks on
// random expressions), asserted on every node the factories make, in builds with assertions
// (Debug, and the sanitizer build, which compiles the CAS with them: SymEngine's habit).
#ifndef NDEBUG
void assert_canonical_mul(Expr coef, std::span<const Expr> factors) {
    assert(!coef.is_zero() && "Mul: a zero coefficient");
    assert((factors.size() >= 2 || !coef.is_one()) && "Mul: a lone factor with coefficient 1");
    for (std::size_t i = 0; i < factors.size(); ++i) {
        assert(factors[i].kind() != Kind::Number && factors[i].kind() != Kind::Mul && "Mul: a number or Mul factor");
        assert((i == 0 || compare(base_of(factors[i - 1]), base_of(factors[i])) < 0) &&
               "Mul: factors not sorted by base, or a base twice");
    }
}
void assert_canonical_add(std::span<const Expr> rests, std::span<const Expr> coefs) {
    assert(!rests.empty() && "Add: no terms");
    for (std::size_t i = 0; i < rests.size(); ++i) {
        assert(!coefs[i].is_zero() && "Add: a zero coefficient");
        assert(rests[i].kind() != Kind::Number && rests[i].kind() != Kind::Add && "Add: a number or Add term");
        assert((rests[i].kind() != Kind::Mul || rests[i]->number.is_one()) && "Add: a Mul term with its coefficient");
        assert((i == 0 || compare(rests[i - 1], rests[i]) < 0) && "Add: terms not sorted, or a term twice");
    }
}
void assert_canonical_pow(Expr b, Expr e) {
    assert(!e.is_zero() && !e.is_one() && !b.is_one() && "Pow: x^0, x^1 or 1^x");
    assert((b.kind() != Kind::Number || !e.is_integer()) && "Pow: a number to an integer power");
}
#endif

Expr make_mul_node(Expr coef, std::span<const Expr> factors) {
#ifndef NDEBUG
    assert_canonical_mul(coef, factors);
#endif
    NodeKey k{Kind::Mul};
    k.number = coef;
    k.args = factors;
    return Expr(pool().intern(k));
}

Expr make_add_node(Expr constant, std::span<const Expr> rests, std::span<const Expr> coefs) {
#ifndef NDEBUG
    assert(rests.size() == coefs.size() && !rests.empty());
    assert((rests.size() >= 2 || !constant.is_zero() || !coefs[0].is_one()) && "Add: a lone term x + 0");
    assert_canonical_add(rests, coefs);
#endif
    NodeKey k{Kind::Add};
    k.number = constant;
    k.args = rests;
    k.coefs = coefs;
    return Expr(pool().intern(k));
}

Expr make_pow_node(Expr b, Expr e) {
#ifndef NDEBUG
    assert_canonical_pow(b, e);
#endif
    const Expr args[2] = {b, e};
    NodeKey k{Kind::Pow};
    k.args = args;
    return Expr(pool().intern(k));
}

/// c·e for a Number c, canonical: distributes over an Add, merges into a Mul's coefficient.
Expr scale(Expr c, Expr e) {
    if (c.is_zero()) return c;
    if (c.is_one()) return e;
    switch (e.kind()) {
    case Kind::Number: return num_mul(c, e);
    case Kind::Mul: {
        const Expr k = num_mul(c, e->number);
        if (k.is_one() && e->nargs == 1) return e.args()[0];
        return make_mul_node(k, e.args());
    }
    case Kind::Add: {
        std::vector<Expr> coefs(e->nargs);
        for (std::uint32_t i = 0; i < e->nargs; ++i) coefs[i] = num_mul(c, e->coefs[i]);
        return make_add_node(num_mul(c, e->number), e.args(), coefs);
    }
    case Kind::Constant:
    case Kind::Symbol:
    case Kind::TimeDerivative:
    case Kind::Function:
    case Kind::Pow: {
        const Expr f[1] = {e};
        return make_mul_node(c, f);
    }
    }
    return e;
}

} // namespace

Expr detail::mul_sorted(Expr coef, std::span<const Expr> factors) {
    assert(coef.kind() == Kind::Number);
    if (factors.empty()) return coef;
    pool().charge(factors.size() + 1);
    if (coef.is_zero()) return coef;
    if (factors.size() == 1) return scale(coef, factors[0]);
    return make_mul_node(coef, factors);
}

Expr detail::times(Expr c, Expr x) {
    assert(c.kind() == Kind::Number);
    pool().charge(2);
    return scale(c, x);
}

namespace {

/// Splits a term into (coefficient, rest).
std::pair<Expr, Expr> split_term(Expr x) {
    if (x.kind() == Kind::Mul && !x->number.is_one()) {
        if (x->nargs == 1) return {x->number, x.args()[0]};
        return {x->number, make_mul_node(make_int(1), x.args())};
    }
    return {make_int(1), x};
}

/// A sum as content · primitive sum: the content is ±gcd(numerators)/lcm(denominators) of
/// its coefficients and constant, signed so that the primitive sum's first term (in the
/// canonical order) has a positive coefficient. Products keep only primitive sums as
/// factors; that is what makes mul associative while c·(a+b) still distributes.
std::pair<Expr, Expr> primitive_part(Expr s) {
    // fast path: integer coefficients that fit a machine word (the common case)
    {
        std::int64_t g = 0;
        bool small = true;
        auto take = [&](Expr c) {
            if (!c->small) small = false;
            else g = std::gcd(g, c->small_value < 0 ? -c->small_value : c->small_value);
        };
        for (std::uint32_t i = 0; i < s->nargs && small; ++i) take(s->coefs[i]);
        if (small && !s->number.is_zero()) take(s->number);
        if (small) {
            const bool negate = detail::num_sign(s->coefs[0]) < 0;
            if (g == 1 && !negate) return {make_int(1), s};
            const std::int64_t content = negate ? -g : g;
            std::vector<Expr> coefs(s->nargs);
            for (std::uint32_t i = 0; i < s->nargs; ++i) coefs[i] = make_int(s->coefs[i]->small_value / content);
            const Expr constant = make_int(s->number->small_value / content);
            return {make_int(content), make_add_node(constant, s.args(), coefs)};
        }
    }
    mpz_class g = 0, l = 1;
    auto take = [&](Expr c) {
        const mpq_class& v = c.value();
        mpz_gcd(g.get_mpz_t(), g.get_mpz_t(), v.get_num_mpz_t());
        mpz_lcm(l.get_mpz_t(), l.get_mpz_t(), v.get_den_mpz_t());
    };
    for (std::uint32_t i = 0; i < s->nargs; ++i) take(s->coefs[i]);
    if (!s->number.is_zero()) take(s->number);
    mpq_class content(g, l);
    content.canonicalize();
    if (detail::num_sign(s->coefs[0]) < 0) content = -content;
    if (content == 1) return {make_int(1), s};
    const Expr inv = make_number(1 / content);
    std::vector<Expr> coefs(s->nargs);
    for (std::uint32_t i = 0; i < s->nargs; ++i) coefs[i] = num_mul(inv, s->coefs[i]);
    return {make_number(content), make_add_node(num_mul(inv, s->number), s.args(), coefs)};
}

} // namespace

// ---- add ----------------------------------------------------------------------------------

Expr add(std::span<const Expr> xs) {
    if (xs.size() == 1) return xs[0];
    pool().charge(xs.size());
    const Expr one = make_int(1);
    Expr constant = make_int(0);
    boost::container::small_vector<std::pair<Expr, Expr>, 16> terms; // (rest, coefficient)
    terms.reserve(xs.size() + 4);
    for (Expr x : xs) {
        switch (x.kind()) {
        case Kind::Number: constant = num_add(constant, x); break;
        case Kind::Add:
            constant = num_add(constant, x->number);
            for (std::uint32_t i = 0; i < x->nargs; ++i) terms.emplace_back(x.args()[i], x->coefs[i]);
            break;
        case Kind::Mul: {
            auto [c, r] = split_term(x);
            terms.emplace_back(r, c);
            break;
        }
        case Kind::Constant:
        case Kind::Symbol:
        case Kind::TimeDerivative:
        case Kind::Function:
        case Kind::Pow: terms.emplace_back(x, one); break;
        }
    }
    std::sort(terms.begin(), terms.end(), [](const auto& a, const auto& b) { return less(a.first, b.first); });
    boost::container::small_vector<Expr, 16> rests, coefs;
    rests.reserve(terms.size());
    coefs.reserve(terms.size());
    for (std::size_t i = 0; i < terms.size();) {
        Expr r = terms[i].first, c = terms[i].second;
        std::size_t j = i + 1;
        for (; j < terms.size() && terms[j].first == r; ++j) c = num_add(c, terms[j].second);
        if (!c.is_zero()) {
            rests.push_back(r);
            coefs.push_back(c);
        }
        i = j;
    }
    if (rests.empty()) return constant;
    if (rests.size() == 1 && constant.is_zero()) return scale(coefs[0], rests[0]);
    return make_add_node(constant, as_span(rests), as_span(coefs));
}

Expr add(std::initializer_list<Expr> xs) { return add(std::span<const Expr>(xs.begin(), xs.size())); }

// ---- mul ----------------------------------------------------------------------------------

namespace {
struct Factor {
    Expr base, exp, original; // original: the factor as given (null after merging)
};
} // namespace

Expr mul(std::span<const Expr> xs) {
    if (xs.size() == 1) return xs[0];
    pool().charge(xs.size());
    const Expr one = make_int(1);
    Expr coef = one;
    boost::container::small_vector<Factor, 16> fs;
    fs.reserve(xs.size() + 4);
    auto push_factor = [&](Expr f) {
        if (f.kind() == Kind::Pow) fs.push_back({f.args()[0], f.args()[1], f});
        else if (f.kind() == Kind::Add) {
            auto [content, prim] = primitive_part(f);
            coef = num_mul(coef, content);
            fs.push_back({prim, one, prim});
        } else fs.push_back({f, one, f});
    };
    for (Expr x : xs) {
        switch (x.kind()) {
        case Kind::Number: coef = num_mul(coef, x); break;
        case Kind::Mul:
            coef = num_mul(coef, x->number);
            for (Expr f : x.args()) push_factor(f);
            break;
        case Kind::Constant:
        case Kind::Symbol:
        case Kind::TimeDerivative:
        case Kind::Function:
        case Kind::Pow:
        case Kind::Add: push_factor(x); break;
        }
    }
    if (coef.is_zero()) return coef;
    std::sort(fs.begin(), fs.end(), [](const Factor& a, const Factor& b) { return less(a.base, b.base); });
    boost::container::small_vector<Expr, 16> out;
    out.reserve(fs.size());
    bool reflatten = false;
    for (std::size_t i = 0; i < fs.size();) {
        std::size_t j = i + 1;
        while (j < fs.size() && fs[j].base == fs[i].base) ++j;
        Expr p;
        if (j == i + 1) p = fs[i].original; // a lone factor is already canonical
        else {
            boost::container::small_vector<Expr, 8> exps;
            exps.reserve(j - i);
            for (std::size_t k = i; k < j; ++k) exps.push_back(fs[k].exp);
            p = pow(fs[i].base, add(as_span(exps)));
        }
        switch (p.kind()) {
        case Kind::Number: coef = num_mul(coef, p); break;
        case Kind::Mul: reflatten = true; out.push_back(p); break;
        case Kind::Constant:
        case Kind::Symbol:
        case Kind::TimeDerivative:
        case Kind::Function:
        case Kind::Pow:
        case Kind::Add:
            if (base_of(p) != fs[i].base) reflatten = true;
            out.push_back(p);
            break;
        }
        i = j;
    }
    if (reflatten) {
        out.push_back(coef);
        return mul(as_span(out));
    }
    if (coef.is_zero()) return coef;
    if (out.empty()) return coef;
    if (out.size() == 1) return scale(coef, out[0]);
    return make_mul_node(coef, as_span(out));
}

Expr mul(std::initializer_list<Expr> xs) { return mul(std::span<const Expr>(xs.begin(), xs.size())); }

// ---- pow ----------------------------------------------------------------------------------

Expr pow(Expr b, Expr e) {
    if (e.kind() == Kind::Number) {
        if (e.is_zero()) return make_int(1);
        if (e.is_one()) return b;
        switch (b.kind()) {
        case Kind::Number: return detail::num_pow(b, e);
        case Kind::Pow:
            if (e.is_integer()) return pow(b.args()[0], mul({b.args()[1], e}));
            break;
        case Kind::Mul:
            if (e.is_integer()) {
                std::vector<Expr> fs;
                fs.reserve(b->nargs + 1);
                fs.push_back(detail::num_pow(b->number, e));
                for (Expr f : b.args()) fs.push_back(pow(f, e));
                return mul(fs);
            }
            break;
        case Kind::Add:
            if (e.is_integer()) {
                auto [content, prim] = primitive_part(b);
                if (!content.is_one()) return mul({detail::num_pow(content, e), make_pow_node(prim, e)});
            }
            break;
        case Kind::Constant:
        case Kind::Symbol:
        case Kind::TimeDerivative:
        case Kind::Function: break;
        }
        return make_pow_node(b, e);
    }
    if (b.is_one()) return b;
    return make_pow_node(b, e);
}

Expr sqrt(Expr x) { return pow(x, rational(1, 2)); }

// ---- functions ----------------------------------------------------------------------------

namespace {

Expr function_node(Function f, std::span<const Expr> args) {
    NodeKey k{Kind::Function};
    k.sub = static_cast<std::uint8_t>(f);
    k.args = args;
    return Expr(pool().intern(k));
}
Expr function_node(Function f, Expr x) { return function_node(f, std::span<const Expr>(&x, 1)); }

/// If x = c·pi for a rational c, c; otherwise null.
Expr pi_multiple(Expr x) {
    if (x == pi()) return make_int(1);
    if (x.kind() == Kind::Mul && x->nargs == 1 && x.args()[0] == pi()) return x->number;
    return Expr{};
}

/// True when x "looks negative": a negative number, or a Mul with a negative coefficient.
bool negative_form(Expr x) {
    if (x.kind() == Kind::Number) return detail::num_sign(x) < 0;
    if (x.kind() == Kind::Mul) return detail::num_sign(x->number) < 0;
    // a sum whose first term (in canonical order) has a negative coefficient: -x has the same
    // terms in the same order with every sign flipped, so exactly one of x and -x is negative
    // (sin(b - a) = -sin(a - b), cos(b - a) = cos(a - b), as SymPy writes them: sin and cos of
    // one argument, which the compiler turns into one sincos call)
    if (x.kind() == Kind::Add) return detail::num_sign(x->coefs[0]) < 0;
    return false;
}

/// f(g(u)) where g is an inverse trigonometric function and the composition an identity on
/// g's real domain: sin(asin u) = cos(acos u) = tan(atan u) = u, sin(acos u) = cos(asin u) =
/// √(1 − u²), tan(asin u) = u/√(1 − u²), tan(acos u) = √(1 − u²)/u, sin(atan u) = u/√(1 + u²),
/// cos(atan u) = 1/√(1 + u²). Null when x is no such function. (So `cos(th)` at th =
/// acos(g/(R w²)) is g/(R w²) and an exact equilibrium is seen as one.)
Expr of_inverse(Function f, Expr x) {
    if (x.kind() != Kind::Function) return Expr{};
    const auto g = static_cast<Function>(x->sub);
    if (g != Function::Asin && g != Function::Acos && g != Function::Atan) return Expr{};
    const Expr u = x.args()[0];
    const Expr one = make_int(1), half = rational(1, 2), minus_half = rational(-1, 2);
    const Expr u2 = pow(u, make_int(2));
    const Expr c = pow(add({one, mul({make_int(-1), u2})}), half); // √(1 − u²)
    if (g == Function::Atan) {
        const Expr r = pow(add({one, u2}), minus_half); // 1/√(1 + u²)
        switch (f) {
        case Function::Sin: return mul({u, r});
        case Function::Cos: return r;
        case Function::Tan: return u;
        default: return Expr{};
        }
    }
    const bool direct = (f == Function::Sin) == (g == Function::Asin); // sin∘asin, cos∘acos
    switch (f) {
    case Function::Sin:
    case Function::Cos: return direct ? u : c;
    case Function::Tan: return g == Function::Asin ? mul({u, pow(c, make_int(-1))}) : mul({c, pow(u, make_int(-1))});
    default: return Expr{};
    }
}

/// sin(c·pi) for rational c whose denominator is 1, 2, 3, 4 or 6; null otherwise.
Expr sin_pi(const mpq_class& c_in) {
    mpq_class c = c_in;
    // reduce to [0, 2)
    mpz_class fl;
    mpz_fdiv_q(fl.get_mpz_t(), c.get_num_mpz_t(), c.get_den_mpz_t());
    mpz_class two_k = fl - (fl % 2 + 2) % 2; // largest even integer ≤ c
    c -= mpq_class(two_k);
    const mpz_class& d = c.get_den();
    if (!(d == 1 || d == 2 || d == 3 || d == 4 || d == 6)) return Expr{};
    const bool upper = c >= 1; // sin negative in (pi, 2pi)
    if (upper) c -= 1;
    if (c > mpq_class(1, 2)) c = 1 - c; // sin(pi - x) = sin(x), now c in [0, 1/2]
    Expr v;
    if (c == 0) v = make_int(0);
    else if (c == mpq_class(1, 6)) v = rational(1, 2);
    else if (c == mpq_class(1, 4)) v = pow(make_int(2), rational(-1, 2));
    else if (c == mpq_class(1, 3)) v = mul({rational(1, 2), pow(make_int(3), rational(1, 2))});
    else v = make_int(1); // c == 1/2
    return upper ? mul({make_int(-1), v}) : v;
}

} // namespace

Expr sin(Expr x) {
    if (Expr v = of_inverse(Function::Sin, x); !v.is_null()) return v;
    if (x.is_zero()) return x;
    if (Expr c = pi_multiple(x); !c.is_null())
        if (Expr v = sin_pi(c.value()); !v.is_null()) return v;
    if (negative_form(x)) return mul({make_int(-1), sin(mul({make_int(-1), x}))});
    return function_node(Function::Sin, x);
}

Expr cos(Expr x) {
    if (Expr v = of_inverse(Function::Cos, x); !v.is_null()) return v;
    if (x.is_zero()) return make_int(1);
    if (Expr c = pi_multiple(x); !c.is_null())
        if (Expr v = sin_pi(c.value() + mpq_class(1, 2)); !v.is_null()) return v;
    if (negative_form(x)) return cos(mul({make_int(-1), x}));
    return function_node(Function::Cos, x);
}

Expr tan(Expr x) {
    if (Expr v = of_inverse(Function::Tan, x); !v.is_null()) return v;
    if (x.is_zero()) return x;
    if (Expr c = pi_multiple(x); !c.is_null()) {
        Expr s = sin_pi(c.value()), k = sin_pi(c.value() + mpq_class(1, 2));
        if (!s.is_null() && !k.is_null()) {
            if (k.is_zero()) throw DomainError("tan is undefined at odd multiples of pi/2");
            return mul({s, pow(k, make_int(-1))});
        }
    }
    if (negative_form(x)) return mul({make_int(-1), tan(mul({make_int(-1), x}))});
    return function_node(Function::Tan, x);
}

Expr exp(Expr x) {
    if (x.is_zero()) return make_int(1);
    if (x.kind() == Kind::Function && static_cast<Function>(x->sub) == Function::Log) return x.args()[0];
    if (x.kind() == Kind::Mul && x->nargs == 1 && x.args()[0].kind() == Kind::Function &&
        static_cast<Function>(x.args()[0]->sub) == Function::Log)
        return pow(x.args()[0].args()[0], x->number); // exp(c·log y) = y^c
    return function_node(Function::Exp, x);
}

Expr log(Expr x) {
    if (x.is_one()) return make_int(0);
    if (x.kind() == Kind::Number && detail::num_sign(x) <= 0)
        throw DomainError(x.is_zero() ? "log(0) is undefined" : "log of a negative number is undefined");
    if (x.kind() == Kind::Function && static_cast<Function>(x->sub) == Function::Exp) return x.args()[0];
    return function_node(Function::Log, x);
}

namespace {
bool is_function(Expr x, Function f) { return x.kind() == Kind::Function && static_cast<Function>(x->sub) == f; }
/// f(−x) = −f(x) for the odd functions: pulls the sign out of a negative-looking argument.
Expr odd(Function f, Expr x, Expr (*self)(Expr)) {
    if (negative_form(x)) return mul({make_int(-1), self(mul({make_int(-1), x}))});
    return function_node(f, x);
}
} // namespace

namespace {
/// The exact values of the inverse functions at the sines and tangents of the multiples of
/// π/6 and π/4: asin(x) = c·π for x = 1/2, √2/2, √3/2, 1 (c = 1/6, 1/4, 1/3, 1/2);
/// atan(x) = c·π for x = √3/3, 1, √3 (c = 1/6, 1/4, 1/3). The arguments are matched as
/// canonical expressions (one pointer compare each); the value c, or a zero c when none.
mpq_class asin_exact(Expr x) {
    const Expr half = rational(1, 2);
    if (x == half) return {1, 6};
    if (x == mul({half, sqrt(make_int(2))})) return {1, 4};
    if (x == mul({half, sqrt(make_int(3))})) return {1, 3};
    if (x.is_one()) return {1, 2};
    return 0;
}
mpq_class atan_exact(Expr x) {
    if (x == mul({rational(1, 3), sqrt(make_int(3))})) return {1, 6};
    if (x.is_one()) return {1, 4};
    if (x == sqrt(make_int(3))) return {1, 3};
    return 0;
}
} // namespace

Expr asin(Expr x) {
    if (x.is_zero()) return x;
    if (x.kind() == Kind::Number && abs(x.value()) > 1) throw DomainError("asin of a number outside [-1, 1] is undefined");
    if (const mpq_class c = asin_exact(x); c != 0) return mul({number(c), pi()});
    return odd(Function::Asin, x, &asin);
}

Expr acos(Expr x) {
    if (x.is_one()) return make_int(0);
    if (x.kind() == Kind::Number && abs(x.value()) > 1) throw DomainError("acos of a number outside [-1, 1] is undefined");
    if (x.is_zero()) return mul({rational(1, 2), pi()});
    // acos = π/2 − asin at the exact points; acos(−u) = π − acos(u)
    if (const mpq_class c = asin_exact(x); c != 0) return mul({number(mpq_class(1, 2) - c), pi()});
    if (negative_form(x))
        if (const mpq_class c = asin_exact(mul({make_int(-1), x})); c != 0) return mul({number(mpq_class(1, 2) + c), pi()});
    return function_node(Function::Acos, x);
}

Expr atan(Expr x) {
    if (x.is_zero()) return x;
    if (const mpq_class c = atan_exact(x); c != 0) return mul({number(c), pi()});
    return odd(Function::Atan, x, &atan);
}

Expr sinh(Expr x) {
    if (x.is_zero()) return x;
    return odd(Function::Sinh, x, &sinh);
}

Expr cosh(Expr x) {
    if (x.is_zero()) return make_int(1);
    if (negative_form(x)) return cosh(mul({make_int(-1), x}));
    return function_node(Function::Cosh, x);
}

Expr tanh(Expr x) {
    if (x.is_zero()) return x;
    return odd(Function::Tanh, x, &tanh);
}

Expr abs(Expr x) {
    if (x.kind() == Kind::Number) return detail::num_sign(x) < 0 ? mul({make_int(-1), x}) : x;
    if (x.kind() == Kind::Constant) return x; // π
    if (negative_form(x)) return abs(mul({make_int(-1), x}));
    if (is_function(x, Function::Abs)) return x;
    // abs(c·u) = c·abs(u) for a number c > 0
    if (x.kind() == Kind::Mul && !x->number.is_one()) return mul({x->number, abs(mul({pow(x->number, make_int(-1)), x}))});
    return function_node(Function::Abs, x);
}

Expr sign(Expr x) {
    if (x.kind() == Kind::Number) return make_int(detail::num_sign(x));
    if (x.kind() == Kind::Constant) return make_int(1);
    if (negative_form(x)) return mul({make_int(-1), sign(mul({make_int(-1), x}))});
    if (is_function(x, Function::Sign)) return x;
    if (x.kind() == Kind::Mul && !x->number.is_one()) return sign(mul({pow(x->number, make_int(-1)), x})); // sign(c·u), c > 0
    return function_node(Function::Sign, x);
}

namespace {
/// The sign of a constant (no symbol, no t: atom_mask 0): exact for a number, from its
/// double value otherwise when that is clearly away from 0; 2 when unknown.
int constant_sign(Expr c) {
    if (c.kind() == Kind::Number) return detail::num_sign(c);
    if (c->atom_mask != 0) return 2;
    double v = 0;
    try {
        v = evaluate(c, Bindings<double>{});
    } catch (const Error&) {
        return 2;
    }
    if (!std::isfinite(v) || std::fabs(v) < 1e-12) return 2;
    return v > 0 ? 1 : -1;
}
} // namespace

Expr atan2(Expr y, Expr x) {
    const int sy = constant_sign(y), sx = constant_sign(x);
    const bool yn = sy != 2, xn = sx != 2;
    if (sy == 0 && sx == 0) throw DomainError("atan2(0, 0) is undefined");
    if (sy == 0 && xn) return sx > 0 ? make_int(0) : pi(); // on the x axis, either side
    if (sx == 0 && yn) return sy > 0 ? mul({rational(1, 2), pi()}) : mul({rational(-1, 2), pi()});
    auto principal = [&] { return atan(mul({y, pow(x, make_int(-1))})); };
    if (sx == 1) return principal(); // x > 0: the principal branch
    if (yn && xn) return add({principal(), sy > 0 ? pi() : mul({make_int(-1), pi()})}); // x < 0: ± π by y's sign
    const Expr args[2] = {y, x};
    return function_node(Function::Atan2, args);
}

Expr function(Function f, std::span<const Expr> args) {
    if (args.size() != function_arity(f))
        throw std::invalid_argument(std::string(function_name(f)) + " takes " + std::to_string(function_arity(f)) +
                                    (function_arity(f) == 1 ? " argument" : " arguments"));
    if (f == Function::Atan2) return atan2(args[0], args[1]);
    return function(f, args[0]);
}

Expr function(Function f, Expr x) {
    switch (f) {
    case Function::Sin: return sin(x);
    case Function::Cos: return cos(x);
    case Function::Tan: return tan(x);
    case Function::Exp: return exp(x);
    case Function::Log: return log(x);
    case Function::Asin: return asin(x);
    case Function::Acos: return acos(x);
    case Function::Atan: return atan(x);
    case Function::Sinh: return sinh(x);
    case Function::Cosh: return cosh(x);
    case Function::Tanh: return tanh(x);
    case Function::Abs: return abs(x);
    case Function::Sign: return sign(x);
    case Function::Atan2: throw std::invalid_argument("atan2 takes 2 arguments");
    }
    return x;
}

// ---- operators -----------------------------------------------------------------------------

Expr operator+(Expr a, Expr b) { return add({a, b}); }
Expr operator-(Expr a, Expr b) { return add({a, mul({make_int(-1), b})}); }
Expr operator*(Expr a, Expr b) { return mul({a, b}); }
Expr operator/(Expr a, Expr b) { return mul({a, pow(b, make_int(-1))}); }
Expr operator-(Expr a) { return mul({make_int(-1), a}); }

// ---- inspection ----------------------------------------------------------------------------

std::string_view symbol_name(Expr e) noexcept {
    if (e.kind() == Kind::Symbol) return e->name;
    if (e.kind() == Kind::TimeDerivative) return e.args()[0]->name;
    return {};
}
int derivative_order(Expr e) noexcept { return e.kind() == Kind::TimeDerivative ? e->sub : 0; }

namespace {
void collect(Expr e, NodeSet& seen, std::vector<Expr>& stack) {
    stack.push_back(e);
    while (!stack.empty()) {
        Expr x = stack.back();
        stack.pop_back();
        if (!seen.insert(x)) continue;
        for (Expr a : x.args()) stack.push_back(a);
    }
}
} // namespace

std::size_t dag_size(std::span<const Expr> es) {
    NodeSet seen;
    std::vector<Expr> stack;
    for (Expr e : es) collect(e, seen, stack);
    return seen.size();
}
std::size_t dag_size(Expr e) { return dag_size(std::span<const Expr>(&e, 1)); }

std::size_t tree_size(Expr e) {
    NodeMap<std::size_t> memo;
    auto rec = [&](auto&& self, Expr x) -> std::size_t {
        if (x->nargs == 0) return 1;
        if (const std::size_t* m = memo.find(x)) return *m;
        std::size_t s = 1;
        auto sat_add = [](std::size_t a, std::size_t b) { return a > SIZE_MAX - b ? SIZE_MAX : a + b; };
        for (std::uint32_t i = 0; i < x->nargs; ++i) {
            s = sat_add(s, self(self, x.args()[i]));
            if (x.kind() == Kind::Add && !x->coefs[i].is_one()) s = sat_add(s, 1);
        }
        if (x.kind() == Kind::Add && !x->number.is_zero()) s = sat_add(s, 1);
        if (x.kind() == Kind::Mul && !x->number.is_one()) s = sat_add(s, 1);
        memo.try_emplace(x, s);
        return s;
    };
    return rec(rec, e);
}

} // namespace phynjo::cas
