// Strict readers of command-line numbers (internal: model_main.cpp, sweep_plan.cpp, runs.cpp, sweep.cpp): a whole
// argument or nothing — "1e-2x", "abc", "" are not numbers.
#pragma once
#include <charconv>
#include <cmath>
#include <optional>
#include <string_view>

namespace phynjo::runtime::detail {

/// The whole steps DT in [0, T]: floor(T/DT), a ratio within 1e-9 of a whole number counting
/// as that number (20 / 0.001 is 20000, not 19999.999…); a shortened last step follows them.
inline long whole_steps(double t_end, double dt) {
    const double ratio = t_end / dt;
    long steps = static_cast<long>(std::floor(ratio));
    if (ratio - static_cast<double>(steps) > 1 - 1e-9) ++steps;
    return steps;
}

/// A whole argument as a finite number, or nothing.
inline std::optional<double> finite_number(std::string_view s) {
    double v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty() || !std::isfinite(v)) return std::nullopt;
    return v;
}

/// A whole argument as a whole number, or nothing.
inline std::optional<long> whole_number(std::string_view s) {
    long v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return v;
}

} // namespace phynjo::runtime::detail
