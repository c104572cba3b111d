// 300 capsules (radius 2.5 cm around a 10 cm segment, 0.2 kg) poured into a 0.8 × 0.8 m box:
// a lattice 12 layers high (16 cm apart, each capsule turned at random) let go at once, whose
// layers land one after another, and settle. e = 0.1 above 0.2 m/s, μ = 0.4, dt = 1/240 s,
// 20 velocity iterations, 5 s, nothing put to sleep. Writes capsule_pour_history.csv (t,
// kinetic energy, largest speed, deepest overlap) and capsule_pour.html.
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
    const int nx = 5, nz = 5, layers = 12;
    const double a = 0.16, side = 0.8, dt = 1.0 / 240, t_end = 5, r = 0.025, half = 0.05;
    std::mt19937 rng(20261205);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    std::normal_distribution<double> gauss;
    Registry reg;
    std::vector<RigidInit> init;
    for (int j = 0; j < layers; ++j)
        for (int i = 0; i < nx; ++i)
            for (int k = 0; k < nz; ++k) {
                reg.add("c" + std::to_string(init.size()));
                RigidInit s;
                s.position = {(i + 0.5) * a + jitter(rng), 0.3 + j * a + jitter(rng), (k + 0.5) * a + jitter(rng)};
                s.orientation = Quaternion{gauss(rng), gauss(rng), gauss(rng), gauss(rng)}.normalized();
                init.push_back(s);
            }
    World w = make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_capsule(0.2, r, half)), init,
                               contact_cache_fields(32));
    const std::vector<Plane> planes{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -side}, Plane{{0, 0, 1}, 0},
                                    Plane{{0, 0, -1}, -side}};
    Stepper stepper = contact_stepper(w, planes, ContactMaterial{restitution_curve(0.1, 0.2), constant_curve(0.4)});
    Recorder page = rigid_page(w, planes, "300 capsules poured into a box (e = 0.1, mu = 0.4, nothing asleep)");
    if (!run_settling(w, stepper, dt, t_end, page, dir / "capsule_pour_history.csv", planes)) return 1;
    std::size_t rest = 0;
    double top = 0;
    for (Index i = 0; i < w.size(); ++i) {
        rest += velocity(w, i).norm() < 0.05;
        top = std::max(top, w.at(kY, i));
    }
    std::printf("capsule pour: %zu capsules in a %.1f m box, %g s: %.1f%% slower than 0.05 m/s, deepest overlap %.3f mm, "
                "highest centre %.2f m\n",
                w.size(), side, t_end, 100.0 * double(rest) / double(w.size()), 1e3 * max_penetration(w, all_bodies(w), planes),
                top);
    page.write_html(dir / "capsule_pour.html");
}
