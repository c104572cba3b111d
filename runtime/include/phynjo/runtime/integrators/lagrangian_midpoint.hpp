#pragma once
/// \file
/// The implicit midpoint rule for generated models, in canonical coordinates (q, p). Order 2,
/// symplectic, symmetric. (source: integrators/lagrangian_midpoint.cpp)
#include "phynjo/runtime/system/constraint_projection.hpp"

namespace phynjo::runtime {

/// Implicit midpoint rule on the canonical variables (q, p), p = ∂L/∂q':
///   q1 = q0 + dt·v(q_m, p_m),  p1 = p0 + dt·F(q_m, v_m),  with the midpoint values
/// q_m = (q0+q1)/2, p_m = (p0+p1)/2 and v solving p(q, v) = p by Newton on M. Solved by
/// fixed-point iteration to round-off. Order 2, symplectic and symmetric: for a
/// conservative autonomous Lagrangian the energy error stays bounded over long runs.
/// Reference: Hairer, Lubich, Wanner, Geometric Numerical Integration, §VI.3.
/// Constrained models (n_constraints > 0): p' = F + Gᵀλ, and the step is wrapped in the
/// symmetric projection (Hairer, BIT 40, 2000) onto φ_h = 0 and the velocity constraints,
/// to `projection.tolerance`; it stays symmetric, so the energy error stays bounded.
NumericWorkflow lagrangian_midpoint(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                                    const ProjectionOptions& projection = {});

} // namespace phynjo::runtime
