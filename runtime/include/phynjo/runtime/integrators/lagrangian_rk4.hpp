#pragma once
/// \file
/// Classical RK4 for generated models, as a workflow of rules. Order 4, not symplectic.
/// (source: integrators/lagrangian_rk4.cpp)
#include "phynjo/runtime/models/lagrangian_system.hpp"

namespace phynjo::runtime {

/// Classical RK4 on (q, q'): save, four stage rules, as a workflow. Order 4.
NumericWorkflow lagrangian_rk4(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout);

} // namespace phynjo::runtime
