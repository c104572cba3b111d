#pragma once
/// \file
/// The equations of motion of a model, derived exactly (docs/language.md, *Meaning*):
///   d/dt(∂L/∂q_i') − ∂L/∂q_i = Q_i − ∂R/∂q_i'   brought to   M(q, t)·q'' = f(q, q', t)
/// with M_ij = ∂²L/∂q_i'∂q_j' and, expanding d/dt(∂L/∂q_i') = Σ_j M_ij q_j'' + Σ_j
/// (∂p_i/∂q_j) q_j' + ∂p_i/∂t,
///   f_i = ∂L/∂q_i + Q_i − ∂R/∂q_i' − Σ_j (∂p_i/∂q_j) q_j' − ∂p_i/∂t.
/// Also p_i = ∂L/∂q_i' and E = Σ_i q_i' p_i − L.
#include "phynjo/codegen/model.hpp"
#include "phynjo/grammar/diagnostics.hpp"

#include <optional>

namespace phynjo::codegen {

struct EquationsOfMotion {
    std::size_t dof = 0;
    std::vector<cas::Expr> mass_matrix; ///< row-major dof×dof, symmetric
    /// True when M depends on the velocities (L not quadratic in them: a relativistic
    /// particle): the generated mass_matrix then takes q' too.
    bool mass_depends_on_velocities = false;
    std::vector<cas::Expr> forcing;     ///< f
    std::vector<cas::Expr> momenta;     ///< p
    cas::Expr energy;                   ///< E
    /// ∂L/∂q_i + Q_i − ∂R/∂q_i': the right side of p_i' in canonical form (for integrators
    /// that work with (q, p)).
    std::vector<cas::Expr> generalized_forces;
    /// Q_i − ∂R/∂q_i': the part of F that is not ∂L/∂q_i (zero for a conservative model).
    /// derive_jacobians uses it to take ∂F/∂y from the symmetry of ∂²L (see there).
    std::vector<cas::Expr> nonconservative_forces;

    // Constraints, file order (docs/language.md, *Constraints*): M q'' = f + Gᵀλ, G q'' = γ.
    std::size_t n_constraints = 0;
    /// G, row-major n_constraints×dof: ∂φ/∂q (holonomic rows), ∂φ/∂q' (nonholonomic rows).
    std::vector<cas::Expr> constraint_matrix;
    /// γ: the part of φ'' (holonomic) or φ' (nonholonomic) without q'', negated.
    std::vector<cas::Expr> gamma;
    /// φ: φ(q, t) for holonomic rows, a·q' + b for nonholonomic rows.
    std::vector<cas::Expr> residuals;
    /// The velocity-level constraints: φ' = G q' + ∂φ/∂t (holonomic rows), φ (nonholonomic).
    std::vector<cas::Expr> velocity_residuals;
    /// The summands of each φ_k and each velocity constraint: their absolute values summed
    /// are the scale against which a residual counts as small (constraint_scales).
    std::vector<std::vector<cas::Expr>> residual_terms, velocity_residual_terms;

    // Jacobians of y' (filled by derive_jacobians) = (q', q'') with y = (q, q'), by implicit differentiation of the
    // saddle-point system. With symbols â for q'' and λ̂ for λ,
    //   r(y, â, λ̂) = f − M â + Gᵀλ̂ = 0,   c(y, â) = γ − G â = 0,
    // so that at â = q'', λ̂ = λ
    //   [M  −Gᵀ] [∂q''/∂y]   [∂r/∂y]
    //   [G   0 ] [∂λ/∂y  ] = [∂c/∂y]
    // — the matrix of the forward solve. Likewise for the inputs u.
    std::vector<cas::Expr> acceleration_symbols; ///< â_i (named "@a<i>": no user name)
    std::vector<cas::Expr> multiplier_symbols;   ///< λ̂_k ("@l<k>")
    std::vector<cas::Expr> jacobian_r; ///< ∂r/∂y, row-major dof × 2·dof
    std::vector<cas::Expr> jacobian_c; ///< ∂c/∂y, row-major n_constraints × 2·dof
    std::vector<cas::Expr> input_r;    ///< ∂r/∂u, row-major dof × n_inputs
    std::vector<cas::Expr> input_c;    ///< ∂c/∂u, row-major n_constraints × n_inputs
    /// For implicit integrators in canonical variables: ∂p/∂y and ∂F/∂y (F the generalized
    /// forces), row-major dof × 2·dof each.
    std::vector<cas::Expr> momenta_jacobian, force_jacobian;
};

/// Documented limits of the derivation.
struct DeriveLimits {
    /// Most distinct subexpressions (DAG nodes) of M, f, p and E together.
    std::size_t max_nodes = 5'000'000;
};

/// Derives the equations of motion. Reports, at the coordinate, a mass matrix that is
/// singular for every q, t and parameter values (for example a coordinate whose velocity
/// does not appear in L); at a constraint, a constraint matrix G whose row is a combination
/// of the earlier rows for every state (a constraint written twice, or implied by others);
/// and, at the lagrangian statement, equations larger than `limits.max_nodes`; returns
/// nothing then.
std::optional<EquationsOfMotion> derive(const Model& model, grammar::DiagnosticSink& sink, const DeriveLimits& limits = {});

/// Fills the Jacobian part of `eom` (acceleration_symbols … input_c) from its M, f, G and γ,
/// in whatever form they are: the emitter calls it on their Horner forms, whose derivatives
/// keep the factored sums.
void derive_jacobians(const Model& model, EquationsOfMotion& eom);

} // namespace phynjo::codegen
