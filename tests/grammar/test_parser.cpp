// The expression grammar of docs/language.md: precedence, associativity, lexical rules.
#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

using namespace phynjo;
using cas::Expr;
using grammar::parse;

TEST_CASE("precedence and associativity", "[grammar]") {
    const Expr x = cas::symbol("x"), a = cas::symbol("a"), b = cas::symbol("b"), c = cas::symbol("c");
    CHECK(parse("-x^2") == -cas::pow(x, Expr(2)));
    CHECK(parse("2^3^2") == Expr(512));
    CHECK(parse("(2^3)^2") == Expr(64));
    CHECK(parse("2^-1") == cas::rational(1, 2));
    CHECK(parse("-2^2") == Expr(-4));
    CHECK(parse("a-b-c") == a - b - c);
    CHECK(parse("a-b-c") != a - (b - c));
    CHECK(parse("a/b/c") == a / (b * c));
    CHECK(parse("a/b*c") == a * c / b);
    CHECK(parse("a+b*c") == a + b * c);
    CHECK(parse("-a*b") == -(a * b));
    CHECK(parse("a*-b") == -(a * b));
    CHECK(parse("a - -b") == a + b);
    CHECK(parse("x'^2") == cas::pow(cas::velocity(x), Expr(2)));
    CHECK(parse("x''") == cas::velocity(cas::velocity(x)));
    CHECK(parse("sin(x)'") == cas::cos(x) * cas::velocity(x));
    CHECK(parse("(a*x)'") == cas::velocity(a) * x + a * cas::velocity(x));
}

TEST_CASE("names, built-ins and lexical rules", "[grammar]") {
    CHECK(parse("pi") == cas::pi());
    CHECK(parse("t") == cas::time_symbol());
    CHECK(parse("t'") == Expr(1));
    CHECK(parse("sqrt(x)") == cas::sqrt(cas::symbol("x")));
    CHECK(parse("_a1_b") == cas::symbol("_a1_b"));
    CHECK(parse("sinx") == cas::symbol("sinx"));
    CHECK(parse("  x  *  y  ") == cas::symbol("x") * cas::symbol("y"));
    CHECK(parse("(x +\n y)") == cas::symbol("x") + cas::symbol("y"));
    CHECK(parse("x # a comment") == cas::symbol("x"));
    CHECK(parse("\tx\t") == cas::symbol("x"));
    CHECK_THROWS_AS(parse("sin"), grammar::ParseError);
    CHECK_THROWS_AS(parse("x y"), grammar::ParseError);
    CHECK_THROWS_AS(parse("1/0"), grammar::ParseError);
    CHECK_THROWS_AS(parse(""), grammar::ParseError);
}

TEST_CASE("a custom resolver rejects unknown names and a derivative hook sees each prime", "[grammar]") {
    const std::string_view text = "a*b + c'";
    grammar::DiagnosticSink sink("model.lag", text);
    grammar::Positions positions(text);
    auto tree = grammar::parse_expression(text, positions, sink);
    REQUIRE(tree);
    grammar::ConvertOptions options;
    options.resolve = [](std::string_view n) -> std::optional<Expr> {
        if (n == "a" || n == "c") return cas::symbol(n);
        return std::nullopt;
    };
    int primes = 0;
    options.derivative = [&](Expr e, const grammar::ast::Postfix&, grammar::DiagnosticSink&,
                             const grammar::Positions&) -> std::optional<Expr> {
        ++primes;
        return cas::velocity(e);
    };
    CHECK_FALSE(grammar::to_expr(*tree, positions, sink, options));
    REQUIRE(sink.error_count() == 1);
    CHECK(sink.format_all() == "model.lag:1:3: error: unknown name 'b'\n    a*b + c'\n      ^\n");
}

TEST_CASE("hostile input gets a diagnostic, not a crash", "[grammar]") {
    const std::string deep_parens = std::string(5000, '(') + "x" + std::string(5000, ')');
    CHECK_THROWS_WITH(parse(deep_parens), Catch::Contains("nested deeper than 200 levels"));
    std::string tower = "x";
    for (int i = 0; i < 5000; ++i) tower += "^x";
    CHECK_THROWS_WITH(parse(tower), Catch::Contains("nested deeper than 200 levels"));
    std::string calls;
    for (int i = 0; i < 5000; ++i) calls += "sin(";
    calls += "x" + std::string(5000, ')');
    CHECK_THROWS_WITH(parse(calls), Catch::Contains("nested deeper than 200 levels"));
    CHECK_THROWS_WITH(parse("1e100000"), Catch::Contains("number too large"));
    CHECK_THROWS_WITH(parse(std::string(40000, '9')), Catch::Contains("number too large"));
    // every number the CAS holds prints to a literal that reads back (found by fuzzing:
    // 10^-10991 printed as a 10,992-digit denominator)
    const cas::Expr tiny = parse("e-1*m1/1e9992/1e999");
    CHECK(parse(cas::to_string(tiny)) == tiny);
    // a tower of 190 powers prints no deeper than it was written (found by fuzzing)
    std::string tower190 = "x";
    for (int i = 0; i < 190; ++i) tower190 += "^y" + std::to_string(i % 3);
    const cas::Expr t190 = parse(tower190);
    CHECK(parse(cas::to_string(t190)) == t190);
    const cas::Expr big = cas::pow(cas::Expr(2), cas::Expr(99990)); // just under 100,000 bits
    CHECK(parse(cas::to_string(big)) == big);
    CHECK_THROWS_WITH(parse("2^(10^9)"), Catch::Contains("exact power too large"));
    CHECK_THROWS_WITH(parse("x\xff"), Catch::Contains("not UTF-8"));
    CHECK_THROWS_WITH(parse(std::string("x\0y", 3)), Catch::Contains("control character 0x00"));
    // a long but shallow input is fine
    std::string sum = "x0";
    for (int i = 1; i < 20000; ++i) sum += " + x" + std::to_string(i);
    CHECK(parse(sum)->nargs == 20000);
    std::string negations(100000, '-');
    CHECK(parse(negations + "x") == cas::symbol("x"));
    Expr x16 = cas::symbol("x"); // the 16th time derivative, the highest order allowed
    for (int i = 0; i < 16; ++i) x16 = cas::velocity(x16);
    CHECK(parse("x" + std::string(16, '\'')) == x16);
    CHECK_THROWS_WITH(parse("x" + std::string(17, '\'')), Catch::Contains("order above 16"));
}
