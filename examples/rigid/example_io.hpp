// Shared by the rigid-body examples: the output directory from `--output DIR` (default "."),
// the recorded run of every example and the settling run of the piles.
#pragma once
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <utility>
#include <vector>

inline std::filesystem::path output_dir(int argc, char** argv) {
    std::filesystem::path dir = ".";
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--output") == 0) dir = argv[i + 1];
    std::filesystem::create_directories(dir);
    return dir;
}

/// The contact step of the box and capsule examples: gravity (9.81 m/s², along −y), every body
/// against every other and the `planes`, 20 velocity iterations, `slop` (m) of depth left alone.
inline phynjo::runtime::Stepper contact_stepper(const phynjo::runtime::World& w, const std::vector<phynjo::runtime::Plane>& planes,
                                                const phynjo::runtime::ContactMaterial& material,
                                                double slop = phynjo::runtime::ContactOptions{}.slop) {
    using namespace phynjo::runtime;
    ContactOptions o;
    o.velocity_iterations = 20;
    o.slop = slop;
    return Stepper(rigid_contact_step(Force3D::gravity(9.81), all_bodies(w), planes, material, o, w.layout_ptr()));
}

/// A pyramid of 1 m cubes on the ground, `rows` rows, 1.02 m apart in a row, centred on x = 0:
/// their names ("b0", …, bottom row first) into `reg`, their starting states into `init`.
inline void box_pyramid_lattice(int rows, phynjo::runtime::Registry& reg, std::vector<phynjo::runtime::RigidInit>& init) {
    for (int r = 0; r < rows; ++r)
        for (int j = 0; j < rows - r; ++j) {
            reg.add("b" + std::to_string(init.size()));
            phynjo::runtime::RigidInit s;
            s.position = {(j - 0.5 * (rows - r - 1)) * 1.02, 0.5 + r, 0};
            init.push_back(s);
        }
}

/// A page titled `title` showing every body of `w` and the `planes`.
inline phynjo::runtime::Recorder rigid_page(const phynjo::runtime::World& w, std::span<const phynjo::runtime::Plane> planes,
                                            std::string title) {
    using namespace phynjo::runtime;
    Recorder page({.title = std::move(title)});
    page.add_rigid_bodies(w, all_bodies(w));
    page.add_planes(planes);
    return page;
}

/// Steps `w` to t_end (dt a step), every state into `page` and shown to observe(s, w) (s the
/// step index, 0 to the last) before the next step; false, having printed why, when the run
/// stopped early.
template <class Observe>
bool run_recorded(phynjo::runtime::World& w, phynjo::runtime::Stepper& stepper, double dt, double t_end,
                  phynjo::runtime::Recorder& page, Observe&& observe) {
    const int steps = static_cast<int>(std::lround(t_end / dt));
    for (int s = 0; s <= steps; ++s) {
        page.capture(w);
        observe(s, static_cast<const phynjo::runtime::World&>(w));
        if (s < steps) {
            const phynjo::runtime::RunReport rep = stepper.run_guarded(w, dt, 1);
            if (!rep.completed) {
                std::printf("stopped: %s\n", rep.reason.c_str());
                return false;
            }
        }
    }
    return true;
}

/// run_recorded, every 4th step's t, kinetic energy (J), largest speed (m/s) and deepest
/// overlap (mm) into the CSV `history`: the settling run of the piles.
inline bool run_settling(phynjo::runtime::World& w, phynjo::runtime::Stepper& stepper, double dt, double t_end,
                         phynjo::runtime::Recorder& page, const std::filesystem::path& history,
                         std::span<const phynjo::runtime::Plane> planes) {
    using namespace phynjo::runtime;
    std::ofstream hist(history);
    hist << "t,kinetic_energy,max_speed,max_penetration_mm\n";
    return run_recorded(w, stepper, dt, t_end, page, [&](int s, const World& x) {
        if (s % 4 != 0) return;
        double vmax = 0;
        for (Index i = 0; i < x.size(); ++i) vmax = std::max(vmax, velocity(x, i).norm());
        hist << s * dt << ',' << rigid_kinetic_energy(x) << ',' << vmax << ',' << 1e3 * max_penetration(x, all_bodies(x), planes)
             << '\n';
    });
}
