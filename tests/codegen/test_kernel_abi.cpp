// Model kernels (phynjo-lagc --emit=kernel, runtime/system/kernel.hpp, jit/compile.hpp): a
// kernel's LagrangianSystem against the CMake-built model's `system(P)`, every function bit
// for bit at random states, on models with constraints, events, shapes, inputs; statuses back
// to the typed errors; parameters by name; a whole run the same.
#include "phynjo/jit/compile.hpp"
#include "phynjo/runtime/runtime.hpp"
#include "phynjo/runtime/system/kernel.hpp"

#include "bouncing_ball.hpp"
#include "cartesian_pendulum.hpp"
#include "double_pendulum.hpp"
#include "four_bar.hpp"
#include "free_plate.hpp"
#include "indefinite3.hpp"
#include "physical_pendulum.hpp"
#include "shapes.hpp"
#include "triple_pendulum.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

using namespace phynjo;
using namespace phynjo::runtime;

namespace {

/// A cache of this process's own, removed at its end.
std::string cache() {
    static const struct Folder {
        std::string path;
        Folder() {
            std::string t = (std::filesystem::temp_directory_path() / "phynjo-test-kernels-XXXXXX").string();
            path = ::mkdtemp(t.data()) ? t : std::string();
        }
        ~Folder() {
            std::error_code ec;
            if (!path.empty()) std::filesystem::remove_all(path, ec);
        }
    } folder;
    return folder.path;
}

std::shared_ptr<const ModelKernel> kernel_of(const std::string& path) {
    jit::JitOptions options;
    options.cache_dir = cache();
    return ModelKernel::load(jit::compile_model_file(path, options).kernel_path);
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// Every function of two systems of one model at `states` random states: the same bits (or
/// the same exception type).
void compare(const LagrangianSystem& a, const LagrangianSystem& b, std::uint32_t seed) {
    REQUIRE(a.dof == b.dof);
    REQUIRE(a.coordinate_names == b.coordinate_names);
    REQUIRE(a.n_constraints == b.n_constraints);
    REQUIRE(a.constraint_names == b.constraint_names);
    REQUIRE(a.constraint_holonomic == b.constraint_holonomic);
    REQUIRE(a.event_names == b.event_names);
    REQUIRE(a.event_directions == b.event_directions);
    REQUIRE(a.event_stops == b.event_stops);
    REQUIRE(a.shape_names == b.shape_names);
    REQUIRE(a.shape_kinds == b.shape_kinds);
    REQUIRE(a.n_spheres == b.n_spheres);
    REQUIRE(a.n_capsules == b.n_capsules);
    REQUIRE(a.n_boxes == b.n_boxes);
    REQUIRE(a.mass_depends_on_velocities == b.mass_depends_on_velocities);
    REQUIRE(bool(a.rk4_step_values_lanes_each) == bool(b.rk4_step_values_lanes_each));
    const std::size_t n = a.dof, nc = a.n_constraints, ne = a.n_events;
    const std::size_t nx = a.n_shape_values();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-2, 2);
    for (int trial = 0; trial < 50; ++trial) {
        std::vector<double> q(n), v(n);
        for (auto& x : q) x = u(rng);
        for (auto& x : v) x = u(rng);
        const double t = u(rng);
        INFO("trial " << trial);
        auto both = [&](auto&& call, std::size_t size) {
            std::vector<double> x(size), y(size);
            bool tx = false, ty = false;
            std::string wx, wy; // the kernel's message (phynjo::kernel::Failure) is the model's exception's
            const std::type_info *kx = nullptr, *ky = nullptr;
            try { call(a, x); } catch (const std::exception& e) { tx = true, wx = e.what(), kx = &typeid(e); }
            try { call(b, y); } catch (const std::exception& e) { ty = true, wy = e.what(), ky = &typeid(e); }
            CHECK(tx == ty);
            if (!tx && !ty) CHECK(same_bits(x, y));
            if (tx && ty) {
                CHECK(wx == wy);
                CHECK(*kx == *ky);
            }
        };
        both([&](const LagrangianSystem& s, std::vector<double>& o) { s.accelerations(t, q, v, o); }, n);
        both([&](const LagrangianSystem& s, std::vector<double>& o) { s.mass_matrix(t, q, v, o); }, n * n);
        both([&](const LagrangianSystem& s, std::vector<double>& o) { s.momenta(t, q, v, o); }, n);
        both([&](const LagrangianSystem& s, std::vector<double>& o) { s.generalized_forces(t, q, v, o); }, n);
        both([&](const LagrangianSystem& s, std::vector<double>& o) { o[0] = s.energy(t, q, v); }, 1);
        both([&](const LagrangianSystem& s, std::vector<double>& o) { s.rhs_jacobian(t, q, v, o); }, 4 * n * n);
        both([&](const LagrangianSystem& s, std::vector<double>& o) {
            std::vector<double> p(n), F(n), dp(2 * n * n), dF(2 * n * n);
            s.canonical_jacobian(t, q, v, p, F, dp, dF);
            o.assign(p.begin(), p.end());
            o.insert(o.end(), F.begin(), F.end());
            o.insert(o.end(), dp.begin(), dp.end());
            o.insert(o.end(), dF.begin(), dF.end());
        }, 0);
        both([&](const LagrangianSystem& s, std::vector<double>& o) {
            std::vector<double> qq = q, vv = v, acc(n);
            s.accelerations(t, q, v, acc);
            s.rk4_step(t, 0.01, qq, vv, acc);
            o = qq;
            o.insert(o.end(), vv.begin(), vv.end());
        }, 0);
        both([&](const LagrangianSystem& s, std::vector<double>& o) {
            std::vector<double> acc(n), g(ne);
            double E = 0;
            const bool ok = s.accelerations_energy_guards(t, q, v, acc, E, g);
            o = acc;
            o.push_back(E);
            o.push_back(ok ? 1 : 0);
            o.insert(o.end(), g.begin(), g.end());
        }, 0);
        if (nc > 0) {
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.constraint_residuals(t, q, v, o); }, nc);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.constraint_velocity_residuals(t, q, v, o); }, nc);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.constraint_scales(t, q, v, o); }, 2 * nc);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.constraint_matrix(t, q, o); }, nc * n);
            both([&](const LagrangianSystem& s, std::vector<double>& o) {
                std::vector<double> acc(n), lambda(nc);
                s.accelerations_and_multipliers(t, q, v, acc, lambda);
                o = acc;
                o.insert(o.end(), lambda.begin(), lambda.end());
            }, 0);
        }
        if (ne > 0) {
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.event_guards(t, q, v, o); }, ne);
            for (std::size_t e = 0; e < ne; ++e)
                both([&](const LagrangianSystem& s, std::vector<double>& o) {
                    std::vector<double> qq = q, vv = v;
                    s.apply_event(e, t, qq, vv);
                    o = qq;
                    o.insert(o.end(), vv.begin(), vv.end());
                }, 0);
        }
        if (nx > 0) {
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.shape_positions(t, q, o); }, nx);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.sphere_jacobians(t, q, o); }, 3 * n * a.n_spheres);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.sphere_radii(o); }, a.n_spheres);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.capsule_jacobians(t, q, o); }, 6 * n * a.n_capsules);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.capsule_radii(o); }, a.n_capsules);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.box_jacobians(t, q, o); }, 6 * n * a.n_boxes);
            both([&](const LagrangianSystem& s, std::vector<double>& o) { s.box_half_extents(o); }, 3 * a.n_boxes);
        }
        if (a.rk4_step_values_lanes_each) { // a sweep's step: lane_width runs from this state and its neighbours
            REQUIRE(a.lane_width == b.lane_width);
            const std::size_t W = a.lane_width;
            both([&](const LagrangianSystem& s, std::vector<double>& o) {
                std::vector<const void*> P(W, s.parameters.get());
                std::vector<double> tt(W), h(W, 0.01), t1(W), qq(n * W), vv(n * W), acc(n * W), E(W), g(ne * W + 1);
                for (std::size_t l = 0; l < W; ++l) {
                    tt[l] = t, t1[l] = t + 0.01;
                    for (std::size_t i = 0; i < n; ++i) qq[i * W + l] = q[i] + 0.1 * l, vv[i * W + l] = v[i], acc[i * W + l] = v[i] - q[i];
                }
                const bool ok = s.rk4_step_values_lanes_each(P.data(), tt.data(), h.data(), t1.data(), qq.data(), vv.data(),
                                                             acc.data(), E.data(), g.data());
                o = qq;
                o.insert(o.end(), vv.begin(), vv.end());
                o.insert(o.end(), acc.begin(), acc.end());
                o.insert(o.end(), E.begin(), E.end());
                o.push_back(ok ? 1 : 0);
            }, 0);
        }
    }
    std::vector<double> qa(n), va(n), qb(n), vb(n);
    a.initial_state(qa, va);
    b.initial_state(qb, vb);
    CHECK(same_bits(qa, qb));
    CHECK(same_bits(va, vb));
}

} // namespace

