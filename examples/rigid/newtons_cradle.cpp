// Newton's cradle between two walls: five touching balls, the first struck at 1 m/s, e = 1.
// Gauss–Seidel collisions pass the impact down the row, the last ball leaves, bounces off the
// wall and comes back, and so on. Writes newtons_cradle.csv (t, x of each ball, v of each ball).
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const int n = 5;
    const double r = 0.05, dt = 1e-3, t_end = 3;
    Registry reg;
    std::vector<RigidInit> init(n);
    for (int i = 0; i < n; ++i) {
        reg.add("ball" + std::to_string(i));
        init[static_cast<std::size_t>(i)].position = {2 * r * i, 0, 0};
    }
    init[0].position.x() = -0.25;
    init[0].velocity = {1, 0, 0};
    World w = make_rigid_world(reg, std::vector<RigidBody>(n, RigidBody::solid_sphere(0.2, r)), init, contact_cache_fields());
    const std::vector<Plane> walls{Plane{{1, 0, 0}, -0.5}, Plane{{-1, 0, 0}, -0.9}}; // x = −0.5 and x = 0.9
    Stepper stepper(rigid_contact_step(Force3D{}, all_bodies(w), walls, ContactMaterial{constant_curve(1), constant_curve(0)},
                                       {}, w.layout_ptr()));
    Recorder page({.title = "Newton's cradle: five rigid balls, e = 1, between walls"});
    page.add_rigid_bodies(w, all_bodies(w));
    page.add_planes(walls);
    std::ofstream csv(dir / "newtons_cradle.csv");
    csv << "t";
    for (int i = 0; i < n; ++i) csv << ",x" << i;
    for (int i = 0; i < n; ++i) csv << ",v" << i;
    csv << '\n';
    const double p0 = total_linear_momentum(w).x(), e0 = rigid_kinetic_energy(w);
    double worst_e = 0;
    int handovers = 0;
    int moving_prev = 0;
    const int steps = static_cast<int>(t_end / dt);
    for (int k = 0; k <= steps; ++k) {
        page.capture(w);
        csv << k * dt;
        for (Index i = 0; i < n; ++i) csv << ',' << w.at(kX, i);
        for (Index i = 0; i < n; ++i) csv << ',' << w.at(kVX, i);
        csv << '\n';
        int moving = -1, count = 0;
        for (Index i = 0; i < n; ++i)
            if (std::abs(w.at(kVX, i)) > 1e-9) {
                moving = static_cast<int>(i);
                ++count;
            }
        if (count == 1 && moving != moving_prev) {
            ++handovers;
            moving_prev = moving;
        }
        worst_e = std::max(worst_e, std::abs(rigid_kinetic_energy(w) - e0) / e0);
        if (k < steps) stepper.step(w, dt);
    }
    std::printf("Newton's cradle: %d balls, e = 1, between walls, %g s\n", n, t_end);
    std::printf("  %d hand-overs from end to end; initial momentum %.3f kg m/s; largest energy error %.1e\n", handovers, p0,
                worst_e);
    page.write_html(dir / "newtons_cradle.html");
    std::printf("  wrote %s and %s\n", (dir / "newtons_cradle.csv").c_str(), (dir / "newtons_cradle.html").c_str());
}
