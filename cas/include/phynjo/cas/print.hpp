#pragma once
/// \file
/// Printers: the input syntax (re-parses to the same expression), C++, LaTeX.
#include "phynjo/cas/expr.hpp"
#include "phynjo/cas/node_map.hpp"

#include <functional>
#include <string>

namespace phynjo::cas {

/// Infix in the input syntax of `docs/language.md`: parsing the result gives back `e` exactly.
/// Terms and factors appear in a readable order (by kind, then alphabetically).
std::string to_string(Expr e);
/// The same with a smaller output limit (throws LimitError past `max_chars`).
std::string to_string(Expr e, std::size_t max_chars);

/// Options of the C++ printer.
struct CppOptions {
    /// Spelling of a variable (Symbol or TimeDerivative). Default: the name, `x_dot`,
    /// `x_ddot`, `x_d3`, …
    std::function<std::string(Expr)> variable_name;
    /// Spellings looked up before `variable_name` is called (no call, no copy: a code
    /// generator names every variable of a body once). Not owned; may be null.
    const NodeMap<std::string>* variable_table = nullptr;
    /// Largest |n| printed as repeated multiplication for `x^n` (integer n); above it, std::pow.
    int max_multiply_power = 8;
    /// Qualification of the math functions (sin, fabs, sqrt, pow, atan2, sign): `std::`, or a
    /// namespace that overloads them for other number types (generated code's lanes: then
    /// sign(x) is a call too).
    std::string math_prefix = "std::";
};

/// A C++ expression of type double: `std::sin`, integer powers as multiplications,
/// rationals as correctly rounded double literals.
std::string to_cpp(Expr e, const CppOptions& options = {});
/// The default C++ spelling of a variable (see CppOptions::variable_name).
std::string default_cpp_name(Expr variable);

/// LaTeX (math mode, without delimiters): \frac, \sin, \dot{x}, greek names as letters.
std::string to_latex(Expr e);

} // namespace phynjo::cas
