// A pile of 1,000 spheres (r = 5 cm, 1 kg) dropped into a box with frictional walls, as in
// bench/bench_pile.cpp: e = 0.5 above 0.2 m/s, μ = 0.5, dt = 1/240 s, 3 s. Writes
// sphere_pile_history.csv (t, kinetic energy, largest speed, deepest overlap) and
// sphere_pile_final.csv (x, y, z, speed of every sphere at the end), and sphere_pile.html.
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const int n = 10;
    const double r = 0.05, a = r * std::cbrt(16 * M_PI / 3), side = n * a, dt = 1.0 / 240, t_end = 3;
    std::mt19937 rng(20261123);
    std::uniform_real_distribution<double> jitter(-0.45 * (a - 2 * r), 0.45 * (a - 2 * r));
    Registry reg;
    std::vector<RigidInit> init;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < n; ++k) {
                reg.add("s" + std::to_string(init.size()));
                RigidInit s;
                s.position = {(i + 0.5) * a + jitter(rng), (j + 0.5) * a + jitter(rng), (k + 0.5) * a + jitter(rng)};
                init.push_back(s);
            }
    World w = make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_sphere(1, r)), init,
                               contact_cache_fields());
    const std::vector<Plane> planes{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -side}, Plane{{0, 0, 1}, 0},
                                    Plane{{0, 0, -1}, -side}};
    Stepper stepper(rigid_contact_step(Force3D::gravity(9.81), all_bodies(w), planes,
                                       ContactMaterial{restitution_curve(0.5, 0.2), constant_curve(0.5)}, {}, w.layout_ptr()));
    Recorder page = rigid_page(w, planes, "1,000 spheres dropped into a box (e = 0.5, mu = 0.5)");
    if (!run_settling(w, stepper, dt, t_end, page, dir / "sphere_pile_history.csv", planes)) return 1;
    std::ofstream fin(dir / "sphere_pile_final.csv");
    fin << "x,y,z,speed\n";
    std::size_t rest = 0;
    double top = 0;
    for (Index i = 0; i < w.size(); ++i) {
        const double v = velocity(w, i).norm();
        rest += v < 0.05;
        top = std::max(top, w.at(kY, i) + r);
        fin << w.at(kX, i) << ',' << w.at(kY, i) << ',' << w.at(kZ, i) << ',' << v << '\n';
    }
    std::printf("sphere pile: %zu spheres in a %.2f m box, %g s\n", w.size(), side, t_end);
    std::printf("  at the end: %.1f%% slower than 0.05 m/s, deepest overlap %.3f mm, pile height %.2f m\n",
                100.0 * double(rest) / double(w.size()), 1e3 * max_penetration(w, all_bodies(w), planes), top);
    page.write_html(dir / "sphere_pile.html");
    std::printf("  wrote %s, %s and %s\n", (dir / "sphere_pile_history.csv").c_str(), (dir / "sphere_pile_final.csv").c_str(),
                (dir / "sphere_pile.html").c_str());
}
