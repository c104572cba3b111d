// phynjo-lagc --emit=linear: the linearization about a state, exact, against closed forms
// (the cart-pole's textbook A and B, the pendulum's eigenvalues) and against central
// differences of the accelerations away from equilibrium (constrained models too).
#include "phynjo/cas/cas.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"
#include "phynjo/codegen/linearize.hpp"
#include "phynjo/grammar/expression.hpp"

#include "compiled_model.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <fstream>
#include <iterator>

using namespace phynjo;
using cas::Expr;

namespace {

using test::Compiled;

Compiled compile(std::string_view text) { return test::compile_model(text); }

std::string file(const std::string& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

codegen::Linearization at(const Compiled& c, std::vector<std::pair<std::string, std::string>> state) {
    std::vector<std::pair<std::string, Expr>> s;
    for (const auto& [name, value] : state) s.emplace_back(name, grammar::parse(value));
    return codegen::linearize(c.model, c.eom, s);
}

/// a − b expands to 0: equal as rational functions (after expansion).
bool same(Expr a, const char* b) { return cas::simplify(cas::expand(a - grammar::parse(b))).is_zero(); }

/// The accelerations of the (constrained) model at a numeric state, from M, f, G, γ
/// evaluated by the CAS and the saddle-point system solved by Eigen.
Eigen::VectorXd accelerations(const Compiled& c, const std::vector<double>& y) {
    const std::size_t n = c.eom.dof, m = c.eom.n_constraints;
    cas::Bindings<double> b;
    const auto q = c.model.coordinate_symbols();
    for (std::size_t i = 0; i < n; ++i) {
        b[q[i]] = y[i];
        b[cas::velocity(q[i])] = y[n + i];
    }
    for (const auto& p : c.model.parameters) b[p.symbol] = p.default_value;
    b[cas::time_symbol()] = 0;
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n + m), static_cast<Eigen::Index>(n + m));
    Eigen::VectorXd r(static_cast<Eigen::Index>(n + m));
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j) K(i, j) = cas::evaluate(c.eom.mass_matrix[i * n + j], b);
        r(i) = cas::evaluate(c.eom.forcing[i], b);
    }
    for (std::size_t k = 0; k < m; ++k) {
        for (std::size_t j = 0; j < n; ++j) {
            const double g = cas::evaluate(c.eom.constraint_matrix[k * n + j], b);
            K(n + k, j) = g;
            K(j, n + k) = -g;
        }
        r(n + k) = cas::evaluate(c.eom.gamma[k], b);
    }
    return K.fullPivLu().solve(r).head(static_cast<Eigen::Index>(n));
}

/// The largest difference between A (evaluated at the defaults) and central differences.
double against_differences(const Compiled& c, const codegen::Linearization& lin) {
    const std::size_t n = c.eom.dof, N = 2 * n;
    cas::Bindings<double> defaults;
    for (const auto& p : c.model.parameters) defaults[p.symbol] = p.default_value;
    std::vector<double> y0(N);
    for (std::size_t i = 0; i < N; ++i) y0[i] = cas::evaluate(lin.state[i], defaults);
    double worst = 0;
    for (std::size_t j = 0; j < N; ++j) {
        const double h = 1e-5;
        auto yp = y0, ym = y0;
        yp[j] += h;
        ym[j] -= h;
        const Eigen::VectorXd d = (accelerations(c, yp) - accelerations(c, ym)) / (2 * h);
        for (std::size_t i = 0; i < n; ++i)
            worst = std::max(worst, std::fabs(cas::evaluate(lin.A[(n + i) * N + j], defaults) - d(static_cast<Eigen::Index>(i))));
        for (std::size_t i = 0; i < n; ++i)
            worst = std::max(worst, std::fabs(cas::evaluate(lin.A[i * N + j], defaults) - (j == n + i ? 1.0 : 0.0)));
    }
    return worst;
}

} // namespace

