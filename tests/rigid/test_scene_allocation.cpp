// A scene's steady steps allocate nothing: generated models (one constrained) and rigid
// spheres under one contact rule, counted by the global allocator of this executable.
#include "bob_pendulum.hpp"
#include "phynjo/runtime/runtime.hpp"
#include "ring_bead.hpp"

#include <catch2/catch.hpp>

#include "counting_allocator.hpp"

using phynjo::test::allocations;
using namespace phynjo::runtime;

// Bugs caught: a scratch vector of the model coupling sized inside the step (J, B, the pairs
// of model spheres, the proxies' sync buffers), a model step that copies its world.
TEST_CASE("steady scene steps allocate nothing", "[scene][allocation]") {
    Registry reg;
    std::vector<RigidInit> init;
    for (int i = 0; i < 6; ++i) {
        reg.add("ball" + std::to_string(i));
        RigidInit s;
        s.position = {-0.3 + 0.12 * i, 0.05 + 0.11 * (i % 2), 0};
        init.push_back(s);
    }
    bob_pendulum::Parameters P;
    P.py = 1.1;
    Scene sc = make_scene(reg, std::vector<RigidBody>(6, RigidBody::solid_sphere(0.5, 0.05)), init,
                          {ModelInstance{"pend", bob_pendulum::system(P)}, ModelInstance{"bead", ring_bead::system({})}},
                          contact_cache_fields());
    const double q[1] = {1.0}, qd[1] = {0};
    set_model_state(sc, 0, q, qd);
    for (const ContactScheme scheme : {ContactScheme::gauss_seidel, ContactScheme::jacobi}) {
        ContactOptions o;
        o.scheme = scheme;
        Executor ex(2);
        Stepper st(scene_step(sc, Force3D::gravity(9.81), {Plane::ground()}, {restitution_curve(0.5, 0.1), constant_curve(0.4)}, o),
                   &ex);
        st.run(sc.world, 1e-3, 300); // warm up: every scratch at its size, contacts made
        const long before = allocations.load();
        st.run(sc.world, 1e-3, 300);
        CHECK(allocations.load() - before == 0);
    }
}
