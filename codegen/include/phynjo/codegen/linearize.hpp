#pragma once
/// \file
/// The linearization of a model about a state (phynjo-lagc --emit=linear): with y = (q, q')
/// and the inputs u,  y' ≈ y'(y0, u0) + A (y − y0) + B (u − u0),  A = ∂y'/∂y, B = ∂y'/∂u,
/// exact — in closed form in the parameters — when the state is exact. Constraints
/// included: A and B are those of the constrained accelerations (implicit differentiation
/// of the saddle-point system, as the generated rhs_jacobian).
#include "phynjo/codegen/equations.hpp"

#include <complex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace phynjo::codegen {

/// A state the user asked for that cannot be used (an unknown name, a value that is not a
/// constant, a singular mass matrix there): the message says which.
struct LinearizeError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Linearization {
    std::vector<std::string> state_names; ///< q_i, then q_i'
    std::vector<std::string> input_names;
    std::vector<cas::Expr> state;         ///< y0, exact
    cas::Expr time;                       ///< t0 (0 unless given)
    std::vector<cas::Expr> rate;          ///< y'(y0), exact
    std::vector<double> rate_values;      ///< y'(y0) at the parameters' defaults
    std::vector<cas::Expr> A, B;          ///< row-major (2·dof)×(2·dof) and (2·dof)×n_inputs
    std::vector<double> A_values;         ///< A at the parameters' defaults, row-major
    /// Eigenvalues of A at the parameters' defaults, by decreasing real part.
    std::vector<std::complex<double>> eigenvalues;
    /// The parameters' defaults used for the eigenvalues (name, value), file order.
    std::vector<std::pair<std::string, double>> defaults;
};

/// Linearizes about the state `at`: (name, exact value) for coordinates `x`, velocities
/// `x'` and time `t`; what is not given is 0. Values may use the parameters. `eom` as
/// derive() gives it: the Jacobians are derived here, of its exact (not Horner) forms.
Linearization linearize(const Model& model, const EquationsOfMotion& eom,
                        const std::vector<std::pair<std::string, cas::Expr>>& at);

/// The linearization as text in the input syntax, or (latex) as a LaTeX fragment.
std::string emit_linear(const Model& model, const Linearization& lin, bool latex);

} // namespace phynjo::codegen