// Bugs caught: a wrong sign or a missing term in the symbolic solve (the adjugate's
// cofactor signs, a transposed cofactor), inputs not at their defaults, B's rows swapped.
TEST_CASE("linearization: the inverted cart-pole's textbook A and B, in closed form", "[codegen][linearize]") {
    const Compiled c = compile(file(PHYNJO_TEST_MODELS "/cart_pole_input.lag"));
    const auto lin = at(c, {{"th", "pi"}});
    REQUIRE(lin.A.size() == 16);
    REQUIRE(lin.B.size() == 4);
    for (Expr r : lin.rate) CHECK(r.is_zero()); // an equilibrium with F at its default 0
    const char* A[16] = {"0", "0", "1", "0", "0", "0", "0", "1", "0", "m*g/M", "0", "0", "0", "(M + m)*g/(M*l)", "0", "0"};
    for (int k = 0; k < 16; ++k) {
        INFO("A entry " << k << ": " << cas::to_string(lin.A[k]));
        CHECK(same(lin.A[k], A[k]));
    }
    const char* B[4] = {"0", "0", "1/M", "1/(M*l)"};
    for (int k = 0; k < 4; ++k) {
        INFO("B entry " << k << ": " << cas::to_string(lin.B[k]));
        CHECK(same(lin.B[k], B[k]));
    }
    CHECK(cas::to_string(lin.A[9]) == "g*m/M"); // printed in closed form, not as a quotient of sums
    // eigenvalues 0, 0, ±sqrt((M + m) g / (M l))
    const double s = std::sqrt(1.1 * 9.81 / 0.5);
    REQUIRE(lin.eigenvalues.size() == 4);
    CHECK(lin.eigenvalues[0].real() == Approx(s).epsilon(1e-12));
    CHECK(lin.eigenvalues[3].real() == Approx(-s).epsilon(1e-12));
    // a force F = 1 held: not an equilibrium, the cart and pole accelerate at 1/M, 1/(M l)
    const auto pushed = at(c, {{"th", "pi"}, {"F", "1"}});
    CHECK(same(pushed.rate[2], "1/M"));
    CHECK(same(pushed.rate[3], "1/(M*l)"));
}

// Bug caught: eigenvalues of the wrong matrix (A transposed still passes; B in A does not),
// the hanging and upright states confused.
TEST_CASE("linearization: the pendulum's eigenvalues, +-i sqrt(g/l) hanging, +-sqrt(g/l) upright", "[codegen][linearize]") {
    const Compiled c = compile(file(PHYNJO_EXAMPLE_MODELS "/pendulum.lag"));
    const double w = std::sqrt(9.81 / 1.0);
    const auto down = at(c, {{"theta", "0"}}), up = at(c, {{"theta", "pi"}});
    CHECK(same(down.A[2], "-g/l"));
    CHECK(same(up.A[2], "g/l"));
    CHECK(std::fabs(down.eigenvalues[0].real()) < 1e-12);
    CHECK(down.eigenvalues[0].imag() == Approx(w).epsilon(1e-12));
    CHECK(down.eigenvalues[1].imag() == Approx(-w).epsilon(1e-12));
    CHECK(up.eigenvalues[0].real() == Approx(w).epsilon(1e-12));
    CHECK(up.eigenvalues[1].real() == Approx(-w).epsilon(1e-12));
    const std::string text = codegen::emit_linear(c.model, up, false);
    CHECK(text.find("1 unstable mode") != std::string::npos);
    CHECK(text.find("the equilibrium is unstable") != std::string::npos);
    CHECK(codegen::emit_linear(c.model, down, false).find("no eigenvalue with a positive real part") != std::string::npos);
    CHECK(codegen::emit_linear(c.model, up, true).find("\\begin{pmatrix}") != std::string::npos);
}

