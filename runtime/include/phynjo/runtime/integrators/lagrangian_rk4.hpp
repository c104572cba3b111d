#pragma once
/// \file
/// Classical RK4 for generated models, as a workflow of rules. Order 4, not symplectic.
/// (source: integrators/lagrangian_rk4.cpp)
#include "phynjo/runtime/system/constraint_projection.hpp"

namespace phynjo::runtime {

/// Classical RK4 on (q, q'): save, four stage rules, as a workflow. Order 4. A constrained
/// model (n_constraints > 0) gets a last rule, `project_constraints`, that projects the
/// state onto the constraints after every step (constraint_projection.hpp, `projection`).
NumericWorkflow lagrangian_rk4(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                               const ProjectionOptions& projection = {});

} // namespace phynjo::runtime
