// Derived equations of motion against closed forms from the textbook (Goldstein, Taylor).
#include "phynjo/cas/cas.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"
#include "phynjo/grammar/expression.hpp"

#include "compiled_model.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace phynjo;
using cas::Expr;

namespace {

codegen::EquationsOfMotion eom_of(std::string_view text) { return test::compile_model(text).eom; }

/// e1 − e2 evaluated at random points is 0 (to 1e-12 relative): equal as functions.
bool same_function(Expr a, Expr b) {
    std::mt19937_64 rng(99);
    std::uniform_real_distribution<double> u(0.3, 1.7);
    for (int trial = 0; trial < 5; ++trial) {
        cas::Bindings<double> at;
        for (Expr v : cas::free_variables(a)) at[v] = u(rng);
        for (Expr v : cas::free_variables(b))
            if (!at.count(v)) at[v] = u(rng);
        const double x = cas::evaluate(a, at), y = cas::evaluate(b, at);
        if (std::fabs(x - y) > 1e-12 * (1 + std::fabs(x))) return false;
    }
    return true;
}

Expr P(const char* s) { return grammar::parse(s); }

} // namespace

TEST_CASE("pendulum: M = m l², f = −m g l sin θ, E = T + V", "[codegen][derive]") {
    const auto e = eom_of("coordinates th\nparameters m = 1, l = 1, g = 9.81\n"
                          "lagrangian 1/2*m*l^2*th'^2 + m*g*l*cos(th)\n");
    CHECK(e.mass_matrix[0] == P("m*l^2"));
    CHECK(e.forcing[0] == P("-m*g*l*sin(th)"));
    CHECK(e.momenta[0] == P("m*l^2*th'"));
    CHECK(e.energy == P("1/2*m*l^2*th'^2 - m*g*l*cos(th)"));
}

TEST_CASE("double pendulum from Cartesian positions", "[codegen][derive]") {
    const auto e = eom_of("coordinates th1, th2\nparameters m1 = 1, m2 = 1, l1 = 1, l2 = 1, g = 9.81\n"
                          "let x1 = l1*sin(th1)\nlet y1 = -l1*cos(th1)\nlet x2 = x1 + l2*sin(th2)\n"
                          "let y2 = y1 - l2*cos(th2)\n"
                          "lagrangian 1/2*m1*(x1'^2 + y1'^2) + 1/2*m2*(x2'^2 + y2'^2) - g*(m1*y1 + m2*y2)\n");
    CHECK(e.mass_matrix[0] == cas::expand(P("(m1 + m2)*l1^2")));
    CHECK(same_function(e.mass_matrix[1], P("m2*l1*l2*cos(th1 - th2)")));
    CHECK(e.mass_matrix[1] == e.mass_matrix[2]);
    CHECK(e.mass_matrix[3] == P("m2*l2^2"));
    CHECK(same_function(e.forcing[0], P("-m2*l1*l2*th2'^2*sin(th1 - th2) - (m1 + m2)*g*l1*sin(th1)")));
    CHECK(same_function(e.forcing[1], P("m2*l1*l2*th1'^2*sin(th1 - th2) - m2*g*l2*sin(th2)")));
}

TEST_CASE("spring pendulum in polar coordinates", "[codegen][derive]") {
    const auto e = eom_of("coordinates r, th\nparameters m = 1, k = 40, l0 = 1, g = 9.81\n"
                          "let x = r*sin(th)\nlet y = -r*cos(th)\n"
                          "lagrangian 1/2*m*(x'^2 + y'^2) - 1/2*k*(r - l0)^2 - m*g*y\n");
    CHECK(e.mass_matrix[0] == P("m"));
    CHECK(e.mass_matrix[1] == Expr(0));
    CHECK(e.mass_matrix[3] == P("m*r^2"));
    CHECK(same_function(e.forcing[0], P("m*r*th'^2 - k*(r - l0) + m*g*cos(th)")));
    CHECK(same_function(e.forcing[1], P("-2*m*r*r'*th' - m*g*r*sin(th)")));
}

TEST_CASE("dissipation, generalized forces and explicit time", "[codegen][derive]") {
    // damped, driven oscillator: m x'' = −k x − b x' + F0 cos(w t)
    const auto e = eom_of("coordinates x\nparameters m = 2, k = 3, b = 0.5, F0 = 1, w = 2\n"
                          "lagrangian 1/2*m*x'^2 - 1/2*k*x^2\ndissipation 1/2*b*x'^2\nforce x = F0*cos(w*t)\n");
    CHECK(e.mass_matrix[0] == P("m"));
    CHECK(e.forcing[0] == P("-k*x - b*x' + F0*cos(w*t)"));
    CHECK(e.generalized_forces[0] == P("-k*x - b*x' + F0*cos(w*t)"));
    // a mass that grows with time: d/dt((1+t) q') = (1+t) q'' + q'
    const auto g = eom_of("coordinates q\nlagrangian 1/2*(1 + t)*q'^2 + q*cos(t)\n");
    CHECK(g.mass_matrix[0] == P("1 + t"));
    CHECK(g.forcing[0] == P("cos(t) - q'"));
    // E' of a let name is its total time derivative; parameters are constant
    const auto h = eom_of("coordinates q\nparameters a = 3\nlet z = a*q^2\nlagrangian 1/2*z'^2\n");
    CHECK(h.mass_matrix[0] == P("4*a^2*q^2"));
    CHECK(h.forcing[0] == P("-4*a^2*q*q'^2"));
}

TEST_CASE("cyclic coordinates and energy function", "[codegen][derive]") {
    // free particle in a rotating frame: L = 1/2 m ((x' − w y)² + (y' + w x)²)
    const auto e = eom_of("coordinates x, y\nparameters m = 1, w = 0.5\n"
                          "lagrangian 1/2*m*((x' - w*y)^2 + (y' + w*x)^2)\n");
    CHECK(same_function(e.forcing[0], P("2*m*w*y' + m*w^2*x")));  // Coriolis + centrifugal
    CHECK(same_function(e.forcing[1], P("-2*m*w*x' + m*w^2*y")));
    CHECK(same_function(e.energy, P("1/2*m*(x'^2 + y'^2) - 1/2*m*w^2*(x^2 + y^2)"))); // Jacobi integral
}
