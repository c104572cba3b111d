#pragma once
/// \file
/// A rigid body's mass properties (mass, body-frame inertia tensor), its collision shape
/// (a sphere, a box or a capsule), validated, and its initial state. The world that holds
/// bodies is rigid_world.hpp.
#include "phynjo/runtime/rigid/quaternion.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string_view>

namespace phynjo::runtime {

/// A body's collision shape, centred on its centre of mass, in its body frame.
enum class Shape : std::uint8_t {
    sphere = 0,  ///< radius r (0: the body collides with nothing)
    box = 1,     ///< half-extents (a, b, c) along body x, y, z
    capsule = 2, ///< the points within r of the segment from (0, −L, 0) to (0, L, 0): a cylinder along body y with hemispherical caps
};

/// Mass properties of one body and its collision shape.
struct RigidBody {
    double mass = 1;                                       ///< kg
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity(); ///< about the centre of mass, body frame, kg·m²
    double radius = 0;                                     ///< sphere or capsule radius, m; 0 for none
    Shape shape = Shape::sphere;
    /// Box: half-extents (a, b, c), m. Capsule: (0, L, 0), L the half-length of its segment.
    Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();

    /// A solid sphere: I = (2/5) m r² 𝟙, with collision radius r.
    static RigidBody solid_sphere(double mass, double radius);
    /// A box's mass properties with half-extents (a, b, c): I = m/3 diag(b²+c², a²+c², a²+b²);
    /// no collision shape (solid_box has one).
    static RigidBody box(double mass, const Eigen::Vector3d& half_extents);
    /// A solid box that collides: box's inertia and the box shape.
    static RigidBody solid_box(double mass, const Eigen::Vector3d& half_extents);
    /// A solid capsule of radius r around the segment of length 2L along body y (uniform
    /// density: a cylinder of mass m_c = m·πr²2L/V and a sphere split in two caps, m_s = m − m_c,
    /// V = πr²2L + (4/3)πr³):
    ///   I_yy = m_c r²/2 + (2/5) m_s r²,
    ///   I_xx = I_zz = m_c (L²/3 + r²/4) + m_s ((2/5) r² + L² + (3/4) L r)
    /// (each cap's centroid lies 3r/8 beyond the end of the segment: the parallel-axis terms).
    static RigidBody solid_capsule(double mass, double radius, double half_length);
    /// Throws InvalidBody naming `label` for a mass that is not positive and finite, an
    /// inertia tensor that is not finite, symmetric and positive definite, principal moments
    /// that violate the triangle inequality I₁ + I₂ ≥ I₃ (no mass distribution has them), a
    /// negative or non-finite radius, a box whose half-extents are not all positive and finite
    /// or a capsule without a positive radius or with a negative or non-finite half-length.
    void validate(std::string_view label) const;
};

/// The initial state of one body (insertRigid).
struct RigidInit {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();         ///< centre of mass, m
    Quaternion orientation = Quaternion::identity();            ///< must be unit (within 1e-6)
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();         ///< m/s
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero(); ///< world frame, rad/s
};

} // namespace phynjo::runtime
