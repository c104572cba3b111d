// Boxes in contact (issue #37): phynjo's contact rule against ODE (dWorldQuickStep, its
// box–box collider, sweep-and-prune space) and Bullet (btDiscreteDynamicsWorld, sequential
// impulses, btBoxBoxDetector through its persistent manifolds) on the same scenes, in one run.
//
// 1. The box pile: N = 1,000 cubes of side 0.1 m and 1 kg, each turned at random (fixed seed),
//    on a jittered lattice of spacing 0.2 m (no overlap at the start) in a 2 × 2 m box whose
//    four sides are walls, dropped onto the ground y = 0 under g = 9.81 m/s². Restitution 0.2
//    above 0.2 m/s, friction 0.5 everywhere, dt = 1/240 s, 20 velocity iterations in every
//    engine, 4 s simulated, nothing put to sleep. The engines run side by side, in turns of 24
//    steps (0.1 s), so that a machine whose speed drifts (a shared or virtual one) slows them
//    alike and the ratios hold where the times do not. Reported per engine: ms per step (mean over
//    the run), the deepest overlap at the end (box–box and box–wall, measured the same way for
//    all: phynjo's manifolds on the final poses), the largest speed and the fraction of boxes
//    slower than 0.05 m/s. `ratio box_pile_1000_ode` = ODE's ms per step / ours, likewise
//    Bullet's.
// 2. The pyramid: 20 rows of 1 m cubes (1 kg, 1.02 m apart in a row, 210 boxes) on the
//    ground, μ = 0.6, dt = 1/240 s, 20 iterations, 10 s: the seconds until some box has moved
//    1 cm or turned 1° from where it started (checked every 0.1 s), per engine.
//
// Usage: bench_box_pile [N]   (default 1000)
#include "phynjo/runtime/runtime.hpp"

#include <btBulletDynamicsCommon.h>
#include <ode/ode.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

using namespace phynjo::runtime;

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kG = 9.81, kDt = 1.0 / 240, kRest = 0.05;
constexpr int kIterations = 20;

struct Pose {
    Eigen::Vector3d p;
    Quaternion q;
};

struct Setup {
    double half = 0, mass = 1, mu = 0.5, e = 0, bounce_vel = 0.2, seconds = 0;
    double side = 0; ///< walls at 0 and side on x and z; 0: the ground alone
    std::vector<Pose> start;
    std::vector<Plane> planes() const {
        if (side == 0) return {Plane::ground()};
        return {Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -side}, Plane{{0, 0, 1}, 0}, Plane{{0, 0, -1}, -side}};
    }
};

Setup box_pile(int count) {
    Setup s;
    s.half = 0.05, s.e = 0.2, s.seconds = 4;
    const int n = static_cast<int>(std::lround(std::cbrt(count)));
    const double a = 0.2;
    s.side = n * a;
    std::mt19937 rng(20261205);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    std::normal_distribution<double> gauss;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < n; ++k)
                s.start.push_back({{(i + 0.5) * a + jitter(rng), (j + 0.5) * a + 0.05 + jitter(rng), (k + 0.5) * a + jitter(rng)},
                                   Quaternion{gauss(rng), gauss(rng), gauss(rng), gauss(rng)}.normalized()});
    return s;
}

Setup pyramid(int rows) {
    Setup s;
    s.half = 0.5, s.mu = 0.6, s.seconds = 10;
    for (int r = 0; r < rows; ++r)
        for (int j = 0; j < rows - r; ++j) s.start.push_back({{(j - 0.5 * (rows - r - 1)) * 1.02, 0.5 + r, 0}, Quaternion::identity()});
    return s;
}

struct Result {
    double ms_per_step = 0, overlap = 0, max_speed = 0, at_rest = 0, stood = 0;
};

/// The engine under test, seen through three calls: step, the poses, the velocities (its state
/// kept alive by the calls).
struct Engine {
    std::function<void()> step;
    std::function<std::vector<Pose>()> poses;
    std::function<std::vector<Eigen::Vector3d>()> velocities;
};

