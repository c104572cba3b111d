// Sweep plans: the axes parsed, the runs numbered, each run's values (sweep_plan.hpp).
#include "phynjo/runtime/simulate/sweep_plan.hpp"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "strict_numbers.hpp"

namespace phynjo::runtime {

namespace {

using detail::finite_number;

/// NAME=A:B[:C] split; throws with the option's own wording.
std::vector<std::string> fields_of(std::string_view text, std::string& name, std::size_t count, const char* form) {
    const auto eq = text.find('=');
    if (eq == std::string_view::npos || eq == 0)
        throw std::invalid_argument("expected " + std::string(form) + ", got '" + std::string(text) + "'");
    name = std::string(text.substr(0, eq));
    std::vector<std::string> parts;
    std::string_view rest = text.substr(eq + 1);
    for (;;) {
        const auto colon = rest.find(':');
        parts.emplace_back(rest.substr(0, colon));
        if (colon == std::string_view::npos) break;
        rest = rest.substr(colon + 1);
    }
    if (parts.size() != count)
        throw std::invalid_argument("expected " + std::string(form) + ", got '" + std::string(text) + "'");
    return parts;
}

double bound(const std::string& s, const std::string& text) {
    if (auto v = finite_number(s)) return *v;
    throw std::invalid_argument("'" + s + "' is not a finite number (in '" + text + "')");
}

/// SplitMix64 (Steele, Lea, Flood 2014): a counter-based stream of 64-bit values.
std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

} // namespace

namespace {

/// "NAME=LO:HI:N" (grid) or "NAME=LO:HI" (uniform): the one reader of both axis forms.
SweepAxis parse_axis(std::string_view text, bool grid) {
    SweepAxis a;
    const auto p = fields_of(text, a.name, grid ? 3 : 2, grid ? "NAME=LO:HI:N" : "NAME=LO:HI");
    const std::string t(text);
    a.lo = bound(p[0], t);
    a.hi = bound(p[1], t);
    a.n = 0;
    if (!grid) {
        if (!(a.lo <= a.hi)) throw std::invalid_argument("LO must not exceed HI (in '" + t + "')");
        return a;
    }
    const auto whole = detail::whole_number(p[2]);
    const long n = whole ? *whole : 0;
    if (n < 1)
        throw std::invalid_argument("'" + p[2] + "' is not a positive whole number of points (in '" + t + "')");
    if (n > 100000000) throw std::invalid_argument("more than 10^8 points on one axis (in '" + t + "')");
    a.n = static_cast<std::size_t>(n);
    return a;
}

} // namespace

SweepAxis parse_grid_axis(std::string_view text) { return parse_axis(text, true); }

SweepAxis parse_uniform_axis(std::string_view text) { return parse_axis(text, false); }

std::size_t SweepPlan::size() const {
    std::size_t n = samples;
    for (const SweepAxis& a : grid) n *= a.n;
    return n;
}

std::vector<std::string> SweepPlan::names() const {
    std::vector<std::string> n;
    for (const SweepAxis& a : grid) n.push_back(a.name);
    for (const SweepAxis& a : uniform) n.push_back(a.name);
    return n;
}

void SweepPlan::values(std::size_t run, std::span<double> out) const {
    std::size_t point = run / samples;
    for (std::size_t k = grid.size(); k-- > 0;) { // the last axis fastest
        const SweepAxis& a = grid[k];
        const std::size_t i = point % a.n;
        point /= a.n;
        out[k] = a.n == 1 ? a.lo : a.lo + static_cast<double>(i) * (a.hi - a.lo) / static_cast<double>(a.n - 1);
    }
    for (std::size_t j = 0; j < uniform.size(); ++j) {
        const std::uint64_t r = splitmix64(seed ^ splitmix64(run * 0x100000001b3ull + j));
        const double u = static_cast<double>(r >> 11) * 0x1.0p-53; // [0, 1)
        out[grid.size() + j] = uniform[j].lo + u * (uniform[j].hi - uniform[j].lo);
    }
}

} // namespace phynjo::runtime
