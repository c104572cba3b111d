#pragma once
/// \file
/// Keeping a constrained generated model on its constraint manifold (docs/language.md,
/// *Constraints*): checks of initial values, and the projections the integrators apply
/// after a step (lagrangian_rk4, DormandPrince45; lagrangian_midpoint projects
/// symmetrically). Projections are minimum-norm (Euclidean in the coordinates):
///   positions  q ← q − G_hᵀ (G_h G_hᵀ)⁻¹ φ_h(q, t)   iterated (Gauss–Newton), holonomic rows;
///   velocities q' ← q' − Gᵀ (G Gᵀ)⁻¹ ψ(q, q', t)      one step (ψ is affine in q'),
/// with ψ the velocity-level constraints: φ' = G q' + ∂φ/∂t for holonomic rows and φ itself
/// for nonholonomic rows. Reference: Hairer, Lubich, Wanner, Geometric Numerical
/// Integration, §IV.4 (standard projection). No allocation in a steady step.
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// Tolerances of the projections.
struct ProjectionOptions {
    /// A constraint counts as satisfied when |φ_i| ≤ tolerance·s_i at position level and
    /// |ψ_i| ≤ tolerance·s'_i at velocity level, with s_i, s'_i the sums of the absolute
    /// values of the terms of φ_i and ψ_i (the generated constraint_scales) — relative to the
    /// size of what cancels (x² + y² − l² against x² + y² + l²) — plus the floor
    /// kScaleFloor·Σ_j |G_ij|·max_j |x_j| (x = q, q'), for rows whose own terms vanish (a
    /// body at rest while others move).
    double tolerance = 1e-12;
    /// Gauss–Newton iterations before the projection gives up (ConvergenceError).
    int max_iterations = 20;
};

/// The weight of the state's size in the scale of a residual (ProjectionOptions::tolerance).
inline constexpr double kScaleFloor = 1e-3;

/// The default relative tolerance of initial values (docs/language.md: 1e-9).
inline constexpr double kInitialConstraintTolerance = 1e-9;

/// The worst-satisfied constraint at a state.
struct ConstraintViolation {
    std::size_t constraint = 0;  ///< index in file order
    bool velocity_level = false; ///< ψ (velocity level) rather than φ (position level)
    double residual = 0;         ///< φ_i or ψ_i
    double scaled = 0;           ///< |residual| / its scale (ProjectionOptions)
};

/// The largest scaled residual over the holonomic rows at position level and all rows at
/// velocity level (position level wins ties). Zero for a model without constraints.
ConstraintViolation worst_constraint_violation(const LagrangianSystem& s, double t, std::span<const double> q,
                                               std::span<const double> qdot);

/// Throws InconsistentInitialValues, naming the constraint and its residual, when a scaled
/// residual exceeds `tolerance`: the worst position-level violation if there is one, else
/// the worst velocity-level one.
void check_constraints(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> qdot,
                       double tolerance = kInitialConstraintTolerance);

/// Projects q onto φ_h(q, t) = 0 (holonomic rows). Throws ConvergenceError when Gauss–Newton
/// does not reach the tolerance, SingularConstraints when G_h G_hᵀ is singular.
void project_positions(const LagrangianSystem& s, double t, std::span<double> q, std::span<const double> qdot,
                       const ProjectionOptions& options = {});

/// Projects q' onto ψ(q, q', t) = 0 (every row); q' already within the tolerance is left
/// exactly as it is. Throws SingularConstraints when G Gᵀ is singular.
void project_velocities(const LagrangianSystem& s, double t, std::span<const double> q, std::span<double> qdot,
                        const ProjectionOptions& options = {});

/// Positions, then velocities; a state within the tolerance is left exactly as it is.
void project_onto_constraints(const LagrangianSystem& s, double t, std::span<double> q, std::span<double> qdot,
                              const ProjectionOptions& options = {});

/// A rule (`project_constraints`, writing q and q') that projects the state onto the
/// constraints at the end of a step (time w.time + dt): what non-symmetric integrators
/// append after their stages.
NumericRule constraint_projection_rule(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                                       const ProjectionOptions& options = {});

namespace detail {
/// x ← x + Gᵀ μ restricted to `rows` (holonomic only when `holonomic_only`): the correction
/// directions of the projections. G is n_constraints×dof; μ has one entry per selected row.
void add_constraint_directions(const LagrangianSystem& s, std::span<const double> G, bool holonomic_only,
                               std::span<const double> mu, std::span<double> x);
/// Solves (G_s G_sᵀ) y = r in place for the selected rows (holonomic only when
/// `holonomic_only`); throws SingularConstraints naming the rows when singular.
void solve_gram(const LagrangianSystem& s, std::span<const double> G, bool holonomic_only, std::span<double> r,
                double t);
/// The number of holonomic rows.
std::size_t holonomic_count(const LagrangianSystem& s);
/// The scales of the residuals (2·n_constraints): the system's constraint_scales (0 when it
/// has none) plus the floor kScaleFloor·Σ_j |G_kj|·max|x|, with `G` the constraint matrix at (t, q).
void constraint_scales(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> qdot,
                       std::span<const double> G, std::vector<double>& scale);
/// The same, evaluating G at (t, q).
void constraint_scales(const LagrangianSystem& s, double t, std::span<const double> q, std::span<const double> qdot,
                       std::vector<double>& scale);
/// |r| / scale; 0 for r = 0, infinite for a non-finite r or r ≠ 0 at scale 0.
inline double scaled_residual(double r, double scale) {
    if (!std::isfinite(r)) return HUGE_VAL;
    if (r == 0) return 0;
    return scale > 0 ? std::fabs(r) / scale : HUGE_VAL;
}
} // namespace detail

} // namespace phynjo::runtime
