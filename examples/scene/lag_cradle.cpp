// Newton's cradle made of five .lag pendulums (examples/models/bob_pendulum.lag, one instance
// each, pivots 2r apart so that the bobs touch at rest) in one scene with the contact rule:
// the first bob is released from −0.5 rad, and every impact hands the motion down the row to
// the last bob (e = 1, Gauss–Seidel collisions), as in the rigid cradle (newtons_cradle.cpp).
// The hand-overs come at T/4 + k T/2 with T the pendulum's exact period at that amplitude,
// T = 4 sqrt(l/g) K(sin(θ0/2)). Writes lag_cradle.csv (t, θ of each pendulum, x of each bob).
#include "bob_pendulum.hpp"
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const int n = 5;
    const double r = 0.05, l = 1, g = 9.81, th0 = -0.5, dt = 1e-3, t_end = 8;
    std::vector<ModelInstance> models;
    for (int i = 0; i < n; ++i) {
        bob_pendulum::Parameters P;
        P.r = r, P.l = l, P.g = g, P.px = 2 * r * i;
        models.push_back({"p" + std::to_string(i), bob_pendulum::system(P)});
    }
    Scene scene = make_scene(Registry{}, {}, {}, std::move(models), contact_cache_fields());
    const double q0[1] = {th0}, v0[1] = {0};
    set_model_state(scene, 0, q0, v0);
    Stepper stepper(scene_step(scene, Force3D{}, {}, ContactMaterial{constant_curve(1), constant_curve(0)}, {},
                               ModelIntegrator::rk4));
    // The exact period at amplitude θ0: K(k) = π / (2 AGM(1, sqrt(1 − k²))).
    const double k = std::sin(std::abs(th0) / 2);
    double a = 1, b = std::sqrt(1 - k * k);
    for (int i = 0; i < 30; ++i) {
        const double an = (a + b) / 2;
        b = std::sqrt(a * b);
        a = an;
    }
    const double T = 4 * std::sqrt(l / g) * std::numbers::pi / (2 * a);

    Recorder page({.title = "Newton's cradle of five .lag pendulums"});
    page.add_scene(scene);
    std::ofstream csv(dir / "lag_cradle.csv");
    csv << "t";
    for (int i = 0; i < n; ++i) csv << ",th" << i;
    for (int i = 0; i < n; ++i) csv << ",x" << i;
    csv << '\n';
    const double e0 = scene_energy(scene);
    double worst_e = 0, worst_dt = 0;
    int handovers = 0, moving_prev = 0;
    const int steps = static_cast<int>(t_end / dt);
    const double w_max = std::sqrt(2 * g / l * (1 - std::cos(th0)));
    for (int s = 0; s <= steps; ++s) {
        page.capture(scene.world);
        csv << s * dt;
        for (std::size_t i = 0; i < n; ++i) csv << ',' << model_q(scene, i)[0];
        for (std::size_t i = 0; i < n; ++i) csv << ',' << scene.world.at(kX, scene.models[i].spheres[0]);
        csv << '\n';
        // The end ball that swings (|θ'| above 1% of the largest angular speed, or off the bottom).
        int moving = -1;
        for (std::size_t i : {std::size_t{0}, std::size_t{n - 1}})
            if (std::abs(model_qdot(scene, i)[0]) > 0.01 * w_max || std::abs(model_q(scene, i)[0]) > 0.01)
                moving = static_cast<int>(i);
        if (moving >= 0 && moving != moving_prev) {
            const double want = T / 4 + handovers * T / 2;
            worst_dt = std::max(worst_dt, std::abs(s * dt - want));
            if (handovers < 4) std::printf("   hand-over %d at t = %.3f s (T/4 + %d T/2 = %.3f s)\n", handovers + 1, s * dt, handovers, want);
            ++handovers;
            moving_prev = moving;
        }
        worst_e = std::max(worst_e, std::abs(scene_energy(scene) - e0) / std::abs(e0 - 5 * (-g * l)));
        if (s < steps) stepper.step(scene.world, dt);
    }
    std::printf("Newton's cradle of five .lag pendulums (l = %g m, released from %g rad, e = 1, dt = %g s, %g s)\n", l, th0,
                dt, t_end);
    std::printf("  %d hand-overs, at most %.1f ms from T/4 + k T/2 (T = %.4f s exact); energy error %.1e of the swing's\n",
                handovers, 1e3 * worst_dt, T, worst_e);
    page.write_html(dir / "lag_cradle.html");
    std::printf("  wrote %s and %s\n", (dir / "lag_cradle.csv").c_str(), (dir / "lag_cradle.html").c_str());
}
