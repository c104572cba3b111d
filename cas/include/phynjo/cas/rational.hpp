#pragma once
/// \file
/// Exact rationals: reading decimal literals exactly, and converting to floating point
/// with correct rounding (round-half-to-even), which `mpq_get_d` (truncation) does not do.
#include <gmpxx.h>

#include <optional>
#include <string>
#include <string_view>

namespace phynjo::cas {

/// Reads a decimal literal (`3`, `0.25`, `.5`, `1e-3`, `6.674e-11`) exactly: `9.81` is
/// 981/100. Returns nothing for malformed text or when the value would need more than
/// `limits::max_number_bits` bits (more than 31,000 significant digits, or a decimal
/// exponent beyond ±31,000).
std::optional<mpq_class> parse_decimal(std::string_view text);

/// The double nearest to `q` (ties to even), as a correctly rounding `strtod` would give
/// for the same decimal. ±infinity when |q| exceeds the double range.
double to_double(const mpq_class& q);
/// The long double nearest to `q` (ties to even).
long double to_long_double(const mpq_class& q);

/// Shortest decimal text that reads back as exactly `x` (std::to_chars), always containing
/// a `.` or an exponent so that it is a floating-point literal in C++.
std::string double_literal(double x);

} // namespace phynjo::cas
