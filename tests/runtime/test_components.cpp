// Components, the registry and component sets; the literals.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

using namespace phynjo::runtime;

TEST_CASE("components are recursive labels", "[runtime][components]") {
    const Component chain("chain", {Component("link1"), Component("link2", {Component("bob")})});
    CHECK(chain.arity() == 2);
    CHECK(chain.children()[1].arity() == 1);
    const auto all = chain.subcomponents();
    REQUIRE(all.size() == 4);
    CHECK(all[0].label() == "chain");
    CHECK(all[1].label() == "link1");
    CHECK(all[2].label() == "link2");
    CHECK(all[3].label() == "bob");
    CHECK(Component("a") == Component("a"));
    CHECK_FALSE(Component("a") == Component("a", {Component("b")}));
}

TEST_CASE("the registry gives dense indices", "[runtime][components]") {
    Registry r;
    CHECK(r.add("ball") == 0);
    CHECK(r.add("box") == 1);
    CHECK(r.add("ball") == 0); // already there
    const Component chain("chain", {Component("l1"), Component("l2")});
    CHECK(r.add_tree(chain) == 2);
    CHECK(r.size() == 5);
    CHECK(r.index("l2") == 4);
    CHECK(r.label(3) == "l1");
    CHECK_FALSE(r.find("nothing"));
    CHECK_THROWS_AS(r.index("nothing"), UnknownComponent);
    CHECK_THROWS_AS(r.add(Component("")), std::invalid_argument);
}

TEST_CASE("component sets", "[runtime][components]") {
    const ComponentSet a{3, 1, 2, 3}, b = ComponentSet::range(2, 6);
    CHECK(a.size() == 3);
    CHECK((a & b) == ComponentSet{2, 3});
    CHECK((a | b) == ComponentSet{1, 2, 3, 4, 5});
    CHECK(a.contains(1));
    CHECK_FALSE(a.contains(4));
}

TEST_CASE("SLit: missing entries read as 0, insert and adjust are pure", "[runtime][literals]") {
    const SLit empty;
    CHECK(empty.lookup(7) == 0.0);
    const SLit a = empty.insert(2, 1.5);
    CHECK(a.lookup(2) == 1.5);
    CHECK(empty.lookup(2) == 0.0); // unchanged
    const SLit b = a.adjust([](double v) { return v + 1; }, 10.0, 2);
    CHECK(b.lookup(2) == 2.5);
    const SLit c = a.adjust([](double v) { return v + 1; }, 10.0, 5); // absent: start from the default
    CHECK(c.lookup(5) == 11.0);
    CHECK_FALSE(a.contains(5));
    const FlagLit f = FlagLit().insert(3, true);
    CHECK(f.lookup(3));
    CHECK_FALSE(f.lookup(4));
}

TEST_CASE("ULiteral carries units and arithmetic is checked at compile time", "[runtime][literals][units]") {
    using namespace boost::units;
    ULiteral<si::length> x(2);
    x.set(0, 1.5 * si::meters);
    x.set(1, 2.0 * si::meters);
    const auto sum = x + x;
    CHECK(sum.lookup(1).value() == 4.0);
    CHECK(x.lookup(7).value() == 0.0);
    const Mass m = 2.0 * si::kilograms;
    const Velocity v = 3.0 * si::meters_per_second;
    const Energy e = 0.5 * m * v * v; // J: the types check the formula
    CHECK(e.value() == 9.0);
    // A mismatch (metres + kilograms) does not compile: see units_mismatch.cpp, a ctest that
    // must fail to compile, beside a control that must compile.
}
