#pragma once
/// \file
/// Adaptive velocity Verlet for N-body gravity. Order 2; symplectic only at a fixed step.
#include "phynjo/runtime/core/executor.hpp"
#include "phynjo/runtime/particles/nbody.hpp"

namespace phynjo::runtime {

/// Adaptive velocity Verlet (kick-drift-kick with the accelerations of the end of one step
/// reused at the start of the next) with step control:
///   dt = clamp(η · min_i (|v_i| + √(ε|a_i|)) / |a_i|, dt_min, dt_max),
/// i.e. a fraction η of the time in which a body's velocity changes by itself (or, for a
/// body at rest, in which it falls through the softening length). Order 2; symplectic
/// only at a fixed step.
/// Reference: L. Verlet, Phys. Rev. 159, 98 (1967); the criterion follows the
/// velocity/acceleration time scale of S. Aarseth, Gravitational N-Body Simulations (2003), §2.
class AdaptiveVerlet {
public:
    struct Options {
        double eta = 0.01;
        double dt_min = 1e-9;
        double dt_max = 1.0;
        int partitions = 1;
    };
    AdaptiveVerlet(const NBodyGravity& g, std::shared_ptr<const Layout> layout, Options options, Executor* executor = nullptr);
    /// Computes the accelerations of `w` (call once before the first step, and after
    /// changing positions by hand).
    void prepare(World& w);
    /// One step with a chosen dt; returns the dt used.
    double step(World& w);
    /// The step the controller would choose now.
    [[nodiscard]] double choose_dt(const World& w) const;

private:
    NBodyGravity g_;
    Options options_;
    Interpreter<World> accelerations_, kick_, drift_;
};

} // namespace phynjo::runtime