// Bugs caught: q'' and λ not substituted for their symbols away from equilibrium (the
// ∂M/∂q·q'' and ∂G/∂q·λ terms), the constrained solve (Gᵀ's sign in the saddle point).
TEST_CASE("linearization away from equilibrium = central differences (double pendulum, Cartesian pendulum)",
          "[codegen][linearize]") {
    const Compiled dp = compile(file(PHYNJO_EXAMPLE_MODELS "/double_pendulum.lag"));
    CHECK(against_differences(dp, at(dp, {{"th1", "1"}, {"th2", "1/2"}, {"th1'", "3/10"}, {"th2'", "-1"}})) < 1e-7);
    const Compiled cp = compile(file(PHYNJO_EXAMPLE_MODELS "/cartesian_pendulum.lag"));
    CHECK(against_differences(cp, at(cp, {{"x", "l*sin(1)"}, {"y", "-l*cos(1)"}, {"x'", "cos(1)"}, {"y'", "sin(1)"}})) <
          1e-7);
    const Compiled fb = compile(file(PHYNJO_EXAMPLE_MODELS "/four_bar.lag"));
    CHECK(against_differences(fb, at(fb, {{"th2", "0.9733899101495463"}, {"th3", "1.696124157962962"}, {"th1'", "4"}})) <
          1e-6);
}

// Bug caught: a state naming something else silently ignored; a singular state giving NaN.
TEST_CASE("linearization: bad states are clear errors", "[codegen][linearize]") {
    const Compiled c = compile(file(PHYNJO_EXAMPLE_MODELS "/pendulum.lag"));
    CHECK_THROWS_WITH(at(c, {{"phi", "0"}}), "'phi' is not a coordinate, a velocity (x'), an input or t of model pendulum");
    CHECK_THROWS_WITH(at(c, {{"theta", "zeta"}}), "the value of theta may use numbers and parameters only, not 'zeta'");
    const Compiled s = compile("coordinates th, ph\nparameters m = 1, l = 1, g = 9.81\n"
                               "lagrangian 1/2*m*l^2*(th'^2 + sin(th)^2*ph'^2) + m*g*l*cos(th)\n");
    CHECK_THROWS_AS(at(s, {{"th", "0"}}), codegen::LinearizeError); // M = diag(m l², 0) at the pole
}

// Bugs caught: an exact equilibrium called "not an equilibrium" because cos(acos(u)) is not
// simplified (the bead on a hoop turning at w, th = acos(g/(R w²))); a residual that only
// rounding keeps from zero reported as a moving state, or no value shown for it. The oracle
// for A: θ'' = sin θ (w² cos θ − g/R), so ∂θ''/∂θ = −w² sin²θ = g²/(R² w²) − w² there.
TEST_CASE("linearization: the bead on a turning hoop off the axis, an equilibrium proved or seen numerically",
          "[codegen][linearize]") {
    const Compiled c = compile("model hoop\ncoordinates th\nparameters m = 1, R = 1, w = 5, g = 9.81\n"
                               "let x = R*sin(th)*cos(w*t)\nlet y = R*sin(th)*sin(w*t)\nlet z = -R*cos(th)\n"
                               "lagrangian 1/2*m*(x'^2 + y'^2 + z'^2) - m*g*z\n");
    const auto lin = at(c, {{"th", "acos(g/(R*w^2))"}});
    for (Expr r : lin.rate) CHECK(r.is_zero());
    CHECK(same(lin.A[2], "g^2/(R^2*w^2) - w^2"));
    const std::string text = codegen::emit_linear(c.model, lin, false);
    CHECK(text.find("(0, 0): an equilibrium\n") != std::string::npos);
    // the same point written so that the simplifier cannot prove it: its value is shown
    const auto num = at(c, {{"th", "asin(sqrt(1 - g^2/(R^2*w^4)))"}});
    const std::string t2 = codegen::emit_linear(c.model, num, false);
    INFO(t2);
    CHECK(!num.rate[1].is_zero());
    CHECK(std::fabs(num.rate_values[1]) < 1e-13);
    CHECK(t2.find("at the parameters' defaults: an equilibrium not proved symbolically, numerically zero to") !=
          std::string::npos);
    // a point that is no equilibrium: its rate at the defaults, w² cos 1 sin 1 − g sin 1 = 3.11139
    const std::string t3 = codegen::emit_linear(c.model, at(c, {{"th", "1"}}), false);
    INFO(t3);
    CHECK(t3.find("= (0, 3.11139) at the parameters' defaults: not an equilibrium") != std::string::npos);
}

