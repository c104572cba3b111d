#pragma once
/// \file
/// Newtonian N-body gravity with Plummer softening on a 3-D particle world, as rules.
///
/// a_i = G Σ_{j≠i} m_j (r_j − r_i) / (|r_j − r_i|² + ε²)^{3/2}; every pair is visited once
/// (Newton's third law), so total momentum is conserved to round-off.
#include "phynjo/runtime/forces.hpp"
#include "phynjo/runtime/integrators.hpp"

namespace phynjo::runtime {

/// Field ids of a particle world (make_particles): positions (m), velocities (m/s), mass
/// (kg), accelerations (m/s²).
inline constexpr FieldId kX = 0, kY = 1, kZ = 2, kVX = 3, kVY = 4, kVZ = 5, kMass = 6, kAX = 7, kAY = 8, kAZ = 9;

/// A 3-D particle world over `components`. With partitions > 1 it also holds one set of
/// partial accelerations per partition (fields ax#k, ay#k, az#k), so that the pair sum can
/// be split into parallel branches with disjoint domains.
World make_particles(const Registry& components, int partitions = 1);

struct NBodyGravity {
    double G = 1.0;          ///< gravitational constant, m³/(kg·s²) (6.674e-11 in SI)
    double softening = 1e-3; ///< Plummer ε, m
};

/// a ← gravity(r): one rule (partitions = 1), or par(partial_0 … partial_{P−1}) then a
/// combine rule; partial k handles a contiguous block of rows of the pair triangle chosen so
/// that every block has the same number of pairs. The result does not depend on the thread
/// count that runs the par (only on `partitions`).
NumericWorkflow nbody_accelerations(const NBodyGravity& g, const std::shared_ptr<const Layout>& layout,
                                    int partitions = 1);
/// v ← v + c·dt·a.
NumericRule kick3d(double c, const std::shared_ptr<const Layout>& layout);
/// r ← r + c·dt·v.
NumericRule drift3d(double c, const std::shared_ptr<const Layout>& layout);

/// v_c ← v_c + c·dt·F_c/m_c for every component, F from a Force3D (its torque is for rigid
/// bodies and ignored on particles). Domain: the velocities.
NumericRule kick3d(const Force3D& force, double c, const std::shared_ptr<const Layout>& layout);

/// The State3D view of a particle world.
State3D state3d(const World& particles);

/// Leapfrog DKD for N-body: drift(½) · accelerations · kick(1) · drift(½). One force
/// evaluation per step. Order 2, symplectic.
NumericWorkflow nbody_leapfrog(const NBodyGravity& g, const std::shared_ptr<const Layout>& layout, int partitions = 1);

/// Energy Σ ½ m v² − Σ_{i<j} G m_i m_j / √(r² + ε²), J (the softened potential).
double nbody_energy(const World& particles, const NBodyGravity& g);
/// Total momentum Σ m v, kg·m/s.
Vec3 nbody_momentum(const World& particles);

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
