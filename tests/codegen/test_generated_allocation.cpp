// Generated functions never allocate (docs/generated-code.md): a counting global allocator.
#include "double_pendulum.hpp"
#include "four_bar.hpp"
#include "nlink_cart_5.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

#include "counting_allocator.hpp"

using phynjo::test::allocations;

TEST_CASE("generated functions do not allocate", "[codegen][allocation]") {
    const double_pendulum::Parameters P;
    const nlink_cart_5::Parameters Q;
    std::vector<double> q{0.3, -0.2}, v{0.1, 0.4}, out(2), M(4);
    std::vector<double> q6(6, 0.1), v6(6, 0.2), o6(6), M6(36);
    const long before = allocations.load();
    double e = 0;
    for (int k = 0; k < 100; ++k) {
        double_pendulum::accelerations(P, 0, q, v, out);
        double_pendulum::mass_matrix(P, 0, q, M);
        double_pendulum::forcing(P, 0, q, v, out);
        double_pendulum::momenta(P, 0, q, v, out);
        double_pendulum::generalized_forces(P, 0, q, v, out);
        e += double_pendulum::energy(P, 0, q, v);
        double_pendulum::initial_state(P, q, v);
        nlink_cart_5::accelerations(Q, 0, q6, v6, o6);
        nlink_cart_5::mass_matrix(Q, 0, q6, M6);
    }
    CHECK(allocations.load() - before == 0);
    CHECK(std::isfinite(e));
}

// Bug caught: a constrained solve, projection or implicit constrained step that allocates
// in a steady step (scratch regrown every step).
TEST_CASE("constrained models: generated functions and steady steps do not allocate", "[codegen][allocation]") {
    using namespace phynjo::runtime;
    const four_bar::Parameters P;
    std::vector<double> q{0.1, 0.9, 1.7}, v{1, -0.5, -0.5}, a(3), lambda(2), G(6), phi(2), sc(4);
    std::vector<World> worlds;
    std::vector<Stepper> steppers;
    const char* integrators[] = {"rk4", "midpoint", "rattle"};
    for (int i = 0; i < 3; ++i) worlds.push_back(four_bar::make_world(P));
    for (int i = 0; i < 3; ++i) steppers.emplace_back(four_bar::workflow(P, worlds[i], integrators[i]));
    for (int i = 0; i < 3; ++i) steppers[i].step(worlds[i], 1e-3); // the first steps size the scratch
    const long before = allocations.load();
    for (int k = 0; k < 100; ++k) {
        four_bar::accelerations_and_multipliers(P, 0, q, v, a, lambda);
        four_bar::accelerations(P, 0, q, v, a);
        four_bar::constraint_matrix(P, 0, q, G);
        four_bar::constraint_residuals(P, 0, q, v, phi);
        four_bar::constraint_scales(P, 0, q, v, sc);
        for (int i = 0; i < 3; ++i) steppers[i].step(worlds[i], 1e-3);
    }
    CHECK(allocations.load() - before == 0);
    CHECK(std::isfinite(worlds[2].at(kGQ, 0)));
}
