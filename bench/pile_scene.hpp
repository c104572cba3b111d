#pragma once
// The sphere pile of bench_pile.cpp (issue #5), shared with bench_viewer.cpp: N = n³ spheres,
// radius 0.05 m, 1 kg, a jittered cubic lattice at 25% volume fraction in a box whose four
// sides are walls, dropped onto the ground y = 0; e = 0.5 above 0.2 m/s, μ = 0.5, dt = 1/240 s.
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace {

using phynjo::runtime::Plane;

constexpr double kR = 0.05, kSphereMass = 1.0, kG = 9.81, kDt = 1.0 / 240, kE = 0.5, kMu = 0.5, kBounceVel = 0.2;
constexpr double kT = 2.0, kRest = 0.05;

struct Pile {
    int n = 0;
    double side = 0; // walls at 0 and side on x and z
    std::vector<Eigen::Vector3d> start;
    std::vector<Plane> planes;
};

inline Pile make_pile(int count) {
    Pile s;
    s.n = static_cast<int>(std::lround(std::cbrt(count)));
    const double a = kR * std::cbrt(16 * M_PI / 3); // (4/3 π r³)/a³ = 0.25
    s.side = s.n * a;
    std::mt19937 rng(20261123);
    const double room = 0.45 * (a - 2 * kR);
    std::uniform_real_distribution<double> jitter(-room, room);
    for (int j = 0; j < s.n; ++j)
        for (int i = 0; i < s.n; ++i)
            for (int k = 0; k < s.n; ++k)
                s.start.emplace_back((i + 0.5) * a + jitter(rng), (j + 0.5) * a + jitter(rng), (k + 0.5) * a + jitter(rng));
    s.planes = {Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -s.side}, Plane{{0, 0, 1}, 0},
                Plane{{0, 0, -1}, -s.side}};
    return s;
}

} // namespace
