#pragma once
/// \file
/// The rigid world: a body's state (RigidState) as fields (position, orientation quaternion,
/// velocity and world angular velocity per component, with the mass properties), views of
/// it, and its conserved quantities.
///
/// Equations (world frame W, body frame B, R = R(Q) maps B → W):
///   ṙ = v,   m v̇ = F,   Q̇ = ½ (0, ω_W) ⊗ Q,
///   I_B ω̇_B + ω_B × (I_B ω_B) = τ_B,   ω_B = Rᵀ ω_W,   τ_B = Rᵀ τ_W   (Euler's equations).
#include "phynjo/runtime/particles/particles3d.hpp"
#include "phynjo/runtime/rigid/rigid_body.hpp"

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::runtime {

/// Field ids of a rigid world: the first seven are the particle world's (x, y, z, vx, vy,
/// vz, m: particles3d.hpp), so Force3D and kick3d read both alike; then, by name:
inline constexpr FieldId kWX = kMass + 1, kWY = kWX + 1, kWZ = kWY + 1; ///< world angular velocity, rad/s
inline constexpr FieldId kQW = kWZ + 1, kQX = kQW + 1, kQY = kQX + 1, kQZ = kQY + 1; ///< orientation (unit quaternion)
inline constexpr FieldId kInvMass = kQZ + 1; ///< 1/m, 1/kg
inline constexpr FieldId kIxx = kInvMass + 1, kIyy = kIxx + 1, kIzz = kIyy + 1, kIxy = kIzz + 1, kIxz = kIxy + 1,
                         kIyz = kIxz + 1; ///< body inertia, kg·m²
inline constexpr FieldId kInvIxx = kIyz + 1, kInvIyy = kInvIxx + 1, kInvIzz = kInvIyy + 1, kInvIxy = kInvIzz + 1,
                         kInvIxz = kInvIxy + 1, kInvIyz = kInvIxz + 1; ///< body inverse inertia, 1/(kg·m²)
inline constexpr FieldId kRadius = kInvIyz + 1; ///< collision sphere radius, m (0: none)
inline constexpr FieldId kRigidFieldCount = kRadius + 1;
/// The field names of a rigid world, in id order (the extra fields follow them).
inline constexpr std::array<std::string_view, kRigidFieldCount> kRigidFields{
    "x",  "y",  "z",  "vx", "vy",    "vz",  "m",   "wx",  "wy",  "wz",   "qw",   "qx",   "qy",   "qz",
    "inv_m", "Ixx", "Iyy", "Izz", "Ixy", "Ixz", "Iyz", "iIxx", "iIyy", "iIzz", "iIxy", "iIxz", "iIyz", "radius"};
static_assert(kRigidFields[kX] == "x" && kRigidFields[kMass] == "m" && kRigidFields[kWX] == "wx" &&
              kRigidFields[kQW] == "qw" && kRigidFields[kInvMass] == "inv_m" && kRigidFields[kIxx] == "Ixx" &&
              kRigidFields[kInvIxx] == "iIxx" && kRigidFields[kRadius] == "radius");

/// The fields a rigid world holds after kRigidFields when any of its bodies is a box or a
/// capsule (a world of spheres has none, so its layout and hashes stay those of spheres):
/// shape (Shape as a number: 0 sphere, 1 box, 2 capsule) and hx, hy, hz (RigidBody::half_extents).
inline constexpr std::array<std::string_view, 4> kShapeFields{"shape", "hx", "hy", "hz"};
/// The id of the field "shape" in `layout` (hx, hy, hz follow it), or −1 for a world of spheres.
int shape_field(const Layout& layout);
/// The shape of body c (a sphere in a world without shape fields).
Shape shape_of(const World& w, Index c);
/// RigidBody::half_extents of body c, m (zero in a world without shape fields).
Eigen::Vector3d half_extents(const World& w, Index c);

/// A rigid world over `components` with one body each (and optional initial states, else
/// at rest at the origin), with kShapeFields when a body is not a sphere, followed by
/// `extra_fields` (e.g. contact_cache_fields()).
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

} // namespace phynjo::runtime
