#pragma once
/// \file
/// From a parsed .lag file to a checked Model: names declared once and before use, the
/// meaning of `'` (docs/language.md), constant parameters and initial values, one force per
/// coordinate; every mistake reported at its place, several per run.
#include "phynjo/codegen/model.hpp"
#include "phynjo/grammar/diagnostics.hpp"
#include "phynjo/grammar/lag.hpp"

#include <optional>
#include <string_view>

namespace phynjo::codegen {

/// The model of a parsed file; nothing if any error was reported. `default_name` is the
/// file's stem (made a valid C++ identifier), used when there is no `model` statement.
std::optional<Model> analyze(const grammar::ParsedModel& parsed, const grammar::Positions& positions,
                             grammar::DiagnosticSink& sink, std::string_view default_name);

/// Parses and analyzes a model file's text.
std::optional<Model> read_model(std::string_view text, std::string_view source_name, grammar::DiagnosticSink& sink);

/// `double_pendulum.lag` → `double_pendulum`; characters not valid in a C++ identifier → `_`.
std::string model_name_from_path(std::string_view path);

/// True for C++ keywords (a parameter or model with such a name cannot be emitted).
bool is_cpp_keyword(std::string_view name);

} // namespace phynjo::codegen
