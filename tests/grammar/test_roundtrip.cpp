// parse(print(e)) == e for 10,000 random expressions (fixed seed).
#include "expr_gen.hpp"
#include "property.hpp"

#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

TEST_CASE("printing then parsing gives back the same expression", "[grammar][print]") {
    phynjo::test::check_property("parse(to_string(e)) == e", [] {
        const phynjo::cas::Expr e = *phynjo::test::gen_expr(5);
        const std::string text = phynjo::cas::to_string(e);
        RC_ASSERT(phynjo::grammar::parse(text) == e);
    }, {.cases = 10000});
}
