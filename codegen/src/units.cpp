// Dimensions of .lag expressions (units.hpp).
#include "units.hpp"

#include "phynjo/grammar/builtins.hpp"

#include <cctype>
#include <utility>

namespace phynjo::codegen::units {

namespace ast = grammar::ast;

namespace {

constexpr std::array<const char*, 7> kBase{"kg", "m", "s", "A", "K", "mol", "cd"};

Dim make(std::initializer_list<int> exps) {
    Dim d;
    std::size_t i = 0;
    for (int x : exps) d.e[i++] = x;
    return d;
}

/// The named units of docs/language.md *Units*, base first.
const std::array<std::pair<const char*, Dim>, 16>& named() {
    static const std::array<std::pair<const char*, Dim>, 16> table{{
        {"kg", make({1})}, {"m", make({0, 1})}, {"s", make({0, 0, 1})}, {"A", make({0, 0, 0, 1})},
        {"K", make({0, 0, 0, 0, 1})}, {"mol", make({0, 0, 0, 0, 0, 1})}, {"cd", make({0, 0, 0, 0, 0, 0, 1})},
        {"rad", make({})}, {"N", make({1, 1, -2})}, {"J", make({1, 2, -2})}, {"W", make({1, 2, -3})},
        {"Pa", make({1, -1, -2})}, {"Hz", make({0, 0, -1})}, {"C", make({0, 0, 1, 1})}, {"V", make({1, 2, -3, -1})},
        {"T", make({1, 0, -2, -1})},
    }};
    return table;
}

std::string power_text(const char* base, const mpq_class& k) {
    if (k == 1) return base;
    if (k.get_den() == 1) return std::string(base) + "^" + k.get_num().get_str();
    return std::string(base) + "^(" + k.get_str() + ")";
}

/// A decimal literal as written (`9.81`, `1e-3`, `2.`) as an exact rational.
std::optional<mpq_class> decimal(const std::string& text) {
    std::size_t i = 0;
    mpz_class digits = 0;
    long scale = 0;
    bool any = false;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) digits = digits * 10 + (text[i++] - '0'), any = true;
    if (i < text.size() && text[i] == '.') {
        ++i;
        while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])))
            digits = digits * 10 + (text[i++] - '0'), --scale, any = true;
    }
    if (!any) return std::nullopt;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        ++i;
        bool neg = false;
        if (i < text.size() && (text[i] == '+' || text[i] == '-')) neg = text[i++] == '-';
        long x = 0;
        while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) {
            x = x * 10 + (text[i++] - '0');
            if (x > 10000) return std::nullopt;
        }
        scale += neg ? -x : x;
    }
    if (i != text.size()) return std::nullopt;
    mpz_class ten = 1;
    mpz_pow_ui(ten.get_mpz_t(), mpz_class(10).get_mpz_t(), static_cast<unsigned long>(scale < 0 ? -scale : scale));
    mpq_class v = scale < 0 ? mpq_class(digits, ten) : mpq_class(digits * ten);
    v.canonicalize();
    return v;
}

std::optional<mpq_class> numeric(const ast::Product& p);

std::optional<mpq_class> numeric(const ast::Unary& u) {
    const ast::Postfix& base = u.power.base;
    if (!base.primes.empty()) return std::nullopt;
    std::optional<mpq_class> v;
    if (const auto* n = boost::get<ast::Number>(&base.primary)) v = decimal(n->text);
    else if (const auto* par = boost::get<ast::Paren>(&base.primary)) v = numeric_value(par->inner.get());
    if (!v) return std::nullopt;
    if (u.power.exponent) {
        const auto k = numeric(u.power.exponent->get());
        if (!k || k->get_den() != 1 || abs(*k) > 64 || (*v == 0 && *k < 0)) return std::nullopt;
        const long n = k->get_num().get_si();
        mpq_class r = 1;
        for (long j = 0; j < (n < 0 ? -n : n); ++j) r *= *v;
        v = n < 0 ? mpq_class(1 / r) : r;
    }
    if (u.signs.size() % 2) *v = -*v;
    return v;
}

std::optional<mpq_class> numeric(const ast::Product& p) {
    if (p.unit) return std::nullopt;
    auto v = numeric(p.first);
    for (const ast::ProductOp& op : p.rest) {
        if (!v) return std::nullopt;
        const auto w = numeric(op.operand);
        if (!w || (op.op == '/' && *w == 0)) return std::nullopt;
        *v = op.op == '*' ? mpq_class(*v * *w) : mpq_class(*v / *w);
    }
    return v;
}

