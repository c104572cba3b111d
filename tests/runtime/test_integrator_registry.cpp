// The integrator registry (runtime/simulate/integrator_registry.hpp): one entry per
// integrator, the one list the simulator, the sweeps, generated code's workflow() and the
// docs' table read.
#include "phynjo/runtime/simulate/integrator_registry.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

using namespace phynjo::runtime;

namespace {
std::string yes_no(bool b) { return b ? "yes" : "no"; }
/// The registry's row of docs/generated-code.md's table of integrators.
std::string doc_row(const IntegratorEntry& e) {
    return "| `" + std::string(e.name) + "` | " + std::string(e.order) + " | " + yes_no(e.symplectic) + " | " +
           yes_no(e.constraints) + " | " + yes_no(e.adaptive) + " | " + yes_no(e.stiff) + " | " + yes_no(e.sweeps) +
           " | " + yes_no(e.workflow != nullptr) + " | " + std::string(e.reference) + " |";
}
} // namespace

// bug: an entry's flags changed (bdf said to take constraints, an integrator renamed, a
// new one added) without the users' table in docs/generated-code.md following
TEST_CASE("the docs' table of integrators is the registry's", "[registry]") {
    std::ifstream in(PHYNJO_SOURCE_DIR "/docs/generated-code.md");
    REQUIRE(in);
    std::stringstream text;
    text << in.rdbuf();
    std::set<std::string> rows;
    std::string line;
    while (std::getline(text, line))
        if (line.rfind("| `", 0) == 0) rows.insert(line);
    for (const IntegratorEntry& e : integrator_registry()) {
        INFO(doc_row(e));
        CHECK(rows.count(doc_row(e)) == 1);
    }
    CHECK(rows.size() == integrator_registry().size());
}

// bug: a name looked up wrongly, the default not first, or the message lists of names
// (the simulator's usage errors) built out of order
TEST_CASE("names, the default and the message lists", "[registry]") {
    REQUIRE(integrator_registry().front().name == "rk4");
    for (const IntegratorEntry& e : integrator_registry()) {
        REQUIRE(find_integrator(e.name) == &e);
        CHECK(e.make != nullptr);
        CHECK(!e.help.empty());
    }
    CHECK(find_integrator("euler") == nullptr);
    CHECK(integrator_names() == "rk4, dopri, midpoint, rattle, cvode, ida or bdf");
    CHECK(integrator_names([](const IntegratorEntry& e) { return e.sweeps; }) == "rk4, dopri, midpoint or rattle");
    CHECK(integrator_names([](const IntegratorEntry& e) { return !e.constraints; }) == "bdf");
}

// bug: generated code's workflow(P, world, NAME) accepting a name without a workflow, or
// its message not naming the caller and the names it takes
TEST_CASE("integrator_workflow refuses a name without a workflow", "[registry]") {
    LagrangianSystem s;
    s.dof = 1;
    s.coordinate_names = {"x"};
    const World w = make_lagrangian_world(s);
    try {
        (void)integrator_workflow(s, w, "dopri", "model::workflow");
        FAIL("no exception");
    } catch (const std::invalid_argument& e) {
        CHECK(std::string(e.what()) ==
              "model::workflow: unknown integrator 'dopri' (rk4, midpoint, rattle, cvode, ida or bdf)");
    }
}
