#pragma once
/// \file
/// The compiler's middle step, between derivation and emission (derive → optimize → emit):
/// every expression the generated functions evaluate, in the form that costs least —
/// common factors out of sums (Horner form, cas::horner, one pass over each group so that
/// the work on common subexpressions is shared), and the Jacobians derived from those forms,
/// whose derivatives keep the factored sums. The emitters print what this gives them and
/// transform nothing; each function body is then one CSE pass (cpp_body.cpp).
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/model.hpp"

#include <string>
#include <vector>

namespace phynjo::codegen {

struct OptimizedEquations {
    /// M, f, p, E, F, G, γ, φ, φ' in Horner form (one pass over them all); the Jacobians
    /// (derive_jacobians) of those forms, in Horner form again (one pass); the scales'
    /// terms as derived.
    EquationsOfMotion eom;
    /// The events' guards, file order (one pass).
    std::vector<cas::Expr> guards;
    /// Per event, its resets' right sides (one pass per event).
    std::vector<std::vector<cas::Expr>> reset_values;
    /// The shapes' points, file order: a sphere's centre (3), a segment's or capsule's ends (6),
    /// a box's centre and orientation quaternion (7) (one pass).
    std::vector<cas::Expr> shape_points;
    /// Per sphere, ∂(X, Y, Z)/∂q row-major 3 × dof (one pass over all spheres).
    std::vector<cas::Expr> sphere_jacobians;
    /// The spheres' radii, as written.
    std::vector<cas::Expr> sphere_radii;
    /// Per capsule, ∂(X1, Y1, Z1, X2, Y2, Z2)/∂q row-major 6 × dof (one pass over all capsules).
    std::vector<cas::Expr> capsule_jacobians;
    /// The capsules' radii, as written.
    std::vector<cas::Expr> capsule_radii;
    /// Per box, ∂(X, Y, Z)/∂q of its centre and the angular-velocity Jacobian J_ω (ω = J_ω q'):
    /// row-major 6 × dof (one pass over all boxes).
    std::vector<cas::Expr> box_jacobians;
    /// The boxes' half extents (HX, HY, HZ), as written.
    std::vector<cas::Expr> box_half_extents;
    /// Per turn of a box whose axis holds parameters (file order): |a|², and what it is ("the
    /// axis of turn 1 of box 'lid'"). The analyzer checked the defaults; the generated shape
    /// functions refuse an axis that other parameters make zero (it would give no orientation).
    struct AxisCheck {
        cas::Expr length2; ///< |a|²
        std::string what;  ///< "the axis of turn 1 of box 'lid'"
    };
    std::vector<AxisCheck> box_axis_checks;
    /// The initial values: the coordinates', then the velocities', as written.
    std::vector<cas::Expr> initial_values;
};

/// The optimize step: `eom` as derive() gave it (no Jacobians) to what the emitters print.
/// Deterministic: the same model gives the same forms.
OptimizedEquations optimize(const Model& model, const EquationsOfMotion& eom);

} // namespace phynjo::codegen
