#pragma once
/// \file
/// Numeric evaluation.
#include "phynjo/cas/expr.hpp"

#include <span>
#include <unordered_map>
#include <vector>

namespace phynjo::cas {

/// Values of the variables (Symbols and TimeDerivatives) of an expression.
template <typename T>
using Bindings = std::unordered_map<Expr, T>;

/// The value of `e` in floating point type T (double or long double), with every number
/// correctly rounded to T first. Throws EvaluationError naming a variable without a value,
/// or when the result (or an intermediate) is not finite.
double evaluate(Expr e, const Bindings<double>& values);
/// The values of several expressions at the same point, sharing the work on common
/// subexpressions.
std::vector<double> evaluate(std::span<const Expr> es, const Bindings<double>& values);

/// The same in long double (64-bit significand), for reference values in tests.
long double evaluate_extended(Expr e, const Bindings<long double>& values);

} // namespace phynjo::cas
