// Common-subexpression elimination: reconstructs the inputs, shares what is shared,
// deterministic.
#include "expr_gen.hpp"
#include "property.hpp"

#include "phynjo/cas/cas.hpp"
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

#include <unordered_set>

using namespace phynjo::cas;
using phynjo::grammar::parse;
using phynjo::test::check_property;

namespace {
/// Substitutes the temporaries back, last first.
std::vector<Expr> inline_back(const CseResult& r) {
    std::vector<Expr> out = r.outputs;
    for (auto it = r.assignments.rbegin(); it != r.assignments.rend(); ++it)
        for (Expr& o : out) o = subs(o, {{it->first, it->second}});
    return out;
}
} // namespace

TEST_CASE("cse shares repeated subexpressions", "[cas][cse]") {
    const std::vector<Expr> in{parse("sin(x)*cos(x) + (x+y)^2"), parse("sin(x)*cos(x)*y + sin(x)")};
    const CseResult r = cse(in);
    REQUIRE(r.assignments.size() == 2);
    CHECK(r.assignments[0].second == parse("sin(x)"));
    CHECK(r.assignments[1].second == parse("cos(x)"));
    CHECK(inline_back(r) == in);
    // temporaries avoid the input's names
    const CseResult r2 = cse(std::vector<Expr>{parse("sin(x0)^2 + sin(x0)")});
    REQUIRE(r2.assignments.size() == 1);
    CHECK(to_string(r2.assignments[0].first) == "x_0");
    // power bases can be hoisted for printers that multiply
    const CseResult r3 = cse(std::vector<Expr>{parse("(a+b)^3")}, {.hoist_power_bases = true});
    REQUIRE(r3.assignments.size() == 1);
    CHECK(r3.assignments[0].second == parse("a+b"));
}

TEST_CASE("cse reconstructs random inputs and is deterministic", "[cas][cse]") {
    check_property("inline(cse(es)) == es", [] {
        const auto es = *rc::gen::container<std::vector<Expr>>(3, phynjo::test::gen_expr(4));
        const CseResult r = cse(es);
        RC_ASSERT(inline_back(r) == es);
        // every temporary is defined before it is used
        std::unordered_set<const Node*> defined;
        for (const auto& [t, v] : r.assignments) {
            for (Expr s : free_symbols(v))
                if (symbol_name(s).substr(0, 1) == "x" && symbol_name(s).size() > 1 &&
                    std::isdigit(static_cast<unsigned char>(symbol_name(s)[1])))
                    RC_ASSERT(defined.count(s.get()) == 1);
            defined.insert(t.get());
        }
        const CseResult again = cse(es);
        RC_ASSERT(again.assignments == r.assignments);
        RC_ASSERT(again.outputs == r.outputs);
    }, {.cases = 500});
}

// Bug caught: partial sums not shared (each of a chain's sums printed whole: O(k) each,
// O(N²) text for N links — nlink_cart(40)'s Jacobians), a term lost or doubled when a sum
// is computed from another, or a sum "shared" with one whose coefficients differ.
TEST_CASE("cse computes a sum from a sum of the same DAG with all but one or two of its terms", "[cas][cse]") {
    auto terms = [](Expr e) { return e.kind() == Kind::Add ? e->nargs + (e->number.is_zero() ? 0u : 1u) : 1u; };
    // a chain: s_k = a1 + … + ak, k = 3 … 8
    std::vector<Expr> chain;
    std::string s = "a1 + a2";
    for (int k = 3; k <= 8; ++k) {
        s += " + a" + std::to_string(k);
        chain.push_back(parse(s));
    }
    const CseResult r = cse(chain);
    CHECK(inline_back(r) == chain);
    std::size_t total = 0;
    for (const auto& [t, v] : r.assignments) total += terms(v);
    for (Expr o : r.outputs) total += terms(o);
    // s_3 … s_7 are temporaries (each used by the next sum): s_3 whole (3 terms), the
    // others a temporary plus a term (4·2); the outputs s_3 … s_7 are those temporaries (5·1),
    // s_8 = s_7 + a8 (2). Whole sums: 3 + 4 + … + 8 = 33.
    CHECK(total == 18);
    CHECK(terms(r.outputs.back()) == 2);
    // two terms more; a constant term; coefficients must match
    const std::vector<Expr> two{parse("a + b + c"), parse("a + b + c + d + e")};
    const CseResult r2 = cse(two);
    CHECK(inline_back(r2) == two);
    CHECK(terms(r2.outputs[1]) == 3);
    const std::vector<Expr> constant{parse("a + 2*b + c"), parse("a + 2*b + c + 1")};
    const CseResult r3 = cse(constant);
    CHECK(inline_back(r3) == constant);
    CHECK(terms(r3.outputs[1]) == 2);
    const std::vector<Expr> other{parse("a + 2*b + c"), parse("a + 3*b + c + d")};
    const CseResult r4 = cse(other);
    CHECK(inline_back(r4) == other);
    CHECK(terms(r4.outputs[1]) == 4);
    // off: every sum whole
    const CseResult r5 = cse(chain, {.share_partial_sums = false});
    CHECK(inline_back(r5) == chain);
    CHECK(terms(r5.outputs.back()) == 8);
}
