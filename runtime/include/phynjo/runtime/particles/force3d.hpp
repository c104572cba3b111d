#pragma once
/// \file
/// The forces DSL in 3-D: a Force3D gives each component a force and a torque (world frame)
/// from a State3D view of a particle or rigid world; force fields add and scale.
#include "phynjo/runtime/core/component.hpp"

#include <array>
#include <functional>
#include <span>
#include <utility>
#include <vector>

namespace phynjo::runtime {

using Vec3 = std::array<double, 3>;

/// The 3-D state a Force3D reads: positions, velocities, world angular velocities and
/// masses per component (a particle world, or the rigid-body state of the next module).
struct State3D {
    std::span<const double> x, y, z, vx, vy, vz, m;
    std::span<const double> wx = {}, wy = {}, wz = {};          ///< rigid worlds only, rad/s
    std::span<const double> qw = {}, qx = {}, qy = {}, qz = {}; ///< rigid worlds only
};

/// A force field in 3-D: for a component, its force (N, world frame) and torque (N·m, world
/// frame). Adds and scales like Force1D.
class Force3D {
public:
    using Field = std::function<std::pair<Vec3, Vec3>(const State3D&, Index)>;
    Force3D() = default;
    explicit Force3D(Field f) : fields_{std::move(f)} {}

    /// (0, −m g, 0): gravity along −y.
    static Force3D gravity(double g);
    /// Hooke spring between i and j: F_i = −k(|r_i − r_j| − l0) r̂_ij, F_j = −F_i.
    static Force3D spring(Index i, Index j, double k, double rest_length);
    /// −γ v.
    static Force3D drag(double gamma);

    [[nodiscard]] std::pair<Vec3, Vec3> operator()(const State3D& s, Index c) const;
    friend Force3D operator+(Force3D a, const Force3D& b);
    friend Force3D operator*(double s, Force3D f);

private:
    std::vector<Field> fields_;
    double scale_ = 1;
};

} // namespace phynjo::runtime
