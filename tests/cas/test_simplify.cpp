// simplify, expand, substitution: results, idempotence, and preserved values.
#include "expr_gen.hpp"
#include "property.hpp"

#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace phynjo::cas;
using phynjo::grammar::parse;
using phynjo::test::check_property;

// Catches: the angle-difference identities missing, applied with the wrong sign, to unequal
// coefficients or rests, or to squared factors.
TEST_CASE("simplify applies the angle-difference identities inside sums", "[cas][simplify]") {
    // Equal in value (evaluated independently) and as short as the identity's right side;
    // which way round the difference is written (cos(a - b) or cos(b - a)) is the CAS's choice.
    auto becomes = [](const char* in, const char* want) {
        const Expr got = simplify(parse(in)), w = parse(want);
        INFO(in << " -> " << to_string(got) << ", want " << want);
        for (double a : {0.3, -1.1})
            for (double b : {0.7, 2.2}) {
                Bindings<double> at{{symbol("a"), a}, {symbol("b"), b}, {symbol("m"), 1.3},
                                         {symbol("l"), 0.6}, {symbol("k"), 2.0}, {symbol("r"), 0.9}};
                CHECK(evaluate(got, at) == Approx(evaluate(w, at)).epsilon(1e-14));
            }
        CHECK(tree_size(got) <= tree_size(w) + 2);
    };
    becomes("cos(a)*cos(b) + sin(a)*sin(b)", "cos(a - b)");
    becomes("m*l*(cos(a)*cos(b) + sin(a)*sin(b)) + k", "m*l*cos(a - b) + k");
    becomes("3*r*sin(a)*cos(b) - 3*r*cos(a)*sin(b)", "3*r*sin(a - b)");
    becomes("sin(b)*cos(a) - sin(a)*cos(b)", "sin(b - a)");
    // not the identity: unequal coefficients, a sum of angles, squares
    CHECK(simplify(parse("cos(a)*cos(b) + 2*sin(a)*sin(b)")) == parse("cos(a)*cos(b) + 2*sin(a)*sin(b)"));
    CHECK(simplify(parse("cos(a)*cos(b) - sin(a)*sin(b)")) == parse("cos(a)*cos(b) - sin(a)*sin(b)"));
    CHECK(simplify(parse("cos(a)^2*cos(b) + sin(a)^2*sin(b)")) == parse("cos(a)^2*cos(b) + sin(a)^2*sin(b)"));
}

TEST_CASE("simplify applies sin^2 + cos^2 = 1 inside sums", "[cas][simplify]") {
    CHECK(simplify(parse("sin(x)^2 + cos(x)^2")) == Expr(1));
    CHECK(simplify(parse("(l*sin(x))^2 + (l*cos(x))^2")) == parse("l^2"));
    CHECK(simplify(parse("3*sin(2*x)^2 + 3*cos(2*x)^2 + y")) == parse("3 + y"));
    CHECK(simplify(parse("sin(x)^4 + sin(x)^2*cos(x)^2")) == parse("sin(x)^2"));
    CHECK(simplify(parse("(a*cos(q)*q')^2 + (a*sin(q)*q')^2")) == parse("a^2*q'^2"));
    CHECK(simplify(parse("(a+b)^2 - a^2 - 2*a*b - b^2")) == Expr(0));
    CHECK(simplify(parse("sin(x)^2 + 2*cos(x)^2")) == parse("sin(x)^2 + 2*cos(x)^2"));
    // the double pendulum's kinetic energy
    const Expr T = parse(
        "1/2*m1*((l1*cos(th1)*th1')^2 + (l1*sin(th1)*th1')^2) + "
        "1/2*m2*((l1*cos(th1)*th1' + l2*cos(th2)*th2')^2 + (l1*sin(th1)*th1' + l2*sin(th2)*th2')^2)");
    const Expr expected = parse("1/2*(m1+m2)*l1^2*th1'^2 + 1/2*m2*l2^2*th2'^2 + "
                                "m2*l1*l2*th1'*th2'*cos(th1 - th2)");
    CHECK(simplify(T - expected) == Expr(0));
    CHECK(expand(T - expected) != Expr(0)); // it is the identities that close the gap
}

TEST_CASE("expand", "[cas][simplify]") {
    CHECK(expand(parse("(x+y)^2")) == parse("x^2 + 2*x*y + y^2"));
    CHECK(expand(parse("(x+1)^3*(x-1)")) == parse("x^4 + 2*x^3 - 2*x - 1"));
    CHECK(expand(parse("sin((a+b)*c)")) == parse("sin(a*c + b*c)"));
    CHECK(expand(parse("(x+y)^(-2)")) == parse("(x+y)^(-2)"));
    CHECK_THROWS_AS(expand(parse("(a+b+c+d+e)^200")), LimitError);
}

namespace {
/// Value of e at a fixed point, or nothing where it is undefined.
std::optional<long double> value_at(Expr e) {
    Bindings<long double> at;
    long double v = 0.31L;
    for (Expr s : free_variables(e)) at[s] = (v += 0.17L);
    try {
        return evaluate_extended(e, at);
    } catch (const EvaluationError&) {
        return std::nullopt;
    }
}
} // namespace

