// A 20-row pyramid of 1 m cubes (1 kg, 1.02 m apart in a row: 210 boxes) standing on the
// ground for 10 s, nothing put to sleep: μ = 0.6, dt = 1/240 s, 20 velocity iterations (as in
// tests/rigid/test_boxes.cpp and bench/bench_box_pile.cpp). Writes box_pyramid_history.csv
// (t, the largest distance and turn of a box from where it started, the deepest overlap),
// box_pyramid_final.csv (x, y of every box at the start and at the end) and box_pyramid.html.
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const int rows = 20;
    const double dt = 1.0 / 240, t_end = 10;
    Registry reg;
    std::vector<RigidInit> init;
    box_pyramid_lattice(rows, reg, init);
    World w = make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_box(1, {0.5, 0.5, 0.5})), init,
                               contact_cache_fields(32));
    const std::vector<Plane> planes{Plane::ground()};
    Stepper stepper = contact_stepper(w, planes, ContactMaterial{restitution_curve(0, 0.05), constant_curve(0.6)}, 2e-5);
    Recorder page = rigid_page(w, planes, "A 20-row pyramid of 210 boxes standing 10 s (mu = 0.6, dt = 1/240 s, nothing asleep)");
    std::ofstream hist(dir / "box_pyramid_history.csv");
    hist << "t,largest_move_mm,largest_turn_deg,deepest_overlap_mm\n";
    double far = 0, turn = 0;
    const bool ran = run_recorded(w, stepper, dt, t_end, page, [&](int s, const World& x) {
        if (s % 24 != 0) return;
        far = 0, turn = 0;
        for (Index i = 0; i < x.size(); ++i) {
            far = std::max(far, (position(x, i) - init[i].position).norm());
            turn = std::max(turn, 2 * std::acos(std::min(1.0, std::abs(orientation(x, i).w))));
        }
        hist << s * dt << ',' << 1e3 * far << ',' << turn * 180 / M_PI << ',' << 1e3 * max_penetration(x, all_bodies(x), planes)
             << '\n';
    });
    if (!ran) return 1;
    std::ofstream fin(dir / "box_pyramid_final.csv");
    fin << "x0,y0,x,y\n";
    for (Index i = 0; i < w.size(); ++i)
        fin << init[i].position.x() << ',' << init[i].position.y() << ',' << w.at(kX, i) << ',' << w.at(kY, i) << '\n';
    std::printf("box pyramid: %zu boxes in %d rows, %g s: every box within %.2f mm and %.4f deg of where it started, "
                "deepest overlap %.3f mm\n",
                w.size(), rows, t_end, 1e3 * far, turn * 180 / M_PI, 1e3 * max_penetration(w, all_bodies(w), planes));
    page.write_html(dir / "box_pyramid.html");
}
