#pragma once
/// \file
/// Rigid bodies on flat state: a RigidBody (mass, body-frame inertia tensor, optional
/// collision-sphere radius), the rigid world that holds the seed's RigidState as fields
/// (position, orientation quaternion, velocity and world angular velocity per component), and
/// the runes `drift_trans`, `drift_rot` and `kick_force3d` as rules with domains.
///
/// Equations (world frame W, body frame B, R = R(Q) maps B → W):
///   ṙ = v,   m v̇ = F,   Q̇ = ½ (0, ω_W) ⊗ Q,
///   I_B ω̇_B + ω_B × (I_B ω_B) = τ_B,   ω_B = Rᵀ ω_W,   τ_B = Rᵀ τ_W   (Euler's equations).
#include "phynjo/runtime/nbody.hpp"
#include "phynjo/runtime/quaternion.hpp"

#include <Eigen/Core>

#include <string_view>

namespace phynjo::runtime {

/// Field ids of a rigid world. 0…6 coincide with the particle world (x, y, z, vx, vy, vz, m),
/// so Force3D fields and kick3d read both alike.
inline constexpr FieldId kWX = 7, kWY = 8, kWZ = 9;                  ///< world angular velocity, rad/s
inline constexpr FieldId kQW = 10, kQX = 11, kQY = 12, kQZ = 13;     ///< orientation (unit quaternion)
inline constexpr FieldId kInvMass = 14;                              ///< 1/m, 1/kg
inline constexpr FieldId kIxx = 15, kIyy = 16, kIzz = 17, kIxy = 18, kIxz = 19, kIyz = 20; ///< body inertia, kg·m²
inline constexpr FieldId kInvIxx = 21, kInvIyy = 22, kInvIzz = 23, kInvIxy = 24, kInvIxz = 25,
                         kInvIyz = 26;                               ///< body inverse inertia, 1/(kg·m²)
inline constexpr FieldId kRadius = 27;                               ///< collision sphere radius, m (0: none)
inline constexpr FieldId kRigidFieldCount = 28;

/// Mass properties of one body and its collision sphere.
struct RigidBody {
    double mass = 1;                                       ///< kg
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity(); ///< about the centre of mass, body frame, kg·m²
    double radius = 0;                                     ///< collision sphere, m; 0 for none

    /// A solid sphere: I = (2/5) m r² 𝟙, with collision radius r.
    static RigidBody solid_sphere(double mass, double radius);
    /// A solid box with half-extents (a, b, c): I = m/3 diag(b²+c², a²+c², a²+b²); no sphere.
    static RigidBody box(double mass, const Eigen::Vector3d& half_extents);
    /// Throws InvalidBody naming `label` for a mass that is not positive and finite, an
    /// inertia tensor that is not finite, symmetric and positive definite, principal moments
    /// that violate the triangle inequality I₁ + I₂ ≥ I₃ (no mass distribution has them), or
    /// a negative or non-finite radius.
    void validate(std::string_view label) const;
};

/// The initial state of one body (the seed's insertRigid).
struct RigidInit {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();         ///< centre of mass, m
    Quaternion orientation = Quaternion::identity();            ///< must be unit (within 1e-6)
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();         ///< m/s
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero(); ///< world frame, rad/s
};

/// A rigid world over `components` with one body each (and optional initial states, else
/// at rest at the origin), followed by `extra_fields` (e.g. contact_cache_fields()).
/// Validates every body and orientation: throws InvalidBody naming the component.
World make_rigid_world(const Registry& components, const std::vector<RigidBody>& bodies,
                       const std::vector<RigidInit>& init = {}, const std::vector<std::string>& extra_fields = {});

/// Every component of a rigid world.
ComponentSet all_bodies(const World& w);

// ---- views ----------------------------------------------------------------------------------
Eigen::Vector3d position(const World& w, Index c);
Eigen::Vector3d velocity(const World& w, Index c);
Eigen::Vector3d angular_velocity(const World& w, Index c);
Quaternion orientation(const World& w, Index c);
void set_position(World& w, Index c, const Eigen::Vector3d& r);
void set_velocity(World& w, Index c, const Eigen::Vector3d& v);
void set_angular_velocity(World& w, Index c, const Eigen::Vector3d& omega);
/// Stores a unit quaternion; throws InvalidBody if ‖q‖ differs from 1 by more than 1e-6.
void set_orientation(World& w, Index c, const Quaternion& q);
/// I_B and I_B⁻¹ as stored.
Eigen::Matrix3d body_inertia(const World& w, Index c);
Eigen::Matrix3d body_inverse_inertia(const World& w, Index c);
/// I_W = R I_B Rᵀ, kg·m².
Eigen::Matrix3d world_inertia(const World& w, Index c);
/// Spin angular momentum I_W ω_W about the centre of mass, kg·m²/s.
Eigen::Vector3d spin_angular_momentum(const World& w, Index c);
/// Σ (r × m v + I_W ω_W) about the origin, kg·m²/s.
Eigen::Vector3d total_angular_momentum(const World& w);
/// Σ m v, kg·m/s.
Eigen::Vector3d total_linear_momentum(const World& w);
/// Σ ½ m v² + ½ ω_W · I_W ω_W, J.
double rigid_kinetic_energy(const World& w);
/// Rotational part ½ ω_B · I_B ω_B of one body, J.
double rotational_energy(const World& w, Index c);

/// The State3D view of a rigid world (with angular velocities and orientations).
State3D rigid_state3d(const World& w);

// ---- runes ----------------------------------------------------------------------------------

/// How drift_rot turns ω into a new orientation.
enum class RotationUpdate {
    exponential,  ///< Q' = exp(½ h ω_W) ⊗ Q: exact for constant ω (default)
    first_order,  ///< the seed's integrateQuat: Q + ½ h Q ⊗ (0, ω_B), renormalised; order 1
};

/// How kick_force3d integrates Euler's equations over its step h.
enum class GyroscopicScheme {
    /// ω_B' = ω_B + h I⁻¹(τ_B − ω̄ × I ω̄), ω̄ = ½(ω_B + ω_B'), solved by fixed-point
    /// iteration. Symmetric, order 2; with τ = 0 it conserves |I ω_B| and ½ ω_B·I ω_B exactly
    /// (both are quadratic invariants, which the implicit midpoint rule preserves).
    implicit_midpoint,
    /// The seed's explicit step ω_B' = ω_B + h I⁻¹(τ_B − ω_B × I ω_B). Order 1; energy drifts.
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

/// The rigid-body Strang splitting
///   drift_trans(½) · drift_rot(½) · kick_force3d(1) · drift_rot(½) · drift_trans(½):
/// one force evaluation per step, order 2 (first order with the seed's explicit schemes).
NumericWorkflow rigid_leapfrog(const Force3D& force, const ComponentSet& bodies,
                               const std::shared_ptr<const Layout>& layout,
                               GyroscopicScheme scheme = GyroscopicScheme::implicit_midpoint);

} // namespace phynjo::runtime
