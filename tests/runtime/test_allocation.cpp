// A built workflow runs a step without any heap allocation: proven with a counting global
// allocator (this test is its own executable so that the replacement is local to it).
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

#include "counting_allocator.hpp"
#include "scenes.hpp"

using phynjo::test::allocations;

using namespace phynjo::runtime;

namespace {
template <typename F>
long count(F&& f) {
    const long before = allocations.load();
    f();
    return allocations.load() - before;
}
} // namespace

namespace {
void* volatile sink; // keeps the compiler from eliding an allocation/free pair
} // namespace

// Catches: a blind counter (one that sees only operator new) under which a World copied in
// every step, or any malloc/aligned_alloc in a step, would pass the tests below.
TEST_CASE("the allocation counter sees every allocation path", "[runtime][allocation]") {
    auto one = [](auto&& allocate_and_free) { return count(allocate_and_free); };
    CHECK(one([] { sink = std::malloc(24); std::free(sink); }) == 1);
    CHECK(one([] { sink = std::calloc(3, 8); std::free(sink); }) == 1);
    CHECK(one([] { sink = std::aligned_alloc(64, 128); std::free(sink); }) == 1);
    int rc = -1;
    CHECK(one([&] { void* p = nullptr; rc = posix_memalign(&p, 64, 128); sink = p; std::free(sink); }) == 1);
    CHECK(rc == 0);
    CHECK(one([] { sink = new double(1); delete static_cast<double*>(sink); }) == 1);
    CHECK(one([] { sink = new double[5]; delete[] static_cast<double*>(sink); }) == 1);
    struct alignas(64) Wide { double x[8]; };
    CHECK(one([] { sink = new Wide; delete static_cast<Wide*>(sink); }) == 1);
    CHECK(one([] { sink = new (std::nothrow) char[7]; delete[] static_cast<char*>(sink); }) == 1);
    // World storage is aligned: copying a world must be seen
    Registry r;
    r.add("a");
    const World w = make_nstate(r);
    CHECK(count([&] { World copy = w; sink = &copy; }) >= 1);
}

TEST_CASE("steady-state steps allocate nothing", "[runtime][allocation]") {
    SECTION("1-D leapfrog with springs, gravity and drag") {
        Registry r;
        for (int i = 0; i < 10; ++i) r.add("b" + std::to_string(i));
        World w = make_nstate(r);
        const ComponentSet all = ComponentSet::range(0, 10);
        Force1D f = Force1D::gravity(9.81, all) + Force1D::drag(0.1, all) + Force1D::spring(0, 1, 2.0, 1.0);
        Stepper s(leapfrog_dkd(nstate_splitting(f, all, w.layout_ptr())));
        s.step(w, 1e-3); // warm: per-thread scratch
        CHECK(count([&] { s.run(w, 1e-3, 1000); }) == 0);
    }
    SECTION("N-body leapfrog, par over partitions, on 2 threads") {
        Registry r;
        for (int i = 0; i < 100; ++i) r.add("s" + std::to_string(i));
        World w = make_particles(r, 2);
        for (Index i = 0; i < w.size(); ++i) {
            w.at(kX, i) = i;
            w.at(kMass, i) = 1;
        }
        Executor ex(2);
        Stepper s(nbody_leapfrog({1.0, 1e-3}, w.layout_ptr(), 2), &ex);
        s.step(w, 1e-3);
        CHECK(count([&] { s.run(w, 1e-3, 1000); }) == 0);
    }
    SECTION("RK4 workflow") {
        Registry r;
        r.add("m");
        World w = make_nstate(r, {1.0}, rk4_fields());
        Stepper s(rk4(Force1D::anchor(0, 0, 1), ComponentSet{0}, w.layout_ptr()));
        s.step(w, 1e-3);
        CHECK(count([&] { s.run(w, 1e-3, 1000); }) == 0);
    }
    SECTION("rigid spheres with contacts: a settled pile") {
        World w = phynjo::test::sphere_grid({.nx = 4, .ny = 4, .nz = 4, .origin = {0.06, 0.06, 0.06},
                                             .spacing = {0.12, 0.12, 0.12}, .jitter = 0, .seed = 1});
        const std::vector<Plane> planes = phynjo::test::box_walls(0.48);
        Stepper s(rigid_contact_step(Force3D::gravity(9.81), all_bodies(w), planes,
                                     ContactMaterial{restitution_curve(0.5, 0.2), constant_curve(0.5)}, {}, w.layout_ptr()));
        s.run(w, 1.0 / 240, 480); // settle: scratch grows to the largest contact count
        CHECK(count([&] { s.run(w, 1.0 / 240, 240); }) == 0);
    }
    SECTION("rigid spheres with contacts: a pile while it falls, lands and piles up") {
        // Catches: scratch (contact lists, broad-phase cells, warm-start slots) that grows
        // as contacts appear; the settled pile above never sees new contacts.
        const World w = phynjo::test::sphere_grid({.nx = 4, .ny = 6, .nz = 4, .origin = {0.07, 0.3, 0.07},
                                                   .spacing = {0.11, 0.15, 0.11}, .jitter = 0.01, .seed = 11});
        const std::vector<Plane> planes = phynjo::test::box_walls(0.48);
        for (ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
            World u = w;
            ContactOptions o;
            o.scheme = scheme;
            Stepper s(rigid_contact_step(Force3D::gravity(9.81), all_bodies(u), planes,
                                         ContactMaterial{restitution_curve(0.5, 0.2), constant_curve(0.5)}, o, u.layout_ptr()));
            s.step(u, 1.0 / 240); // first step: no contact yet
            INFO((scheme == ContactScheme::jacobi ? "Jacobi" : "Gauss-Seidel"));
            CHECK(count([&] { s.run(u, 1.0 / 240, 480); }) == 0);
            CHECK(u.at(kY, 0) < 0.1); // the lowest sphere fell and landed
            CHECK(u.at(kY, 23) < 0.9); // the upper ones piled up on it
        }
    }
    SECTION("boxes, capsules and spheres with contacts: a pile while it falls, lands and piles up") {
        // Catches: the manifolds' scratch (their rows, blocks, bounds, the solver's LCP
        // sets) growing as contacts appear.
        const World w = phynjo::test::shape_grid(4, 5, 4, {0.06, 0.08, 0.06}, 0.11, 0.005, 5);
        const std::vector<Plane> planes = phynjo::test::box_walls(0.44);
        for (ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
            World u = w;
            ContactOptions o;
            o.scheme = scheme;
            Stepper s(rigid_contact_step(Force3D::gravity(9.81), all_bodies(u), planes,
                                         ContactMaterial{restitution_curve(0.3, 0.2), constant_curve(0.5)}, o, u.layout_ptr()));
            s.step(u, 1.0 / 240);
            INFO((scheme == ContactScheme::jacobi ? "Jacobi" : "Gauss-Seidel"));
            CHECK(count([&] { s.run(u, 1.0 / 240, 480); }) == 0);
            CHECK(u.at(kY, 0) < 0.07); // the lowest body fell and landed
        }
    }
}