/// Runs every engine over the setup's time, in turns of 24 steps, timing the steps alone; the
/// standing time is checked after each turn (every 0.1 s), outside the timer.
std::vector<Result> run(const Setup& s, std::vector<Engine>& engines) {
    const int steps = static_cast<int>(std::lround(s.seconds / kDt)), check = 24;
    std::vector<Result> results(engines.size());
    std::vector<double> sec(engines.size(), 0.0);
    for (Result& r : results) r.stood = -1;
    for (int k = 0; k < steps; k += check)
        for (std::size_t x = 0; x < engines.size(); ++x) {
            Engine& e = engines[x];
            Result& r = results[x];
            const auto t0 = Clock::now();
            for (int j = 0; j < check && k + j < steps; ++j) e.step();
            sec[x] += std::chrono::duration<double>(Clock::now() - t0).count();
            if (r.stood >= 0) continue;
            const std::vector<Pose> now = e.poses();
            for (std::size_t i = 0; i < now.size(); ++i) {
                const Quaternion d = now[i].q * s.start[i].q.conjugate();
                const double turn = 2 * std::acos(std::min(1.0, std::abs(d.w)));
                if ((now[i].p - s.start[i].p).norm() > 0.01 || turn > M_PI / 180) {
                    r.stood = (k + check) * kDt;
                    break;
                }
            }
        }
    for (std::size_t x = 0; x < engines.size(); ++x) {
        Result& r = results[x];
        if (r.stood < 0) r.stood = s.seconds;
        r.ms_per_step = 1e3 * sec[x] / steps;
        // The deepest overlap, by phynjo's manifolds on the final poses, the same for every engine.
        const std::vector<Pose> end = engines[x].poses();
        Registry reg;
        std::vector<RigidInit> init(end.size());
        for (std::size_t i = 0; i < end.size(); ++i) {
            reg.add("b" + std::to_string(i));
            init[i].position = end[i].p;
            init[i].orientation = end[i].q;
        }
        const World w =
            make_rigid_world(reg, std::vector<RigidBody>(end.size(), RigidBody::solid_box(s.mass, Eigen::Vector3d::Constant(s.half))), init);
        r.overlap = max_penetration(w, all_bodies(w), s.planes());
        std::size_t slow = 0;
        for (const auto& v : engines[x].velocities()) {
            r.max_speed = std::max(r.max_speed, v.norm());
            if (v.norm() < kRest) ++slow;
        }
        r.at_rest = static_cast<double>(slow) / static_cast<double>(end.size());
    }
    return results;
}

// ---- phynjo ----------------------------------------------------------------------------------

struct PhynjoState {
    World w;
    Stepper st;
    PhynjoState(World world, const Setup& s, const ContactOptions& o, const ContactMaterial& mat)
        : w(std::move(world)), st(rigid_contact_step(Force3D::gravity(kG), all_bodies(w), s.planes(), mat, o, w.layout_ptr())) {}
};

Engine phynjo_engine(const Setup& s) {
    Registry reg;
    std::vector<RigidInit> init(s.start.size());
    for (std::size_t i = 0; i < s.start.size(); ++i) {
        reg.add("b" + std::to_string(i));
        init[i].position = s.start[i].p;
        init[i].orientation = s.start[i].q;
    }
    World w = make_rigid_world(reg, std::vector<RigidBody>(s.start.size(), RigidBody::solid_box(s.mass, Eigen::Vector3d::Constant(s.half))),
                               init, contact_cache_fields(32));
    ContactOptions o;
    o.velocity_iterations = kIterations;
    o.slop = 2e-5 * s.half / 0.05;
    const ContactMaterial mat{restitution_curve(s.e, s.bounce_vel), constant_curve(s.mu)};
    auto x = std::make_shared<PhynjoState>(std::move(w), s, o, mat);
    return {[x] { x->st.step(x->w, kDt); },
            [x] {
                std::vector<Pose> out;
                for (Index i = 0; i < x->w.size(); ++i) out.push_back({position(x->w, i), orientation(x->w, i)});
                return out;
            },
            [x] {
                std::vector<Eigen::Vector3d> out;
                for (Index i = 0; i < x->w.size(); ++i) out.push_back(velocity(x->w, i));
                return out;
            }};
}

// ---- ODE -------------------------------------------------------------------------------------

struct OdeCtx {
    dWorldID world;
    dJointGroupID contacts;
    const Setup* s;
};

