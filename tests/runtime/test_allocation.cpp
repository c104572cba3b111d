// A built workflow runs a step without any heap allocation: proven with a counting global
// allocator (this test is its own executable so that the replacement is local to it).
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>

#include "counting_allocator.hpp"

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
        Registry r;
        std::vector<RigidInit> init;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                for (int k = 0; k < 4; ++k) {
                    r.add("s" + std::to_string(init.size()));
                    RigidInit s;
                    s.position = {0.06 + 0.12 * i, 0.06 + 0.12 * j, 0.06 + 0.12 * k};
                    init.push_back(s);
                }
        World w = make_rigid_world(r, std::vector<RigidBody>(init.size(), RigidBody::solid_sphere(1, 0.05)), init,
                                   contact_cache_fields());
        const std::vector<Plane> planes{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -0.48},
                                        Plane{{0, 0, 1}, 0}, Plane{{0, 0, -1}, -0.48}};
        Stepper s(rigid_contact_step(Force3D::gravity(9.81), all_bodies(w), planes,
                                     ContactMaterial{restitution_curve(0.5, 0.2), constant_curve(0.5)}, {}, w.layout_ptr()));
        s.run(w, 1.0 / 240, 480); // settle: scratch grows to the largest contact count
        CHECK(count([&] { s.run(w, 1.0 / 240, 240); }) == 0);
    }
}
