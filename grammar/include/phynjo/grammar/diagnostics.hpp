#pragma once
/// \file
/// One diagnostic sink for every stage (parser, name resolution, derivation):
/// `FILE:LINE:COL: error: WHAT`, then the source line and a caret under the place.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::grammar {

enum class Severity { Error, Note };

struct Diagnostic {
    Severity severity = Severity::Error;
    std::size_t offset = 0; ///< byte offset into the source text
    std::size_t length = 1; ///< bytes underlined (at least one caret)
    std::string message;
};

/// Line and column (1-based; columns count UTF-8 code points) of a byte offset.
struct Location {
    std::size_t line = 1;
    std::size_t column = 1;
};

class DiagnosticSink {
public:
    /// `text` must outlive the sink. `first_line` numbers the first line of `text` (batch
    /// tools parse one line of a larger input at a time).
    DiagnosticSink(std::string source_name, std::string_view text, std::size_t first_line = 1);

    void error(std::size_t offset, std::size_t length, std::string message);
    void note(std::size_t offset, std::size_t length, std::string message);

    [[nodiscard]] std::size_t error_count() const noexcept { return errors_; }
    [[nodiscard]] const std::vector<Diagnostic>& diagnostics() const noexcept { return diagnostics_; }
    [[nodiscard]] std::string_view text() const noexcept { return text_; }
    [[nodiscard]] const std::string& source_name() const noexcept { return name_; }

    [[nodiscard]] Location locate(std::size_t offset) const;
    /// One diagnostic as `NAME:LINE:COL: error: MESSAGE\n    LINE TEXT\n    ^~~\n`.
    [[nodiscard]] std::string format(const Diagnostic& d) const;
    /// Every diagnostic, in the order reported.
    [[nodiscard]] std::string format_all() const;

private:
    std::string name_;
    std::string_view text_;
    std::size_t first_line_;
    std::vector<std::size_t> line_starts_;
    std::vector<Diagnostic> diagnostics_;
    std::size_t errors_ = 0;
};

/// Thrown by the convenience entry points with every formatted diagnostic as its message.
class ParseError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

} // namespace phynjo::grammar
