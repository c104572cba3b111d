// Runtime guards: invalid bodies rejected at construction; non-finite state reported with the
// entry and the tick where it appeared; failing rules reported, not thrown through.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace phynjo::runtime;

TEST_CASE("invalid bodies are rejected when the world is made", "[runtime][guards]") {
    Registry r;
    r.add("a");
    r.add("b");
    CHECK_THROWS_WITH(make_nstate(r, {1.0, -2.0}), "mass of 'b' must be positive and finite, got -2.000000");
    CHECK_THROWS_AS(make_nstate(r, {0.0, 1.0}), InvalidBody);
    CHECK_THROWS_AS(make_nstate(r, {1.0, std::numeric_limits<double>::quiet_NaN()}), InvalidBody);
    CHECK_THROWS_AS(make_nstate(r, {1.0}), std::invalid_argument);
}

TEST_CASE("a guarded run stops at the first non-finite entry and says where", "[runtime][guards]") {
    Registry r;
    r.add("left");
    r.add("right");
    World w = make_nstate(r);
    // 1-D gravity between two bodies at the same place: the force G m m/d² is infinite
    w.at(kQ, 0) = w.at(kQ, 1) = 0.5;
    const ComponentSet all{0, 1};
    Stepper s(leapfrog_kdk(nstate_splitting(Force1D::newtonian(1.0, all), all, w.layout_ptr())));
    s.run(w, 0.01, 0);
    const RunReport rep = s.run_guarded(w, 0.01, 100);
    CHECK_FALSE(rep.completed);
    CHECK(rep.steps == 0);
    CHECK(rep.tick == 3); // kick, drift, kick
    CHECK(rep.reason == rep.where + " became " + (rep.reason.find("NaN") != std::string::npos ? "NaN" : "infinite") +
                            " at tick 3 (t = 0.010000 s)");
    CHECK((rep.where == "q:left" || rep.where == "p:left"));
    // a run that goes well says so
    World ok = make_nstate(r);
    ok.at(kQ, 1) = 1;
    Stepper calm(leapfrog_kdk(nstate_splitting(Force1D::spring(0, 1, 1.0, 1.0), all, ok.layout_ptr())));
    const RunReport fine = calm.run_guarded(ok, 0.01, 1000);
    CHECK(fine.completed);
    CHECK(fine.steps == 1000);
    CHECK(fine.reason.empty());
}

TEST_CASE("a rule that throws stops a guarded run with its message", "[runtime][guards]") {
    Registry r;
    r.add("x");
    World w = make_nstate(r);
    NumericRule bad{"bad", Domain(kQ, ComponentSet{0}), {}, [](double, World& world) {
                        if (world.tick >= 3) throw NonFiniteResult("the model blew up");
                        world.at(kQ, 0) += 1;
                    },
                    w.layout_ptr()};
    Stepper s(NumericWorkflow::run(bad));
    const RunReport rep = s.run_guarded(w, 0.1, 10);
    CHECK_FALSE(rep.completed);
    CHECK(rep.steps == 3);
    CHECK(rep.reason == "a rule failed: the model blew up");
    CHECK(w.at(kQ, 0) == 3.0);
}