// Bug caught: a wrong Gauss–Jordan elimination, the path above 8 unknowns (a row operation
// on the wrong rows, a pivot row swapped in K but not in R, the back substitution skipped):
// every other linearized model has at most 5 unknowns and takes the adjugate. The Cartesian
// triple pendulum has 6 coordinates and 3 constraints: 9 unknowns, and the saddle-point matrix
// has a zero block, so the pivots must be chosen. The oracle: central differences of the
// accelerations from M, f, G, γ solved by Eigen's LU. The state is on the constraints with
// rational values (links along (3, −4)/5, (4, −3)/5, (0, −1), turning at 1/2, −1, 2 rad/s).
TEST_CASE("linearization above 8 unknowns (Gauss-Jordan) = central differences: Cartesian triple pendulum",
          "[codegen][linearize]") {
    const Compiled c = compile("coordinates x1, y1, x2, y2, x3, y3\nparameters m = 1, l = 1, g = 9.81\n"
                               "lagrangian 1/2*m*(x1'^2 + y1'^2 + x2'^2 + y2'^2 + x3'^2 + y3'^2) - m*g*(y1 + y2 + y3)\n"
                               "constraint rod1: x1^2 + y1^2 = l^2\n"
                               "constraint rod2: (x2 - x1)^2 + (y2 - y1)^2 = l^2\n"
                               "constraint rod3: (x3 - x2)^2 + (y3 - y2)^2 = l^2\n");
    REQUIRE(c.eom.dof + c.eom.n_constraints == 9);
    const auto lin = at(c, {{"x1", "3/5"}, {"y1", "-4/5"}, {"x2", "7/5"}, {"y2", "-7/5"}, {"x3", "7/5"}, {"y3", "-12/5"},
                            {"x1'", "2/5"}, {"y1'", "3/10"}, {"x2'", "-1/5"}, {"y2'", "-1/2"}, {"x3'", "9/5"},
                            {"y3'", "-1/2"}});
    CHECK(against_differences(c, lin) < 1e-6);
    // the rates are the accelerations of the independent solve
    std::vector<double> y;
    cas::Bindings<double> defaults;
    for (const auto& p : c.model.parameters) defaults[p.symbol] = p.default_value;
    for (Expr s : lin.state) y.push_back(cas::evaluate(s, defaults));
    const Eigen::VectorXd a = accelerations(c, y);
    for (std::size_t i = 0; i < 6; ++i) CHECK(lin.rate_values[6 + i] == Approx(a(static_cast<Eigen::Index>(i))).margin(1e-12));
}

// Bug caught: a monomial shared by the adjugate's numerator and determinant left in both (the
// example cart-pole printed −3 g lh² mp²/(4 lh² mc mp + lh² mp²)), or cancelled wrongly. The
// oracle: the textbook cart-pole (a rod of half-length lh, I = mp lh²/3 about its centre):
// ∂ẍ/∂θ = −3 g mp/(4 mc + mp) at the top, and the entries' values at random parameters
// unchanged by the cancellation (central differences).
TEST_CASE("linearization: a monomial shared by numerator and determinant cancels (the example cart-pole)",
          "[codegen][linearize]") {
    const Compiled c = compile(file(PHYNJO_EXAMPLE_MODELS "/cart_pole.lag"));
    const auto lin = at(c, {{"th", "pi"}});
    CHECK(cas::to_string(lin.A[9]) == "-3*g*mp/(4*mc + mp)");
    CHECK(same(lin.A[9], "-3*g*mp/(4*mc + mp)"));
    CHECK(against_differences(c, lin) < 1e-7);
    const std::string text = codegen::emit_linear(c.model, lin, false);
    INFO(text);
    CHECK(text.find("an equilibrium at these values (not for every value of the parameters)") != std::string::npos);
}
