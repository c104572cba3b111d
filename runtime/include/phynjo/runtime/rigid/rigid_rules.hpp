#pragma once
/// \file
/// The rules of a rigid world — the runes `driftTrans`, `driftRot` and `kickForce3D` —
/// each with its domain: translation drift, rotation drift, and the force/torque kick that
/// integrates Euler's equations. integrators/rigid_leapfrog.hpp composes them.
#include "phynjo/runtime/rigid/rigid_world.hpp"

namespace phynjo::runtime {

/// How drift_rot turns ω into a new orientation.
enum class RotationUpdate {
    exponential,  ///< Q' = exp(½ h ω_W) ⊗ Q: exact for constant ω (default)
    first_order,  ///< integrateQuat: Q + ½ h Q ⊗ (0, ω_B), renormalised; order 1
};

/// How kick_force3d integrates Euler's equations over its step h.
enum class GyroscopicScheme {
    /// ω_B' = ω_B + h I⁻¹(τ_B − ω̄ × I ω̄), ω̄ = ½(ω_B + ω_B'), solved by fixed-point
    /// iteration. Symmetric, order 2; with τ = 0 it conserves |I ω_B| and ½ ω_B·I ω_B exactly
    /// (both are quadratic invariants, which the implicit midpoint rule preserves).
    implicit_midpoint,
    /// The explicit step ω_B' = ω_B + h I⁻¹(τ_B − ω_B × I ω_B). Order 1; energy drifts.
    explicit_euler,
};

/// driftTrans: r ← r + c·dt·v for `bodies`. Domain: x, y, z of bodies; reads v. Symplectic.
NumericRule drift_trans(const ComponentSet& bodies, double c, const std::shared_ptr<const Layout>& layout);

/// driftRot: Q ← Q rotated by ω_W over c·dt (ω_W held fixed, so ω_B is unchanged and so are
/// the rotational energy and |L|). Domain: qw, qx, qy, qz of bodies; reads ω.
NumericRule drift_rot(const ComponentSet& bodies, double c, const std::shared_ptr<const Layout>& layout,
                      RotationUpdate update = RotationUpdate::exponential);

/// kickForce3D: with (F, τ_W) = force(state, c) and h = c·dt,
///   v ← v + h F/m,   ω_B ← Euler's equations over h with τ_B = Rᵀ τ_W,   ω_W ← R ω_B.
/// Domain: vx, vy, vz, wx, wy, wz of bodies; reads the whole state (a Force3D may read
/// anything). Throws ConvergenceError if the implicit midpoint iteration does not converge
/// (|h ω| far beyond 1).
NumericRule kick_force3d(const Force3D& force, const ComponentSet& bodies, double c,
                         const std::shared_ptr<const Layout>& layout,
                         GyroscopicScheme scheme = GyroscopicScheme::implicit_midpoint);

} // namespace phynjo::runtime
