#pragma once
/// \file
/// The rigid-body Strang splitting. Order 2, symmetric. (source: integrators/rigid_leapfrog.cpp)
#include "phynjo/runtime/rigid/rigid_rules.hpp"

namespace phynjo::runtime {

/// The rigid-body Strang splitting
///   drift_trans(½) · drift_rot(½) · kick_force3d(1) · drift_rot(½) · drift_trans(½):
/// one force evaluation per step, order 2 (first order with the explicit schemes).
NumericWorkflow rigid_leapfrog(const Force3D& force, const ComponentSet& bodies,
                               const std::shared_ptr<const Layout>& layout,
                               GyroscopicScheme scheme = GyroscopicScheme::implicit_midpoint);

} // namespace phynjo::runtime
