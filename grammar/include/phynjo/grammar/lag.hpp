#pragma once
/// \file
/// Parsing `.lag` model files (docs/language.md) into position-tagged statements.
#include "phynjo/grammar/ast.hpp"
#include "phynjo/grammar/builtins.hpp"
#include "phynjo/grammar/diagnostics.hpp"
#include "phynjo/grammar/expression.hpp"

#include <vector>

namespace phynjo::grammar {

/// Limits for whole files, on top of the expression limits.
struct FileLimits {
    /// Largest model file, bytes (a 100 MB file gets a diagnostic, not a parse).
    std::size_t max_bytes = 16u << 20;
    Limits expression;
};

/// The statements of a model file, in order, with the positions of their nodes. Statements
/// with syntax errors are reported to the sink and left out; parsing goes on with the next
/// statement, so several errors are reported in one run.
struct ParsedModel {
    std::vector<ast::Statement> statements;
    /// False when the file as a whole was rejected (too large, not UTF-8): nothing more to
    /// say about its contents.
    bool readable = true;
    /// The first word of every statement that had a syntax error (reported already): a later
    /// stage does not report such a statement as missing.
    std::vector<std::string> failed_keywords;
    /// The names a failed coordinates, parameters or let statement declares: a later stage
    /// does not report them as unknown.
    std::vector<std::string> failed_names;
    /// True when the file carries a unit anywhere (a `[` outside comments): its
    /// dimensions are then checked (docs/language.md, *Units*).
    bool has_units = false;
};

/// Parses `text` (the whole file). `positions` must be constructed on the same text.
ParsedModel parse_model(std::string_view text, Positions& positions, DiagnosticSink& sink, const FileLimits& limits = {});

/// The keywords of the language, which cannot be declared (nor can the built-in names:
/// is_builtin in builtins.hpp).
bool is_keyword(std::string_view name);

} // namespace phynjo::grammar