// Bugs caught: a kernel function wired to another (forcing for accelerations), an output
// length or layout wrong in the C table, the kernel built with other flags than the model's
// (contracted multiply-adds change bits), a parameter set on the wrong field, names and flags
// of constraints, events and shapes lost.
TEST_CASE("kernels: every function bit for bit the CMake-built model's", "[codegen][kernel]") {
    const std::string models = PHYNJO_SOURCE_DIR "/examples/models/";
    SECTION("double pendulum (lanes), with parameters set by name") {
        const auto k = kernel_of(models + "double_pendulum.lag");
        KernelParameters P(k);
        P.set("m2", 2.5);
        P.set("l1", 0.7);
        double_pendulum::Parameters Q;
        Q.m2 = 2.5, Q.l1 = 0.7;
        CHECK(P.get("m2") == 2.5);
        CHECK(P.get("g") == 9.81);
        compare(kernel_system(P), double_pendulum::system(Q), 1);
    }
    SECTION("four-bar (constraints, an input)") {
        const auto k = kernel_of(models + "four_bar.lag");
        KernelParameters P(k);
        P.set("tau", 0.3);
        four_bar::Parameters Q;
        Q.tau = 0.3;
        CHECK(k->table().n_inputs == 1);
        CHECK(k->table().parameter_is_input[k->parameter_index("tau")] == 1);
        compare(kernel_system(P), four_bar::system(Q), 2);
    }
    SECTION("bouncing ball (an event, units)") {
        const auto k = kernel_of(models + "bouncing_ball.lag");
        CHECK(std::string(k->table().parameter_units[k->parameter_index("g")]) == "m/s^2");
        compare(kernel_system(KernelParameters(k)), bouncing_ball::system(), 3);
    }
    SECTION("triple pendulum (LDLT of a 3x3 mass matrix)") {
        compare(kernel_system(KernelParameters(kernel_of(PHYNJO_SOURCE_DIR "/tests/codegen/models/triple_pendulum.lag"))),
                triple_pendulum::system(), 5);
    }
    SECTION("indefinite 3x3 mass matrix (the pivoted LU after LDLT stops)") {
        compare(kernel_system(KernelParameters(kernel_of(PHYNJO_SOURCE_DIR "/tests/codegen/models/indefinite3.lag"))),
                indefinite3::system(), 6);
    }
    SECTION("physical pendulum (a parameter defined from others, set and following)") {
        const auto k = kernel_of(PHYNJO_SOURCE_DIR "/tests/codegen/models/physical_pendulum.lag");
        KernelParameters P(k);
        physical_pendulum::Parameters Q;
        compare(kernel_system(P), physical_pendulum::system(Q), 7);
        P.set("Mp", 3.0); // I follows
        Q.Mp = 3.0;
        compare(kernel_system(P), physical_pendulum::system(Q), 8);
        P.set("I", 0.7); // I set
        Q.I = 0.7;
        compare(kernel_system(P), physical_pendulum::system(Q), 8);
    }
    SECTION("Cartesian pendulum (a constraint, a diagonal mass matrix)") {
        compare(kernel_system(KernelParameters(kernel_of(models + "cartesian_pendulum.lag"))), cartesian_pendulum::system(), 9);
    }
    SECTION("free plate (a box: its axes checked, its angular Jacobian)") {
        compare(kernel_system(KernelParameters(kernel_of(PHYNJO_SOURCE_DIR "/tests/rigid/models/free_plate.lag"))),
                free_plate::system(), 10);
    }
    SECTION("shapes (3-D spheres and segments, time)") {
        const auto k = kernel_of(PHYNJO_SOURCE_DIR "/tests/codegen/models/shapes.lag");
        compare(kernel_system(KernelParameters(k)), shapes::system(), 4);
    }
}

