#include "phynjo/grammar/diagnostics.hpp"

#include <algorithm>

namespace phynjo::grammar {

DiagnosticSink::DiagnosticSink(std::string source_name, std::string_view text, std::size_t first_line)
    : name_(std::move(source_name)), text_(text), first_line_(first_line) {
    line_starts_.push_back(0);
    for (std::size_t i = 0; i < text_.size(); ++i)
        if (text_[i] == '\n') line_starts_.push_back(i + 1);
}

void DiagnosticSink::error(std::size_t offset, std::size_t length, std::string message) {
    diagnostics_.push_back({Severity::Error, offset, length, std::move(message)});
    ++errors_;
}
void DiagnosticSink::note(std::size_t offset, std::size_t length, std::string message) {
    diagnostics_.push_back({Severity::Note, offset, length, std::move(message)});
}

Location DiagnosticSink::locate(std::size_t offset) const {
    offset = std::min(offset, text_.size());
    const auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset) - 1;
    const std::size_t line = static_cast<std::size_t>(it - line_starts_.begin());
    std::size_t column = 1;
    for (std::size_t i = *it; i < offset; ++i)
        if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) ++column; // count code points
    return {line + first_line_, column};
}

std::string DiagnosticSink::format(const Diagnostic& d) const {
    const Location loc = locate(d.offset);
    const std::size_t start = line_starts_[loc.line - first_line_];
    std::size_t end = text_.find('\n', start);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    std::string out = name_ + ":" + std::to_string(loc.line) + ":" + std::to_string(loc.column) + ": " +
                      (d.severity == Severity::Error ? "error: " : "note: ") + d.message + "\n";
    out += "    ";
    out += line;
    out += "\n    ";
    // caret line: keep tabs so that the caret lines up under the source
    const std::size_t col_bytes = std::min(d.offset, end) - start;
    for (std::size_t i = 0; i < col_bytes; ++i) {
        const unsigned char c = static_cast<unsigned char>(line.size() > i ? line[i] : ' ');
        if ((c & 0xC0) == 0x80) continue;
        out += c == '\t' ? '\t' : ' ';
    }
    out += '^';
    // underline the rest of the range on this line, in code points
    std::size_t stop = std::min(d.offset + std::max<std::size_t>(d.length, 1), end);
    for (std::size_t i = d.offset + 1; i < stop; ++i)
        if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) out += '~';
    out += '\n';
    return out;
}

std::string DiagnosticSink::format_all() const {
    std::string s;
    for (const Diagnostic& d : diagnostics_) s += format(d);
    return s;
}

} // namespace phynjo::grammar
