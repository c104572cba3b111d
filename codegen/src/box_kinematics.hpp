#pragma once
// A box shape's pose and velocity Jacobian from its centre and turns (model.hpp, Shape): the
// exact expressions the generated shape_positions and box_jacobians print.
#include "phynjo/codegen/model.hpp"

#include <span>
#include <vector>

namespace phynjo::codegen::detail {

/// The box's centre (X, Y, Z) and orientation quaternion (w, x, y, z) = q_n ⊗ … ⊗ q_1, with
/// q_k = (cos(A_k/2), sin(A_k/2) â_k) for the k-th turn by A_k about â_k = a_k/|a_k|: 7
/// expressions. No turn: the identity (1, 0, 0, 0).
std::vector<cas::Expr> box_pose(const Shape& box);

/// ∂(X, Y, Z)/∂q (rows 0–2) and the angular-velocity Jacobian (rows 3–5): 6 × dof row-major,
/// ω = J_ω q'. ω = Σ_k A_k' u_k with u_k = R_n ⋯ R_{k+1} â_k (the k-th axis carried by the
/// later turns; R_j by Rodrigues' formula), so J_ω's column i is Σ_k (∂A_k/∂q_i) u_k — exact,
/// with no trigonometric simplification needed.
std::vector<cas::Expr> box_jacobian(const Shape& box, std::span<const cas::Expr> q);

} // namespace phynjo::codegen::detail
