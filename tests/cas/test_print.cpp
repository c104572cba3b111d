// The printers: readable infix in the input syntax, C++ and LaTeX.
#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

using namespace phynjo::cas;
using phynjo::grammar::parse;

TEST_CASE("infix printing", "[cas][print]") {
    CHECK(to_string(parse("1/2*m*l^2*theta'^2 + m*g*l*cos(theta)")) == "g*l*m*cos(theta) + l^2*m*theta'^2/2");
    CHECK(to_string(parse("x - 3*y")) == "x - 3*y");
    CHECK(to_string(parse("-x^2")) == "-x^2");
    CHECK(to_string(parse("x/(2*y)")) == "x/(2*y)");
    CHECK(to_string(parse("(x+y)^2/z")) == "(x + y)^2/z");
    CHECK(to_string(parse("x^(-2)")) == "1/x^2");
    CHECK(to_string(parse("x^(1/2)")) == "sqrt(x)");
    CHECK(to_string(parse("x^y^z")) == "x^y^z");
    CHECK(to_string(parse("x^(-y)")) == "x^(-y)");
    CHECK(to_string(parse("(x^y)^z")) == "(x^y)^z");
    CHECK(to_string(parse("(-2)^x")) == "(-2)^x");
    CHECK(to_string(parse("(1/2)^x")) == "(1/2)^x");
    CHECK(to_string(parse("x''")) == "x''");
    CHECK(to_string(parse("9.81")) == "981/100");
    CHECK(to_string(parse("-1/3")) == "-1/3");
    CHECK(to_string(parse("2*pi*t")) == "2*pi*t");
    CHECK(to_string(parse("-(x+y)*z")) == "-z*(x + y)");
}

TEST_CASE("C++ printing", "[cas][print]") {
    CHECK(to_cpp(parse("x^3")) == "x*x*x");
    CHECK(to_cpp(parse("x^-2")) == "1.0/(x*x)");
    CHECK(to_cpp(parse("9.81*sin(x)")) == "9.81*std::sin(x)");
    CHECK(to_cpp(parse("x/3")) == "0.3333333333333333*x");
    CHECK(to_cpp(parse("sqrt(x) + exp(y)")) == "std::exp(y) + std::sqrt(x)"); // alphabetical
    CHECK(to_cpp(parse("x^20")) == "std::pow(x, 20.0)");
    CHECK(to_cpp(parse("x^y")) == "std::pow(x, y)");
    CHECK(to_cpp(parse("q'*q''")) == "q_dot*q_ddot");
    CHECK(to_cpp(parse("pi")) == "3.141592653589793");
    CppOptions o;
    o.variable_name = [](Expr v) { return "s[" + std::string(symbol_name(v)) + "]"; };
    CHECK(to_cpp(parse("x*y"), o) == "s[x]*s[y]");
}

TEST_CASE("LaTeX printing", "[cas][print]") {
    CHECK(to_latex(parse("1/2*m*l^2*theta'^2")) == "\\frac{l^{2} m \\dot{\\theta}^{2}}{2}");
    CHECK(to_latex(parse("sin(th1)^2")) == "\\sin^{2}{\\left(\\theta_{1} \\right)}");
    // Greek names (and th, ph) as letters, digits and what follows '_' as subscripts, the dot
    // on the letter (catches \mathrm{th}, q\_ and dots over subscripts)
    CHECK(to_latex(parse("th2'")) == "\\dot{\\theta}_{2}");
    CHECK(to_latex(parse("ph'' + omega3")) == "\\omega_{3} + \\ddot{\\phi}");
    CHECK(to_latex(parse("q_2'")) == "\\dot{q}_{2}");
    CHECK(to_latex(parse("Omega")) == "\\Omega");
    CHECK(to_latex(parse("x''")) == "\\ddot{x}");
    CHECK(to_latex(parse("sqrt(x) - exp(y)")) == "\\sqrt{x} - e^{y}");
    CHECK(to_latex(parse("m_cart*pi")) == "\\pi m_{cart}");
}

TEST_CASE("printing has a documented length limit", "[cas][print]") {
    // a DAG printed as a tree doubles at every level: 2^30 leaves from 30 nodes
    Expr e = symbol("x");
    for (int k = 0; k < 30; ++k) e = sin(e) + cos(e);
    CHECK(dag_size(e) < 100);
    CHECK_THROWS_AS(to_string(e, 100'000), LimitError);
    CHECK_THROWS_WITH(to_string(e, 1000), "printed expression too long (more than 1000 characters)");
    CHECK(to_string(sin(symbol("x")), 1000) == "sin(x)");
}
