// A pile of spheres settling on the ground between four frictional walls: phynjo's contact
// rule against ODE (dWorldQuickStep, sweep-and-prune space) and Bullet
// (btDiscreteDynamicsWorld, sequential impulses) on the same scene, in the same run.
//
// Scene (issue #5): N = n³ spheres, radius 0.05 m, mass 1 kg, placed without overlap at 25%
// volume fraction (a jittered cubic lattice of spacing 0.05·(16π/3)^{1/3} m) in a box whose four
// sides are walls; dropped onto the ground y = 0 under g = 9.81 m/s². Restitution 0.5 above
// 0.2 m/s (each engine's threshold set to 0.2 m/s), friction 0.5 everywhere, dt = 1/240 s,
// 2 s simulated. Reported per engine: ms per step (mean over the run), maximum penetration at
// the end (deepest sphere–sphere or sphere–wall overlap, measured the same way for all), maximum
// speed and the fraction of spheres slower than 0.05 m/s at the end.
//
// The coupling (issue #16): the same pile with a .lag double pendulum (examples/models/striker.lag,
// pivot above the middle of the box, released upside down, lengths scaled with the box: at
// N = 1,000 links of 0.5 and 0.6 m under a pivot 1.5 m high) falling into it, in one scene
// with one contact rule: `ratio pile_N_with_pendulum` = ms per step of the pile alone / with
// the pendulum (both phynjo, best of three alternating runs each).
//
// Usage: bench_pile [N …]   (default 1000 8000 27000; PHYNJO_PILE_SIZES overrides too)
//        PILE_PROFILE=alone|pendulum bench_pile N: one phynjo run only (for profilers)
#include "bench_striker.hpp"
#include "pile_scene.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <btBulletDynamicsCommon.h>
#include <ode/ode.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

using namespace phynjo::runtime;