// Bugs caught: a quick kernel (-O0) whose arithmetic differs from the optimized one's (a
// constant folded by the optimizer with other rounding than the library's call, sin and cos
// merged into a sincos with other bits), the optimized kernel never built in the background,
// or built and not adopted.
TEST_CASE("kernels: the quick kernel gives the optimized kernel's bits, on every held model", "[codegen][kernel]") {
    jit::JitOptions quick;
    quick.cache_dir = cache() + "/tiers";
    quick.quick = true;
    int models = 0;
    for (const char* folder : {"/examples/models", "/tests/codegen/models", "/tests/rigid/models"})
        for (const auto& entry : std::filesystem::directory_iterator(std::string(PHYNJO_SOURCE_DIR) + folder)) {
            if (entry.path().extension() != ".lag") continue;
            INFO(entry.path().filename().string());
            jit::CompiledModel c;
            try {
                c = jit::compile_model_file(entry.path().string(), quick);
            } catch (const jit::ModelError&) {
                continue; // a model meant to fail
            }
            REQUIRE(c.quick);
            const auto optimized = jit::optimized_kernel(c, 300);
            REQUIRE(optimized);
            CHECK(*optimized == c.optimized_path);
            compare(kernel_system(KernelParameters(ModelKernel::load(c.kernel_path))),
                    kernel_system(KernelParameters(ModelKernel::load(*optimized))), static_cast<std::uint32_t>(++models));
            // the next compile of the model returns the optimized kernel
            const jit::CompiledModel again = jit::compile_model_file(entry.path().string(), quick);
            CHECK((again.cache_hit && !again.quick && again.kernel_path == *optimized));
        }
    CHECK(models >= 40);
}

