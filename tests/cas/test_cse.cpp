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
