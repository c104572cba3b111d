// Three balls with restitution 0.9, 0.7 and 0.5 dropped from 1 m: each bounce reaches e² of
// the height before. The three contact rules have disjoint domains and run as one `par`.
// Writes bouncing_balls.csv (t, height of each ball above the ground) and bouncing_balls.html.
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <cstdio>
#include <fstream>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const double r = 0.05, h0 = 1.0, dt = 1e-4, t_end = 4;
    const double e[3] = {0.9, 0.7, 0.5};
    Registry reg;
    std::vector<RigidInit> init(3);
    for (int i = 0; i < 3; ++i) {
        reg.add("ball_e" + std::to_string(e[i]).substr(0, 3));
        init[static_cast<std::size_t>(i)].position = {0, h0 + r, 0.5 * i};
    }
    World w = make_rigid_world(reg, std::vector<RigidBody>(3, RigidBody::solid_sphere(0.1, r)), init, contact_cache_fields());
    const auto layout = w.layout_ptr();
    using W = NumericWorkflow;
    std::vector<W> grounds;
    for (Index i = 0; i < 3; ++i)
        grounds.push_back(W::run(contact_ground(ComponentSet{i}, ContactMaterial{restitution_curve(e[i], 0.05), constant_curve(0)},
                                                {}, layout)));
    const ComponentSet all = all_bodies(w);
    Stepper stepper(W::seq(W::run(kick_force3d(Force3D::gravity(9.81), all, 1, layout)), W::par(grounds),
                           W::run(drift_trans(all, 1, layout))));
    Recorder page({.title = "three balls bouncing: e = 0.9, 0.7, 0.5"});
    page.add_rigid_bodies(w, all);
    const Plane ground = Plane::ground();
    page.add_planes({&ground, 1});
    std::ofstream csv(dir / "bouncing_balls.csv");
    csv << "t,h_e0.9,h_e0.7,h_e0.5\n";
    std::vector<std::vector<double>> apex(3, std::vector<double>{h0});
    double prev[3] = {0, 0, 0};
    const int steps = static_cast<int>(t_end / dt);
    for (int n = 0; n <= steps; ++n) {
        page.capture(w);
        if (n % 20 == 0) csv << n * dt << ',' << w.at(kY, 0) - r << ',' << w.at(kY, 1) - r << ',' << w.at(kY, 2) - r << '\n';
        for (Index i = 0; i < 3; ++i) {
            const double vy = w.at(kVY, i);
            if (prev[i] > 0 && vy <= 0) apex[i].push_back(w.at(kY, i) - r);
            prev[i] = vy;
        }
        if (n < steps) stepper.step(w, dt);
    }
    std::printf("bouncing balls dropped from %g m, dt = %g s\n", h0, dt);
    for (int i = 0; i < 3; ++i) {
        std::printf("  e = %.1f (e^2 = %.2f): apex ratios", e[i], e[i] * e[i]);
        for (std::size_t k = 1; k < apex[static_cast<std::size_t>(i)].size() && k <= 4; ++k)
            std::printf(" %.4f", apex[static_cast<std::size_t>(i)][k] / apex[static_cast<std::size_t>(i)][k - 1]);
        std::printf("\n");
    }
    page.write_html(dir / "bouncing_balls.html");
    std::printf("  wrote %s and %s\n", (dir / "bouncing_balls.csv").c_str(), (dir / "bouncing_balls.html").c_str());
}
