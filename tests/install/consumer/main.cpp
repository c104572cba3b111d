#include <phynjo/cas/cas.hpp>
#include <phynjo/grammar/expression.hpp>

#include <iostream>

int main() {
    using namespace phynjo;
    const cas::Expr L = grammar::parse("1/2*m*l^2*theta'^2 + m*g*l*cos(theta)");
    const cas::Expr p = cas::diff(L, grammar::parse("theta'"));
    std::cout << cas::to_string(p) << "\n";
    return cas::to_string(p) == "l^2*m*theta'" ? 0 : 1;
}
