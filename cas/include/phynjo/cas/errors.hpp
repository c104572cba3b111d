#pragma once
/// \file
/// Typed exceptions for mistakes in what users give the CAS (the second tier of errors:
/// our own invariants are assertions).
#include <cstdint>
#include <stdexcept>
#include <string>

namespace phynjo::cas {

/// Base of every error the CAS reports about its input.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A mathematically undefined operation: division by zero, `log(0)`, `tan(pi/2)`, …
class DomainError : public Error {
public:
    using Error::Error;
};

/// A documented resource limit was hit (number size, expansion size, derivative order…).
class LimitError : public Error {
public:
    using Error::Error;
};

/// Numeric evaluation failed: a symbol without a value, or a non-finite result.
class EvaluationError : public Error {
public:
    using Error::Error;
};

/// The documented resource limits. They turn hostile input into an error rather than an
/// exhausted memory.
namespace limits {
/// Largest exact number made by `pow` or read from a literal, in bits of numerator or
/// denominator (about 30,000 decimal digits).
inline constexpr std::size_t max_number_bits = 100'000;
/// Longest literal: significant digits, and the magnitude of the decimal exponent after the
/// fraction is folded in. Enough for every number of max_number_bits bits (30,103 digits),
/// so that printed expressions always read back.
inline constexpr long max_literal_digits = 31'000;
/// Most terms `expand` may produce for one expression.
inline constexpr std::size_t max_expand_terms = 100'000;
/// Most distinct nodes one Pool may hold: a budget on the work and memory of everything
/// built in it (the 41-coordinate nlink_cart_40 model needs 225,000). Pool::set_node_limit
/// changes it per pool.
inline constexpr std::size_t max_nodes = 10'000'000;
/// Most terms and factors that sums and products of one Pool may process in all: a budget on
/// time (about a minute of work), so that no input runs unbounded. nlink_cart_40, the
/// largest benchmark model, uses 1.5 million. Pool::set_work_limit changes it per pool.
inline constexpr std::uint64_t max_work = 200'000'000;
/// Longest text a printer produces for one expression (a DAG printed as a tree can be
/// exponentially longer than the DAG); beyond it, LimitError.
inline constexpr std::size_t max_printed_chars = 16u << 20;
/// Highest time-derivative order of a symbol (`x''…'`).
inline constexpr int max_derivative_order = 16;
} // namespace limits

} // namespace phynjo::cas
