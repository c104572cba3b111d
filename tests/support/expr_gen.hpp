#pragma once
// Random expressions for property tests: every node kind, exact rationals, velocities.
#include "phynjo/cas/cas.hpp"

#include <rapidcheck.h>

#include <ostream>
#include <string>

namespace phynjo::cas {
inline void showValue(Expr e, std::ostream& os) { os << to_string(e); }
} // namespace phynjo::cas

namespace phynjo::test {

using cas::Expr;

/// Applies f, falling back to `fallback` when the mathematics is undefined (log(0), 1/0…).
template <typename F>
Expr safely(F&& f, Expr fallback) {
    try {
        return f();
    } catch (const cas::Error&) {
        return fallback;
    }
}

inline rc::Gen<Expr> gen_leaf() {
    using namespace rc;
    return gen::weightedOneOf<Expr>({
        {4, gen::map(gen::element<std::string>("x", "y", "z", "m", "theta"), [](const std::string& n) { return cas::symbol(n); })},
        {1, gen::map(gen::element<std::string>("x", "theta"), [](const std::string& n) { return cas::velocity(cas::symbol(n)); })},
        {3, gen::map(gen::pair(gen::inRange(-9, 10), gen::inRange(1, 5)),
                     [](std::pair<int, int> p) { return cas::rational(p.first, p.second); })},
        {1, gen::map(gen::just(0), [](int) { return cas::pi(); })},
        {1, gen::map(gen::just(0), [](int) { return cas::time_symbol(); })},
    });
}

/// Expressions of at most `depth` levels of operations.
inline rc::Gen<Expr> gen_expr(int depth = 4) {
    using namespace rc;
    if (depth <= 0) return gen_leaf();
    const auto sub = gen_expr(depth - 1);
    const auto two = gen::pair(sub, sub);
    return gen::weightedOneOf<Expr>({
        {5, gen_leaf()},
        {3, gen::map(two, [](std::pair<Expr, Expr> p) { return p.first + p.second; })},
        {1, gen::map(two, [](std::pair<Expr, Expr> p) { return p.first - p.second; })},
        {3, gen::map(two, [](std::pair<Expr, Expr> p) { return p.first * p.second; })},
        {1, gen::map(two, [](std::pair<Expr, Expr> p) { return safely([&] { return p.first / p.second; }, p.first); })},
        {1, gen::map(gen::pair(sub, gen::inRange(-3, 5)),
                     [](std::pair<Expr, int> p) { return safely([&] { return cas::pow(p.first, Expr(p.second)); }, p.first); })},
        {1, gen::map(gen::pair(sub, gen::element(1, 2, -1)),
                     [](std::pair<Expr, int> p) {
                         return safely([&] { return cas::pow(p.first, cas::rational(p.second, 2)); }, p.first);
                     })},
        {1, gen::map(two, [](std::pair<Expr, Expr> p) { return safely([&] { return cas::pow(p.first, p.second); }, p.first); })},
        {1, gen::map(sub, [](Expr e) { return cas::sin(e); })},
        {1, gen::map(sub, [](Expr e) { return cas::cos(e); })},
        {1, gen::map(sub, [](Expr e) { return safely([&] { return cas::tan(e); }, e); })},
        {1, gen::map(sub, [](Expr e) { return cas::exp(e); })},
        {1, gen::map(sub, [](Expr e) { return safely([&] { return cas::log(e); }, e); })},
        // the inverse, hyperbolic and piecewise functions
        {1, gen::map(sub, [](Expr e) { return safely([&] { return cas::asin(e); }, e); })},
        {1, gen::map(sub, [](Expr e) { return safely([&] { return cas::acos(e); }, e); })},
        {1, gen::map(sub, [](Expr e) { return cas::atan(e); })},
        {1, gen::map(sub, [](Expr e) { return cas::sinh(e); })},
        {1, gen::map(sub, [](Expr e) { return cas::cosh(e); })},
        {1, gen::map(sub, [](Expr e) { return cas::tanh(e); })},
        {1, gen::map(sub, [](Expr e) { return cas::abs(e); })},
        {1, gen::map(sub, [](Expr e) { return cas::sign(e); })},
        {1, gen::map(two, [](std::pair<Expr, Expr> p) { return safely([&] { return cas::atan2(p.first, p.second); }, p.first); })},
    });
}

} // namespace phynjo::test

namespace rc {
template <>
struct Arbitrary<phynjo::cas::Expr> {
    static Gen<phynjo::cas::Expr> arbitrary() { return phynjo::test::gen_expr(4); }
};
} // namespace rc
