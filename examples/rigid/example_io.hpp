// Shared by the rigid-body examples: the output directory from `--output DIR` (default "."),
// and the settling run of the piles.
#pragma once
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

inline std::filesystem::path output_dir(int argc, char** argv) {
    std::filesystem::path dir = ".";
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], "--output") == 0) dir = argv[i + 1];
    std::filesystem::create_directories(dir);
    return dir;
}

/// Steps `w` to t_end, every state into `page` and every 4th step's t, kinetic energy (J),
/// largest speed (m/s) and deepest overlap (mm) into the CSV `history`; false, having printed
/// why, when the run stopped early.
inline bool run_settling(phynjo::runtime::World& w, phynjo::runtime::Stepper& stepper, double dt, double t_end,
                         phynjo::runtime::Recorder& page, const std::filesystem::path& history,
                         std::span<const phynjo::runtime::Plane> planes) {
    using namespace phynjo::runtime;
    std::ofstream hist(history);
    hist << "t,kinetic_energy,max_speed,max_penetration_mm\n";
    const int steps = static_cast<int>(std::lround(t_end / dt));
    for (int s = 0; s <= steps; ++s) {
        page.capture(w);
        if (s % 4 == 0) {
            double vmax = 0;
            for (Index i = 0; i < w.size(); ++i) vmax = std::max(vmax, velocity(w, i).norm());
            hist << s * dt << ',' << rigid_kinetic_energy(w) << ',' << vmax << ','
                 << 1e3 * max_penetration(w, all_bodies(w), planes) << '\n';
        }
        if (s < steps) {
            const RunReport rep = stepper.run_guarded(w, dt, 1);
            if (!rep.completed) {
                std::printf("stopped: %s\n", rep.reason.c_str());
                return false;
            }
        }
    }
    return true;
}