/// True when the product is made of numbers only (a `[unit]` may follow it).
bool numbers_only(const ast::Product& p, bool with_unit = false);
bool numbers_only(const ast::Expression& e) {
    if (!numbers_only(e.first)) return false;
    for (const auto& op : e.rest)
        if (!numbers_only(op.operand)) return false;
    return true;
}
bool numbers_only(const ast::Unary& u) {
    const ast::Postfix& base = u.power.base;
    if (!base.primes.empty()) return false;
    bool ok = false;
    if (boost::get<ast::Number>(&base.primary)) ok = true;
    else if (const auto* par = boost::get<ast::Paren>(&base.primary)) ok = numbers_only(par->inner.get());
    return ok && (!u.power.exponent || numbers_only(u.power.exponent->get()));
}
bool numbers_only(const ast::Product& p, bool with_unit) {
    if ((p.unit && !with_unit) || !numbers_only(p.first)) return false;
    for (const auto& op : p.rest)
        if (!numbers_only(op.operand)) return false;
    return true;
}

} // namespace

bool Dim::dimensionless() const {
    for (const auto& x : e)
        if (x != 0) return false;
    return true;
}

Dim operator*(const Dim& a, const Dim& b) {
    Dim d;
    for (std::size_t i = 0; i < 7; ++i) d.e[i] = a.e[i] + b.e[i];
    d.any = a.any || b.any;
    return d;
}
Dim operator/(const Dim& a, const Dim& b) {
    Dim d;
    for (std::size_t i = 0; i < 7; ++i) d.e[i] = a.e[i] - b.e[i];
    d.any = a.any || b.any;
    return d;
}
Dim pow(const Dim& a, const mpq_class& k) {
    Dim d = a;
    for (auto& x : d.e) x *= k;
    return d;
}

std::string to_string(const Dim& d) {
    std::string num, den;
    int n_den = 0;
    for (std::size_t i = 0; i < 7; ++i) {
        if (d.e[i] > 0) num += (num.empty() ? "" : "*") + power_text(kBase[i], d.e[i]);
        if (d.e[i] < 0) {
            den += (den.empty() ? "" : "*") + power_text(kBase[i], -d.e[i]);
            ++n_den;
        }
    }
    if (num.empty() && den.empty()) return "1";
    if (num.empty()) num = "1";
    if (den.empty()) return num;
    return num + "/" + (n_den > 1 ? "(" + den + ")" : den);
}

std::string describe(const Dim& d) {
    for (std::size_t k = 8; k < named().size(); ++k) // the derived units
        if (named()[k].second == d) return std::string(named()[k].first) + " = " + to_string(d);
    return to_string(d);
}

Dim energy() { return make({1, 2, -2}); }
Dim power() { return make({1, 2, -3}); }
Dim seconds() { return make({0, 0, 1}); }
Dim metres() { return make({0, 1}); }

ParsedUnit parse_unit(std::string_view text) {
    ParsedUnit out;
    std::size_t i = 0;
    auto blank = [&] {
        while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    };
    auto fail = [&](std::size_t at, std::size_t len, std::string msg) {
        out.dim.reset();
        out.where = at;
        out.length = std::max<std::size_t>(len, 1);
        out.error = std::move(msg);
        return out;
    };
    Dim d;
    char op = '*';
    blank();
    if (i == text.size()) return fail(0, 1, "an empty unit");
    while (true) {
        blank();
        const std::size_t b = i;
        Dim f;
        if (i < text.size() && std::isalpha(static_cast<unsigned char>(text[i]))) {
            while (i < text.size() && std::isalpha(static_cast<unsigned char>(text[i]))) ++i;
            const std::string_view word = text.substr(b, i - b);
            bool found = false;
            for (const auto& [name, dim] : named())
                if (word == name) {
                    f = dim;
                    found = true;
                }
            if (!found)
                return fail(b, i - b, "unknown unit '" + std::string(word) +
                                          "' (units: kg m s A K mol cd rad, and N J W Pa Hz C V T)");
        } else if (i < text.size() && text[i] == '1') {
            ++i; // `1/s`
        } else
            return fail(b, 1, b < text.size() ? "expected a unit name, found '" + std::string(1, text[b]) + "'"
                                              : "expected a unit name after '" + std::string(1, op) + "'");
        blank();
        if (i < text.size() && text[i] == '^') {
            ++i;
            blank();
            const std::size_t e0 = i;
            bool neg = false;
            if (i < text.size() && text[i] == '-') neg = true, ++i;
            long k = 0;
            const std::size_t digits = i;
            while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) && k < 1000) k = k * 10 + (text[i++] - '0');
            if (i == digits) return fail(e0, 1, "expected a whole exponent after '^'");
            f = pow(f, mpq_class(neg ? -k : k));
        }
        d = op == '*' ? d * f : d / f;
        blank();
        if (i == text.size()) break;
        if (text[i] != '*' && text[i] != '/') return fail(i, 1, "expected '*', '/' or the end of the unit, found '" + std::string(1, text[i]) + "'");
        op = text[i++];
    }
    out.dim = d;
    return out;
}

std::optional<mpq_class> numeric_value(const ast::Expression& e) {
    auto v = numeric(e.first);
    for (const auto& op : e.rest) {
        if (!v) return std::nullopt;
        const auto w = numeric(op.operand);
        if (!w) return std::nullopt;
        *v = op.op == '+' ? mpq_class(*v + *w) : mpq_class(*v - *w);
    }
    return v;
}