void ode_near(void* data, dGeomID a, dGeomID b) {
    auto* ctx = static_cast<OdeCtx*>(data);
    dContact c[8];
    const int n = dCollide(a, b, 8, &c[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
        c[i].surface.mode = dContactBounce | dContactApprox1;
        c[i].surface.mu = ctx->s->mu;
        c[i].surface.bounce = ctx->s->e;
        c[i].surface.bounce_vel = ctx->s->bounce_vel;
        const dJointID j = dJointCreateContact(ctx->world, ctx->contacts, &c[i]);
        dJointAttach(j, dGeomGetBody(a), dGeomGetBody(b));
    }
}

/// One ODE world at a time (dInitODE2 … dCloseODE).
struct OdeState {
    OdeCtx ctx;
    dSpaceID space;
    std::vector<dBodyID> bodies;
    explicit OdeState(const Setup& s) : ctx{(dInitODE2(0), dWorldCreate()), dJointGroupCreate(0), &s} {
        dWorldSetGravity(ctx.world, 0, -kG, 0);
        dWorldSetQuickStepNumIterations(ctx.world, kIterations);
        space = dSweepAndPruneSpaceCreate(nullptr, dSAP_AXES_XZY);
        for (const Plane& p : s.planes()) dCreatePlane(space, p.normal.x(), p.normal.y(), p.normal.z(), p.offset);
        for (const Pose& p : s.start) {
            const dBodyID b = dBodyCreate(ctx.world);
            dMass m;
            dMassSetBoxTotal(&m, s.mass, 2 * s.half, 2 * s.half, 2 * s.half);
            dBodySetMass(b, &m);
            dBodySetPosition(b, p.p.x(), p.p.y(), p.p.z());
            const dQuaternion q{p.q.w, p.q.x, p.q.y, p.q.z};
            dBodySetQuaternion(b, q);
            dBodySetAutoDisableFlag(b, 0);
            const dGeomID g = dCreateBox(space, 2 * s.half, 2 * s.half, 2 * s.half);
            dGeomSetBody(g, b);
            bodies.push_back(b);
        }
    }
    OdeState(const OdeState&) = delete;
    OdeState& operator=(const OdeState&) = delete;
    ~OdeState() {
        dSpaceDestroy(space);
        dJointGroupDestroy(ctx.contacts);
        dWorldDestroy(ctx.world);
        dCloseODE();
    }
};

Engine ode_engine(const Setup& s) {
    auto x = std::make_shared<OdeState>(s);
    return {[x] {
                dSpaceCollide(x->space, &x->ctx, &ode_near);
                dWorldQuickStep(x->ctx.world, kDt);
                dJointGroupEmpty(x->ctx.contacts);
            },
            [x] {
                std::vector<Pose> out;
                for (dBodyID b : x->bodies) {
                    const dReal* p = dBodyGetPosition(b);
                    const dReal* q = dBodyGetQuaternion(b);
                    out.push_back({{p[0], p[1], p[2]}, Quaternion{q[0], q[1], q[2], q[3]}.normalized()});
                }
                return out;
            },
            [x] {
                std::vector<Eigen::Vector3d> out;
                for (dBodyID b : x->bodies) {
                    const dReal* v = dBodyGetLinearVel(b);
                    out.emplace_back(v[0], v[1], v[2]);
                }
                return out;
            }};
}

// ---- Bullet ----------------------------------------------------------------------------------

struct BulletState {
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btDefaultMotionState>> states;
    std::vector<std::unique_ptr<btRigidBody>> bodies;
    std::size_t first = 0; // the boxes: bodies after the planes
    explicit BulletState(const Setup& s) {
        world.setGravity(btVector3(0, -kG, 0));
        world.getSolverInfo().m_numIterations = kIterations;
        world.getSolverInfo().m_restitutionVelocityThreshold = s.bounce_vel;
        // Bullet multiplies the two bodies' coefficients: √x each gives x for every contact.
        const double mu = std::sqrt(s.mu), e = std::sqrt(s.e);
        auto add = [&](btCollisionShape* shape, double mass, const btTransform& at) {
            btVector3 inertia(0, 0, 0);
            if (mass > 0) shape->calculateLocalInertia(mass, inertia);
            states.push_back(std::make_unique<btDefaultMotionState>(at));
            btRigidBody::btRigidBodyConstructionInfo info(mass, states.back().get(), shape, inertia);
            info.m_restitution = e;
            info.m_friction = mu;
            bodies.push_back(std::make_unique<btRigidBody>(info));
            bodies.back()->setActivationState(DISABLE_DEACTIVATION); // nothing put to sleep
            world.addRigidBody(bodies.back().get());
        };
        for (const Plane& p : s.planes()) {
            shapes.push_back(std::make_unique<btStaticPlaneShape>(btVector3(p.normal.x(), p.normal.y(), p.normal.z()), p.offset));
            add(shapes.back().get(), 0, btTransform::getIdentity());
        }
        shapes.push_back(std::make_unique<btBoxShape>(btVector3(s.half, s.half, s.half)));
        btCollisionShape* box = shapes.back().get();
        first = bodies.size();
        for (const Pose& p : s.start)
            add(box, s.mass, btTransform(btQuaternion(p.q.x, p.q.y, p.q.z, p.q.w), btVector3(p.p.x(), p.p.y(), p.p.z())));
    }
    BulletState(const BulletState&) = delete;
    BulletState& operator=(const BulletState&) = delete;
    ~BulletState() {
        for (auto& b : bodies) world.removeRigidBody(b.get());
    }
};

Engine bullet_engine(const Setup& s) {
    auto x = std::make_shared<BulletState>(s);
    return {[x] { x->world.stepSimulation(kDt, 0, kDt); },
            [x] {
                std::vector<Pose> out;
                for (std::size_t i = x->first; i < x->bodies.size(); ++i) {
                    const btTransform& t = x->bodies[i]->getCenterOfMassTransform();
                    const btQuaternion q = t.getRotation();
                    out.push_back({{t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z()}, Quaternion{q.w(), q.x(), q.y(), q.z()}.normalized()});
                }
                return out;
            },
            [x] {
                std::vector<Eigen::Vector3d> out;
                for (std::size_t i = x->first; i < x->bodies.size(); ++i) {
                    const btVector3 v = x->bodies[i]->getLinearVelocity();
                    out.emplace_back(v.x(), v.y(), v.z());
                }
                return out;
            }};
}

void print(const char* scene, const char* engine, const Result& r, bool standing) {
    std::printf("%-12s %-7s %8.3f ms/step   deepest overlap %8.4f mm   max speed %7.4f m/s   at rest %5.1f%%", scene, engine,
                r.ms_per_step, r.overlap * 1e3, r.max_speed, 100 * r.at_rest);
    if (standing) std::printf("   stood %5.1f s", r.stood);
    std::printf("\n");
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    const int count = argc > 1 ? std::atoi(argv[1]) : 1000;
    const char* only = std::getenv("BOX_PILE_PROFILE"); // profiling aid: phynjo's pile alone
    const Setup pile = box_pile(count);
    const int n = static_cast<int>(pile.start.size());
    std::printf("box pile: %d cubes of side 0.1 m, 1 kg, e = 0.2 (above 0.2 m/s), mu = 0.5, dt = 1/240 s, %d iterations, 4 s, 1 thread\n",
                n, kIterations);
    std::vector<Engine> engines{phynjo_engine(pile)};
    if (only == nullptr) engines.push_back(ode_engine(pile)), engines.push_back(bullet_engine(pile));
    const std::vector<Result> r = run(pile, engines);
    engines.clear(); // (ODE keeps one world at a time)
    print("pile", "phynjo", r[0], false);
    if (only != nullptr) return 0;
    print("pile", "ODE", r[1], false);
    print("pile", "Bullet", r[2], false);
    std::printf("ratio box_pile_%d_ode = %.2f\n", n, r[1].ms_per_step / r[0].ms_per_step);
    std::printf("ratio box_pile_%d_bullet = %.2f\n", n, r[2].ms_per_step / r[0].ms_per_step);
    const Setup pyr = pyramid(20);
    std::printf("pyramid: 20 rows, 210 cubes of side 1 m, 1 kg, mu = 0.6, dt = 1/240 s, %d iterations, 10 s; stood = seconds until a box moved 1 cm or turned 1 deg\n",
                kIterations);
    engines = {phynjo_engine(pyr), ode_engine(pyr), bullet_engine(pyr)};
    const std::vector<Result> q = run(pyr, engines);
    print("pyramid", "phynjo", q[0], true);
    print("pyramid", "ODE", q[1], true);
    print("pyramid", "Bullet", q[2], true);
}
