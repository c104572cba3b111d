#pragma once
/// \file
/// A rigid body's mass properties (mass, body-frame inertia tensor, collision-sphere
/// radius), validated, and its initial state. The world that holds bodies is rigid_world.hpp.
#include "phynjo/runtime/rigid/quaternion.hpp"

#include <Eigen/Core>

#include <string_view>

namespace phynjo::runtime {

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

/// The initial state of one body (insertRigid).
struct RigidInit {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();         ///< centre of mass, m
    Quaternion orientation = Quaternion::identity();            ///< must be unit (within 1e-6)
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();         ///< m/s
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero(); ///< world frame, rad/s
};

} // namespace phynjo::runtime