void Checker::error(const boost::spirit::x3::position_tagged& node, const std::string& message) {
    const auto s = pos_.of(node);
    sink_.error(s.offset, s.length, message);
}

bool Checker::expect(const boost::spirit::x3::position_tagged& node, const Dim& found, const Dim& expected,
                     const std::string& what) {
    if (found.any || found == expected) return true;
    error(node, what + ": expected " + describe(expected) + ", found " + describe(found));
    return false;
}

std::optional<Dim> Checker::of(const ast::Unit& u) {
    const ParsedUnit p = parse_unit(u.text);
    if (!p.dim) {
        const auto s = pos_.of(u);
        sink_.error(s.offset + 1 + p.where, p.length, p.error); // +1: the '['
    }
    return p.dim;
}

std::optional<Dim> Checker::of(const ast::Expression& e) {
    auto d = of(e.first);
    for (const ast::SumOp& op : e.rest) {
        auto f = of(op.operand);
        if (!d || !f) return std::nullopt;
        if (d->any) {
            d = f;
            continue;
        }
        if (f->any || *f == *d) continue;
        error(op.operand, std::string("'") + op.op + "' joins terms of different dimensions: " + describe(*d) + " and " +
                              describe(*f));
        return std::nullopt;
    }
    return d;
}

std::optional<Dim> Checker::of(const ast::Product& p) {
    auto d = of(p.first);
    for (const ast::ProductOp& op : p.rest) {
        auto f = of(op.operand);
        if (!d || !f) return std::nullopt;
        d = op.op == '*' ? *d * *f : *d / *f;
    }
    if (p.unit) {
        if (!numbers_only(p, true)) {
            error(*p.unit, "a unit follows a number or a product of numbers (9.81 [m/s^2], 1/2 [N/m]), not an "
                           "expression with names (it has the dimension of its names)");
            return std::nullopt;
        }
        d = of(*p.unit); // a number with a unit, 0 included
        for (const ast::ProductOp& op : p.after) { // `0.5 [N]*x`: the quantity times the rest
            auto f = of(op.operand);
            if (!d || !f) return std::nullopt;
            d = op.op == '*' ? *d * *f : *d / *f;
        }
    }
    return d;
}

std::optional<Dim> Checker::of(const ast::Unary& u) { return of(u.power); }

std::optional<Dim> Checker::of(const ast::Power& p) {
    auto d = of(p.base);
    if (!p.exponent) return d;
    const ast::Unary& ex = p.exponent->get();
    auto de = of(ex);
    if (!d || !de) return std::nullopt;
    if (!de->any && !de->dimensionless()) {
        error(ex, "an exponent must be dimensionless, found " + describe(*de));
        return std::nullopt;
    }
    if (d->any || d->dimensionless()) return d;
    const auto k = numeric(ex);
    if (!k) {
        error(ex, "a power of a quantity with a dimension (" + describe(*d) + ") needs a number as exponent");
        return std::nullopt;
    }
    return pow(*d, *k);
}

std::optional<Dim> Checker::of(const ast::Postfix& p) {
    std::optional<Dim> d;
    if (const auto* n = boost::get<ast::Number>(&p.primary)) {
        d = Dim{};
        if (n->text.find_first_not_of("0.") == std::string::npos || n->text.find_first_of("123456789") == std::string::npos)
            d->any = true; // 0 fits every dimension
    } else if (const auto* name = boost::get<ast::Name>(&p.primary)) {
        if (name->text == "t") d = seconds();
        else if (name->text == "pi") d = Dim{};
        else {
            d = lookup_(name->text);
            if (!d) return std::nullopt;
        }
    } else if (const auto* par = boost::get<ast::Paren>(&p.primary)) {
        d = of(par->inner.get());
    } else if (const auto* call = boost::get<ast::Call>(&p.primary)) {
        d = of(*call);
    }
    if (!d) return std::nullopt;
    for (std::size_t k = 0; k < p.primes.size(); ++k) *d = *d / seconds();
    return d;
}

std::optional<Dim> Checker::of(const ast::Call& c) {
    const std::string& f = c.function.text;
    auto a = of(c.arg.get());
    std::optional<Dim> b;
    if (!c.more.empty()) b = of(c.more.front().get());
    if (!a || (!c.more.empty() && !b)) return std::nullopt;
    if (f == "sqrt") return a->any ? *a : pow(*a, mpq_class(1, 2));
    if (f == "abs") return a;
    if (f == "sign") return Dim{};
    if (f == "atan2") {
        if (b && !(a->any || b->any || *a == *b)) {
            error(c, "the arguments of atan2 differ in dimension: " + describe(*a) + " and " + describe(*b));
            return std::nullopt;
        }
        return Dim{};
    }
    if (!a->any && !a->dimensionless()) {
        error(c.arg.get(), "the argument of " + f + " must be dimensionless, found " + describe(*a));
        return std::nullopt;
    }
    return Dim{};
}

} // namespace phynjo::codegen::units
