#pragma once
/// \file
/// Differentiation.
#include "phynjo/cas/expr.hpp"

#include <span>

namespace phynjo::cas {

/// ∂e/∂var for a Symbol or a TimeDerivative `var` (x and x' are independent variables, as in
/// ∂L/∂q and ∂L/∂q'). The product rule is applied to the flattened product,
/// d(u1·…·un) = Σ_i u1…u_i'…un, one Mul per term. Memoized in the pool, so a DAG with
/// shared subexpressions is differentiated once per node. Throws Error if `var` is not a
/// Symbol or TimeDerivative.
Expr diff(Expr e, Expr var);

/// The total time derivative of a mechanical quantity e(q, q', t) whose only time-dependent
/// symbols are the coordinates: Σ_i (∂e/∂q_i)·q_i' + (∂e/∂q_i')·q_i'' + ∂e/∂t. Every other
/// symbol is a constant.
Expr total_time_derivative(Expr e, std::span<const Expr> coordinates);

/// x' for a Symbol x (or x'' for x', …).
Expr velocity(Expr x);

} // namespace phynjo::cas
