#pragma once
/// \file
/// The implicit midpoint rule for generated models, in canonical coordinates (q, p). Order 2,
/// symplectic, symmetric. (source: integrators/lagrangian_midpoint.cpp)
#include "phynjo/runtime/models/lagrangian_system.hpp"

namespace phynjo::runtime {

/// Implicit midpoint rule on the canonical variables (q, p), p = ∂L/∂q':
///   q1 = q0 + dt·v(q_m, p_m),  p1 = p0 + dt·F(q_m, v_m),  with the midpoint values
/// q_m = (q0+q1)/2, p_m = (p0+p1)/2 and v solving p(q, v) = p by Newton on M. Solved by
/// fixed-point iteration to round-off. Order 2, symplectic and symmetric: for a
/// conservative autonomous Lagrangian the energy error stays bounded over long runs.
/// Reference: Hairer, Lubich, Wanner, Geometric Numerical Integration, §VI.3.
NumericWorkflow lagrangian_midpoint(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout);

} // namespace phynjo::runtime