TEST_CASE("simplify is idempotent and preserves values", "[cas][simplify]") {
    check_property("simplify(simplify(e)) == simplify(e)", [] {
        const Expr e = *phynjo::test::gen_expr(4);
        const Expr s = simplify(e);
        RC_ASSERT(simplify(s) == s);
    }, {.cases = 1000});
    check_property("simplify and expand keep the value", [] {
        const Expr e = *phynjo::test::gen_expr(3);
        const auto v = value_at(e);
        RC_PRE(v.has_value() && std::fabs(*v) < 1e6L);
        for (Expr r : {simplify(e), expand(e)}) {
            const auto w = value_at(r);
            RC_ASSERT(w.has_value());
            RC_ASSERT(std::fabs(*w - *v) <= 1e-9L * (1 + std::fabs(*v)));
        }
    }, {.cases = 1000});
}

TEST_CASE("substitution and free symbols", "[cas][simplify]") {
    const Expr x = symbol("x"), y = symbol("y");
    CHECK(subs(parse("x^2 + y"), {{x, y + 1}}) == parse("(y+1)^2 + y"));
    CHECK(subs(parse("sin(x)*x'"), {{velocity(x), Expr(3)}}) == parse("3*sin(x)"));
    CHECK(subs(parse("x'"), {{x, parse("y^2")}}) == parse("2*y*y'"));
    CHECK(subs(parse("sin(x+y) + x"), {{x + y, pi()}}) == x);
    const auto fs = free_symbols(parse("m*x'^2 + sin(theta)*t"));
    REQUIRE(fs.size() == 4);
    CHECK(to_string(fs[0]) == "m");
    CHECK(to_string(fs[1]) == "t");
    CHECK(to_string(fs[2]) == "theta");
    CHECK(to_string(fs[3]) == "x");
    const auto fv = free_variables(parse("x + x' + x''"));
    CHECK(fv.size() == 3);
    CHECK(contains(parse("sin(x*y) + 1"), x * y));
    CHECK_FALSE(contains(parse("sin(x*y) + 1"), parse("z")));
}

TEST_CASE("horner: common factors out of sums, same value, fewer operations", "[cas][simplify]") {
    CHECK(horner(parse("a*x + a*y + b*z")) == parse("a*(x + y) + b*z"));
    CHECK(horner(parse("-l*m1*c - l*m2*c - l*m3*c")) == parse("-l*c*(m1 + m2 + m3)"));
    CHECK(horner(parse("x^3 + 2*x^2 + 3*x + 4")) == parse("x*(x*(x + 2) + 3) + 4"));
    const Expr big = expand(parse("(a + b + c)^4"));
    CHECK(tree_size(horner(big)) < tree_size(big)); // 67 vs 90 nodes
    check_property("horner keeps the value", [] {
        const Expr e = expand(*phynjo::test::gen_expr(3));
        const auto v = value_at(e);
        RC_PRE(v.has_value() && std::fabs(*v) < 1e6L);
        const auto w = value_at(horner(e));
        RC_ASSERT(w.has_value());
        RC_ASSERT(std::fabs(*w - *v) <= 1e-9L * (1 + std::fabs(*v)));
    }, {.cases = 500});
}

// Catches: compositions of a trigonometric function with an inverse one left unsimplified (so
// an exact equilibrium at th = acos(...) is called "not an equilibrium"), or simplified with the
// wrong identity (sin(acos u) = u, a sign, 1 + u² for 1 − u²). The oracle: the values of both
// sides at points inside each inverse function's domain, computed by the C library.
TEST_CASE("trigonometric functions of inverse ones: the identities on the real domain", "[cas][simplify]") {
    CHECK(parse("cos(acos(u))") == parse("u"));
    CHECK(parse("sin(asin(u))") == parse("u"));
    CHECK(parse("tan(atan(u))") == parse("u"));
    CHECK(parse("cos(acos(g/(R*w^2)))") == parse("g/(R*w^2)"));
    CHECK(parse("sin(asin(-u))") == parse("-u"));
    const char* cases[][2] = {{"sin(acos(u))", "sqrt(1 - u^2)"},    {"cos(asin(u))", "sqrt(1 - u^2)"},
                              {"tan(asin(u))", "u/sqrt(1 - u^2)"},  {"tan(acos(u))", "sqrt(1 - u^2)/u"},
                              {"sin(atan(u))", "u/sqrt(1 + u^2)"},  {"cos(atan(u))", "1/sqrt(1 + u^2)"},
                              {"cos(acos(u))", "u"},                {"sin(asin(u))", "u"}};
    for (const auto& [in, want] : cases) {
        const Expr got = parse(in);
        INFO(in << " -> " << to_string(got));
        CHECK(got == parse(want));
        for (double u : {-0.9, -0.3, 0.2, 0.75}) {
            const Bindings<double> at{{symbol("u"), u}};
            const std::string f(in);
            const double inner = f.find("acos") != std::string::npos   ? std::acos(u)
                                 : f.find("asin") != std::string::npos ? std::asin(u)
                                                                       : std::atan(u);
            const double outer = f.rfind("sin", 0) == 0 ? std::sin(inner) : f.rfind("cos", 0) == 0 ? std::cos(inner) : std::tan(inner);
            CHECK(evaluate(got, at) == Approx(outer).epsilon(1e-14));
        }
    }
    // not identities: a multiple of the angle, an inverse function of another argument
    CHECK(to_string(parse("cos(2*acos(u))")) == "cos(2*acos(u))");
    CHECK(to_string(parse("sinh(asin(u))")) == "sinh(asin(u))");
}
