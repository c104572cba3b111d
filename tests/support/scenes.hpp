#pragma once
// Scenes several tests share: an N-body cluster and a box of spheres between walls.
#include "phynjo/runtime/runtime.hpp"

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace phynjo::test {

/// n bodies at random in the cube [-1, 1]³, velocity components up to ±speed and masses
/// (mass_base ± 0.5)/n, drawn in that order from std::mt19937(seed).
inline runtime::World random_cluster(int n, std::uint32_t seed, int partitions, double speed = 0.3,
                                     double mass_base = 1.0) {
    using namespace runtime;
    Registry r;
    for (int i = 0; i < n; ++i) r.add("star" + std::to_string(i));
    World w = make_particles(r, partitions);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (Index i = 0; i < static_cast<Index>(n); ++i) {
        w.at(kX, i) = u(rng);
        w.at(kY, i) = u(rng);
        w.at(kZ, i) = u(rng);
        w.at(kVX, i) = speed * u(rng);
        w.at(kVY, i) = speed * u(rng);
        w.at(kVZ, i) = speed * u(rng);
        w.at(kMass, i) = (mass_base + u(rng) * 0.5) / n;
    }
    return w;
}

/// nx·ny·nz solid spheres (1 kg, radius 0.05 m) at origin + spacing ⊙ (i, j, k), each
/// coordinate moved by up to ±jitter and, with `spin`, given angular velocities up to ±jitter
/// rad/s, drawn from std::mt19937(seed); with the contact warm-start fields.
struct SphereGrid {
    int nx = 4, ny = 4, nz = 4;
    Eigen::Vector3d origin{0.07, 0.1, 0.07};
    Eigen::Vector3d spacing{0.13, 0.13, 0.13};
    double jitter = 0.01;
    std::uint32_t seed = 7;
    bool spin = false;
};
inline runtime::World sphere_grid(const SphereGrid& g) {
    using namespace runtime;
    Registry reg;
    std::vector<RigidInit> init;
    std::mt19937 rng(g.seed);
    std::uniform_real_distribution<double> jitter(-g.jitter, g.jitter);
    for (int i = 0; i < g.nx; ++i)
        for (int j = 0; j < g.ny; ++j)
            for (int k = 0; k < g.nz; ++k) {
                reg.add("s" + std::to_string(init.size()));
                RigidInit s;
                s.position = {g.origin.x() + g.spacing.x() * i + jitter(rng), g.origin.y() + g.spacing.y() * j + jitter(rng),
                              g.origin.z() + g.spacing.z() * k + jitter(rng)};
                if (g.spin) s.angular_velocity = {jitter(rng), jitter(rng), jitter(rng)};
                init.push_back(s);
            }
    return make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_sphere(1, 0.05)), init,
                            contact_cache_fields());
}

/// nx·ny·nz bodies at origin + spacing ⊙ (i, j, k), in turn a box (half-extents 0.03–0.05 m),
/// a capsule (radius 0.025 m, half-length 0.02 m) and a sphere (radius 0.04 m), 1 kg each,
/// turned at random, moved by up to ±jitter, drawn from std::mt19937(seed); with 32 warm-start
/// slots a body (a box's manifolds take up to four).
inline runtime::World shape_grid(int nx, int ny, int nz, const Eigen::Vector3d& origin, double spacing, double jitter,
                                 std::uint32_t seed) {
    using namespace runtime;
    Registry reg;
    std::vector<RigidBody> bodies;
    std::vector<RigidInit> init;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1), size(0.03, 0.05);
    std::normal_distribution<double> gauss;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) {
                const std::size_t n = init.size();
                reg.add("b" + std::to_string(n));
                if (n % 3 == 0)
                    bodies.push_back(RigidBody::solid_box(1, {size(rng), size(rng), size(rng)}));
                else if (n % 3 == 1)
                    bodies.push_back(RigidBody::solid_capsule(1, 0.025, 0.02));
                else
                    bodies.push_back(RigidBody::solid_sphere(1, 0.04));
                RigidInit s;
                s.position = origin + spacing * Eigen::Vector3d(i, j, k) + jitter * Eigen::Vector3d(u(rng), u(rng), u(rng));
                s.orientation = Quaternion{gauss(rng), gauss(rng), gauss(rng), gauss(rng)}.normalized();
                init.push_back(s);
            }
    return make_rigid_world(reg, bodies, init, contact_cache_fields(32));
}

/// The ground and four walls of the square box [0, side]² (x and z).
inline std::vector<runtime::Plane> box_walls(double side) {
    using runtime::Plane;
    return {Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -side}, Plane{{0, 0, 1}, 0},
            Plane{{0, 0, -1}, -side}};
}

} // namespace phynjo::test
