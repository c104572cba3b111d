// 343 cubes (side 0.1 m, 1 kg), each turned at random, dropped into a 1.4 × 1.4 m box with
// frictional walls, as in bench/bench_box_pile.cpp: e = 0.2 above 0.2 m/s, μ = 0.5,
// dt = 1/240 s, 20 velocity iterations, 6 s, nothing put to sleep. Writes
// box_pile_history.csv (t, kinetic energy, largest speed, deepest overlap), box_pile_final.csv
// (x, y, z, speed of every box at the end) and box_pile.html.
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
    const int n = 7;
    const double a = 0.2, side = n * a, dt = 1.0 / 240, t_end = 6;
    std::mt19937 rng(20261205);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    std::normal_distribution<double> gauss;
    Registry reg;
    std::vector<RigidInit> init;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < n; ++k) {
                reg.add("b" + std::to_string(init.size()));
                RigidInit s;
                s.position = {(i + 0.5) * a + jitter(rng), (j + 0.5) * a + 0.05 + jitter(rng), (k + 0.5) * a + jitter(rng)};
                s.orientation = Quaternion{gauss(rng), gauss(rng), gauss(rng), gauss(rng)}.normalized();
                init.push_back(s);
            }
    World w = make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_box(1, {0.05, 0.05, 0.05})), init,
                               contact_cache_fields(32));
    const std::vector<Plane> planes{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -side}, Plane{{0, 0, 1}, 0},
                                    Plane{{0, 0, -1}, -side}};
    Stepper stepper = contact_stepper(w, planes, ContactMaterial{restitution_curve(0.2, 0.2), constant_curve(0.5)}, 2e-5);
    Recorder page = rigid_page(w, planes, "343 boxes dropped into a box (e = 0.2, mu = 0.5, nothing asleep)");
    if (!run_settling(w, stepper, dt, t_end, page, dir / "box_pile_history.csv", planes)) return 1;
    std::ofstream fin(dir / "box_pile_final.csv");
    fin << "x,y,z,speed\n";
    std::size_t rest = 0;
    for (Index i = 0; i < w.size(); ++i) {
        const double v = velocity(w, i).norm();
        rest += v < 0.05;
        fin << w.at(kX, i) << ',' << w.at(kY, i) << ',' << w.at(kZ, i) << ',' << v << '\n';
    }
    std::printf("box pile: %zu boxes in a %.1f m box, %g s: %.1f%% slower than 0.05 m/s, deepest overlap %.3f mm\n", w.size(),
                side, t_end, 100.0 * double(rest) / double(w.size()), 1e3 * max_penetration(w, all_bodies(w), planes));
    page.write_html(dir / "box_pile.html");
}
