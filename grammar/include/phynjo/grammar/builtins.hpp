#pragma once
/// \file
/// The built-in names of the model language (docs/language.md, *Lexical rules*), declared once:
/// the constants `t` (time) and `pi`, and the functions. The converter to CAS expressions,
/// the front end (names that cannot be declared) and the messages all read these tables.
#include "phynjo/cas/expr.hpp"

#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace phynjo::grammar {

struct BuiltinFunction {
    std::string_view name;
    cas::Expr (*apply)(cas::Expr) = nullptr;            ///< the canonicalizing CAS factory (one argument)
    cas::Expr (*apply2)(cas::Expr, cas::Expr) = nullptr; ///< or of two (atan2)
    [[nodiscard]] constexpr std::size_t arity() const { return apply2 ? 2 : 1; }
};

/// The built-in functions, in the order messages list them.
inline constexpr std::array<BuiltinFunction, 15> builtin_functions{{{"sin", &cas::sin},
                                                                    {"cos", &cas::cos},
                                                                    {"tan", &cas::tan},
                                                                    {"exp", &cas::exp},
                                                                    {"log", &cas::log},
                                                                    {"sqrt", &cas::sqrt},
                                                                    {"asin", &cas::asin},
                                                                    {"acos", &cas::acos},
                                                                    {"atan", &cas::atan},
                                                                    {"atan2", nullptr, &cas::atan2},
                                                                    {"sinh", &cas::sinh},
                                                                    {"cosh", &cas::cosh},
                                                                    {"tanh", &cas::tanh},
                                                                    {"abs", &cas::abs},
                                                                    {"sign", &cas::sign}}};
/// The built-in constants: time and π.
inline constexpr std::array<std::string_view, 2> builtin_constants{"t", "pi"};

/// The built-in function of that name, or nullptr.
const BuiltinFunction* find_builtin_function(std::string_view name);
/// True for every built-in name (constants and functions): such names cannot be declared.
bool is_builtin(std::string_view name);
/// "sin, cos, tan, exp, log, sqrt, asin, …", for messages.
std::string builtin_function_list();

} // namespace phynjo::grammar