namespace {

struct Result {
    double ms_per_step = 0, penetration = 0, max_speed = 0, at_rest = 0;
};

/// Penetration, speed and rest fraction, measured the same way for every engine.
Result measure(const Pile& s, const std::vector<Eigen::Vector3d>& pos, const std::vector<Eigen::Vector3d>& vel) {
    Registry reg;
    for (std::size_t i = 0; i < pos.size(); ++i) reg.add("s" + std::to_string(i));
    std::vector<RigidInit> init(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) init[i].position = pos[i];
    const World w = make_rigid_world(reg, std::vector<RigidBody>(pos.size(), RigidBody::solid_sphere(kSphereMass, kR)), init);
    Result r;
    r.penetration = max_penetration(w, all_bodies(w), s.planes);
    std::size_t slow = 0;
    for (const auto& v : vel) {
        r.max_speed = std::max(r.max_speed, v.norm());
        if (v.norm() < kRest) ++slow;
    }
    r.at_rest = static_cast<double>(slow) / static_cast<double>(vel.size());
    return r;
}

using Clock = std::chrono::steady_clock;
const int kSteps = static_cast<int>(std::lround(kT / kDt));

// ---- phynjo ----------------------------------------------------------------------------------

/// The pile alone (rigid_contact_step), or with the striker (scene_step): the spheres are the
/// first components of either world.
Result run_phynjo(const Pile& s, bool with_striker = false, double* striker_low = nullptr) {
    Registry reg;
    for (std::size_t i = 0; i < s.start.size(); ++i) reg.add("s" + std::to_string(i));
    std::vector<RigidInit> init(s.start.size());
    for (std::size_t i = 0; i < s.start.size(); ++i) init[i].position = s.start[i];
    const std::vector<RigidBody> spheres(s.start.size(), RigidBody::solid_sphere(kSphereMass, kR));
    const ContactMaterial material{restitution_curve(kE, kBounceVel), constant_curve(kMu)};
    ContactOptions o; // defaults, stated in bench/RESULTS.md
    std::vector<ModelInstance> models;
    if (with_striker) {
        striker::Parameters P;
        const double f = s.n / 10.0; // the geometry of N = 1,000, scaled with the box
        P.l1 = 0.5 * f, P.l2 = 0.6 * f, P.px = s.side / 2, P.py = 1.5 * f, P.pz = s.side / 2;
        models.push_back({"striker", striker::system(P)});
    }
    Scene scene = make_scene(reg, spheres, init, std::move(models), contact_cache_fields());
    World& w = scene.world;
    double low = 1e9;
    std::optional<Stepper> st;
    if (with_striker) {
        // Upside down above the lattice (no overlap at the start), it falls through the pile.
        set_model_state(scene, 0, std::vector<double>{2.5, 2.8}, std::vector<double>{0, 0});
        st.emplace(scene_step(scene, Force3D::gravity(kG), s.planes, material, o));
    } else {
        st.emplace(rigid_contact_step(Force3D::gravity(kG), scene.bodies, s.planes, material, o, w.layout_ptr()));
    }
    const auto t0 = Clock::now();
    if (with_striker) {
        const Index bob = scene.models[0].spheres[1];
        for (int k = 0; k < kSteps; ++k) {
            st->step(w, kDt);
            low = std::min(low, w.at(kY, bob));
        }
    } else {
        st->run(w, kDt, static_cast<std::size_t>(kSteps));
    }
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    if (striker_low != nullptr) *striker_low = low;
    std::vector<Eigen::Vector3d> pos, vel;
    for (Index i : scene.bodies.indices()) {
        pos.push_back(position(w, i));
        vel.push_back(velocity(w, i));
    }
    Result r = measure(s, pos, vel);
    r.ms_per_step = 1e3 * sec / kSteps;
    return r;
}

// ---- ODE -------------------------------------------------------------------------------------

struct OdeCtx {
    dWorldID world;
    dJointGroupID contacts;
};

void ode_near(void* data, dGeomID a, dGeomID b) {
    auto* ctx = static_cast<OdeCtx*>(data);
    dContact c[4];
    const int n = dCollide(a, b, 4, &c[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
        c[i].surface.mode = dContactBounce | dContactApprox1;
        c[i].surface.mu = kMu;
        c[i].surface.bounce = kE;
        c[i].surface.bounce_vel = kBounceVel;
        const dJointID j = dJointCreateContact(ctx->world, ctx->contacts, &c[i]);
        dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
    }
}

Result run_ode(const Pile& s) {
    dInitODE2(0);
    OdeCtx ctx{dWorldCreate(), dJointGroupCreate(0)};
    dWorldSetGravity(ctx.world, 0, -kG, 0);
    const dSpaceID space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XZY);
    dCreatePlane(space, 0, 1, 0, 0);
    dCreatePlane(space, 1, 0, 0, 0);
    dCreatePlane(space, -1, 0, 0, -s.side);
    dCreatePlane(space, 0, 0, 1, 0);
    dCreatePlane(space, 0, 0, -1, -s.side);
    std::vector<dBodyID> bodies;
    for (const auto& p : s.start) {
        const dBodyID b = dBodyCreate(ctx.world);
        dMass m;
        dMassSetSphereTotal(&m, kSphereMass, kR);
        dBodySetMass(b, &m);
        dBodySetPosition(b, p.x(), p.y(), p.z());
        const dGeomID g = dCreateSphere(space, kR);
        dGeomSetBody(g, b);
        bodies.push_back(b);
    }
    const auto t0 = Clock::now();
    for (int k = 0; k < kSteps; ++k) {
        dSpaceCollide(space, &ctx, &ode_near);
        dWorldQuickStep(ctx.world, kDt);
        dJointGroupEmpty(ctx.contacts);
    }
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    std::vector<Eigen::Vector3d> pos, vel;
    for (dBodyID b : bodies) {
        const dReal* p = dBodyGetPosition(b);
        const dReal* v = dBodyGetLinearVel(b);
        pos.emplace_back(p[0], p[1], p[2]);
        vel.emplace_back(v[0], v[1], v[2]);
    }
    dSpaceDestroy(space);
    dJointGroupDestroy(ctx.contacts);
    dWorldDestroy(ctx.world);
    dCloseODE();
    Result r = measure(s, pos, vel);
    r.ms_per_step = 1e3 * sec / kSteps;
    return r;
}

// ---- Bullet ----------------------------------------------------------------------------------

Result run_bullet(const Pile& s) {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher(&config);
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world(&dispatcher, &broadphase, &solver, &config);
    world.setGravity(btVector3(0, -kG, 0));
    // Bullet multiplies the two bodies' coefficients: √0.5 each gives 0.5 for every contact.
    const double c = std::sqrt(0.5);
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> states;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    auto add = [&](btCollisionShape* shape, double mass, const btVector3& at) {
        btVector3 inertia(0, 0, 0);
        if (mass > 0) shape->calculateLocalInertia(mass, inertia);
        states.push_back(std::make_unique<btDefaultMotionState>(btTransform(btQuaternion::getIdentity(), at)));
        btRigidBody::btRigidBodyConstructionInfo info(mass, states.back().get(), shape, inertia);
        info.m_restitution = c;
        info.m_friction = c;
        bodies.push_back(std::make_unique<btRigidBody>(info));
        bodies.back()->setActivationState(DISABLE_DEACTIVATION); // same work every step, like the others
        world.addRigidBody(bodies.back().get());
    };
    shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0));
    add(shapes.back().get(), 0, {0, 0, 0});
    shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(1, 0, 0), 0));
    add(shapes.back().get(), 0, {0, 0, 0});
    shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(-1, 0, 0), -s.side));
    add(shapes.back().get(), 0, {0, 0, 0});
    shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0));
    add(shapes.back().get(), 0, {0, 0, 0});
    shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, -1), -s.side));
    add(shapes.back().get(), 0, {0, 0, 0});
    shapes.push_back(std::make_unique<btSphereShape>(kR));
    btCollisionShape* sphere = shapes.back().get();
    const std::size_t first = bodies.size();
    for (const auto& p : s.start) add(sphere, kSphereMass, btVector3(p.x(), p.y(), p.z()));
    world.getSolverInfo().m_restitutionVelocityThreshold = kBounceVel;
    const auto t0 = Clock::now();
    for (int k = 0; k < kSteps; ++k) world.stepSimulation(kDt, 0, kDt);
    const double sec = std::chrono::duration<double>(Clock::now() - t0).count();
    std::vector<Eigen::Vector3d> pos, vel;
    for (std::size_t i = first; i < bodies.size(); ++i) {
        const btVector3 p = bodies[i]->getCenterOfMassPosition();
        const btVector3 v = bodies[i]->getLinearVelocity();
        pos.emplace_back(p.x(), p.y(), p.z());
        vel.emplace_back(v.x(), v.y(), v.z());
    }
    for (auto& b : bodies) world.removeRigidBody(b.get());
    Result r = measure(s, pos, vel);
    r.ms_per_step = 1e3 * sec / kSteps;
    return r;
}

