#pragma once
/// \file
/// The 3-D particle world: positions, velocities, masses and accelerations per component,
/// and its drift and kick rules (the accelerations come from a force rule, e.g. N-body
/// gravity in nbody.hpp, or a Force3D).
#include "phynjo/runtime/core/workflow.hpp"
#include "phynjo/runtime/particles/force3d.hpp"

namespace phynjo::runtime {

/// Field ids of a particle world (make_particles): positions (m), velocities (m/s), mass
/// (kg), accelerations (m/s²).
inline constexpr FieldId kX = 0, kY = 1, kZ = 2, kVX = 3, kVY = 4, kVZ = 5, kMass = 6, kAX = 7, kAY = 8, kAZ = 9;

/// A 3-D particle world over `components`. With partitions > 1 it also holds one set of
/// partial accelerations per partition (fields ax#k, ay#k, az#k), so that the pair sum can
/// be split into parallel branches with disjoint domains.
World make_particles(const Registry& components, int partitions = 1);

/// v ← v + c·dt·a.
NumericRule kick3d(double c, const std::shared_ptr<const Layout>& layout);
/// r ← r + c·dt·v.
NumericRule drift3d(double c, const std::shared_ptr<const Layout>& layout);

/// v_c ← v_c + c·dt·F_c/m_c for every component, F from a Force3D (its torque is for rigid
/// bodies and ignored on particles). Domain: the velocities.
NumericRule kick3d(const Force3D& force, double c, const std::shared_ptr<const Layout>& layout);

/// The State3D view of a particle world.
State3D state3d(const World& particles);

} // namespace phynjo::runtime