// Bugs caught: a kernel's failure lost at the C boundary (a NaN, or a generic error where the
// typed one is documented), the kernel unloaded while a system still calls it, parameters by
// an unknown name accepted.
TEST_CASE("kernels: typed errors through the C table, and the kernel outlives its systems", "[codegen][kernel][errors]") {
    LagrangianSystem sys;
    {
        const auto k = kernel_of(PHYNJO_SOURCE_DIR "/examples/models/double_pendulum.lag");
        KernelParameters P(k);
        P.set("m1", 0);
        P.set("m2", 0);
        CHECK_THROWS_WITH(P.set("mass", 1), Catch::Contains("no parameter 'mass'") && Catch::Contains("m1, m2, l1, l2, g"));
        CHECK_THROWS_AS(P.set("m1", std::nan("")), std::invalid_argument);
        sys = kernel_system(P);
    } // the kernel and P go out of scope: the system holds both
    std::vector<double> q{0.1, 0.2}, v{0, 0}, a(2);
    CHECK_THROWS_AS(sys.accelerations(0, q, v, a), SingularMassMatrix);
    double E = 0;
    std::vector<double> g;
    CHECK_FALSE(sys.accelerations_energy_guards(0, q, v, a, E, g));
    CHECK_THROWS_AS(ModelKernel::load("/nonexistent/kernel.so"), KernelError);
    CHECK_THROWS_WITH(ModelKernel::load(PHYNJO_SOURCE_DIR "/README.md"), Catch::Contains("README.md"));
}

// Bugs caught: a run through a kernel that differs from the same run on the CMake-built model
// (the integrator seeing another system), live parameters not followed.
TEST_CASE("kernels: a constrained run and a live input, the same world as the model's", "[codegen][kernel]") {
    const auto k = kernel_of(PHYNJO_SOURCE_DIR "/examples/models/four_bar.lag");
    KernelParameters P(k);
    four_bar::Parameters Q;
    World a = make_lagrangian_world(kernel_live_system(&P)), b = four_bar::make_world(Q);
    Stepper sa(integrator_workflow(kernel_live_system(&P), a, "rattle", "test")), sb(four_bar::live_workflow(&Q, b, "rattle"));
    for (int step = 0; step < 2000; ++step) {
        if (step == 1000) P.set("tau", 2.0), Q.tau = 2.0; // a motor switched on mid-run
        sa.step(a, 1e-3);
        sb.step(b, 1e-3);
    }
    CHECK(a == b);
}