void print(const char* engine, int n, const Result& r) {
    std::printf("pile N=%-6d %-7s %9.2f ms/step   max penetration %6.3f mm   max speed %7.4f m/s   at rest %5.1f%%\n", n,
                engine, r.ms_per_step, r.penetration * 1e3, r.max_speed, 100 * r.at_rest);
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    std::vector<int> sizes;
    for (int i = 1; i < argc; ++i) sizes.push_back(std::atoi(argv[i]));
    if (sizes.empty()) {
        if (const char* e = std::getenv("PHYNJO_PILE_SIZES")) {
            std::istringstream is(e);
            for (int n; is >> n;) sizes.push_back(n);
        } else {
            sizes = {1000, 8000, 27000};
        }
    }
    std::printf("sphere pile: r = %.2f m, m = %.0f kg, e = %.1f (above %.1f m/s), mu = %.1f, dt = 1/240 s, %.0f s, 1 thread\n",
                kR, kSphereMass, kE, kBounceVel, kMu, kT);
    for (int count : sizes) {
        const Pile s = make_pile(count);
        const int n = s.n * s.n * s.n;
        if (const char* only = std::getenv("PILE_PROFILE")) { // profiling aid: one phynjo run, nothing else
            const Result r = run_phynjo(s, std::string(only) == "pendulum");
            print(only, n, r);
            continue;
        }
        const Result p = run_phynjo(s);
        print("phynjo", n, p);
        // The coupling's cost: best of three alternating runs of each.
        double alone = p.ms_per_step, with = 1e300, low = 0;
        Result ps;
        for (int rep = 0; rep < 3; ++rep) {
            if (rep > 0) alone = std::min(alone, run_phynjo(s).ms_per_step);
            ps = run_phynjo(s, true, &low);
            with = std::min(with, ps.ms_per_step);
        }
        ps.ms_per_step = with;
        print("+pend.", n, ps);
        std::printf("  (the striker's lower bob reached y = %.2f m, in the pile; pile alone best of three: %.2f ms/step)\n", low,
                    alone);
        std::printf("ratio pile_%d_with_pendulum = %.2f\n", n, alone / with);
        const Result o = run_ode(s);
        print("ODE", n, o);
        const Result b = run_bullet(s);
        print("Bullet", n, b);
        std::printf("ratio pile_%d_ode = %.2f\n", n, o.ms_per_step / p.ms_per_step);
        std::printf("ratio pile_%d_bullet = %.2f\n", n, b.ms_per_step / p.ms_per_step);
        std::fflush(stdout);
    }
}
