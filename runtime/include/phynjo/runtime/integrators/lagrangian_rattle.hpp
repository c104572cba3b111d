#pragma once
/// \file
/// RATTLE for generated models with holonomic constraints (or none): the constrained
/// generalized leapfrog in canonical variables. Order 2, symmetric; symplectic for a
/// conservative model with time-independent constraints. (source: integrators/lagrangian_rattle.cpp)
#include "phynjo/runtime/system/constraint_projection.hpp"

namespace phynjo::runtime {

/// RATTLE on (q, p), p = ∂L/∂q', with F = ∂L/∂q + Q − ∂R/∂q' (generalized_forces), v(q, p)
/// the velocities of momenta p, G = ∂φ/∂q and t1 = t0 + h:
///   p½ = p0 + h/2 (F(t0, q0, v(q0, p½)) + G(q0)ᵀλ)
///   q1 = q0 + h/2 (v(t0, q0, p½) + v(t1, q1, p½)),      φ(q1, t1) = 0
///   p1 = p½ + h/2 (F(t1, q1, v(q1, p½)) + G(q1)ᵀμ),    G(q1) v(q1, p1) + ∂φ/∂t = 0
/// λ by Broyden's method from (h²/4) G(q1) (M(q0)⁻¹ + M(q1)⁻¹) G(q0)ᵀ, μ by Newton on the
/// velocity constraints; both to `projection.tolerance` (constraint_projection.hpp). Without
/// constraints: the generalized leapfrog (Störmer–Verlet for a non-separable Hamiltonian).
/// Order 2, symmetric; symplectic for a conservative model with scleronomic constraints, so
/// its energy error stays bounded over long runs, chaotic ones included; the constraints hold
/// at position and velocity level after every step.
/// References: H. C. Andersen, J. Comput. Phys. 52, 24 (1983); L. O. Jay, SIAM J. Numer.
/// Anal. 33, 368 (1996); Hairer, Lubich, Wanner, Geometric Numerical Integration, §VII.1.
/// Throws std::invalid_argument for a model with nonholonomic constraints (lagrangian_midpoint
/// handles those).
NumericWorkflow lagrangian_rattle(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                                  const ProjectionOptions& projection = {});

} // namespace phynjo::runtime
