#pragma once
/// \file
/// The runs of a sweep: grid axes and Monte Carlo axes, parsed from the simulators' --grid and
/// --uniform, and the plan that numbers the runs and gives each its values.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::runtime {

/// One swept quantity: a grid axis (n ≥ 1 values LO + i (HI − LO)/(n − 1), LO alone for n = 1)
/// or a Monte Carlo axis (n = 0: uniform on [LO, HI)).
struct SweepAxis {
    std::string name; ///< a parameter or input, a coordinate (its initial value) or NAME' (its initial velocity)
    double lo = 0, hi = 0;
    std::size_t n = 0;
};

/// "NAME=LO:HI:N" (a grid axis). Throws std::invalid_argument naming what is malformed.
SweepAxis parse_grid_axis(std::string_view text);
/// "NAME=LO:HI" (a Monte Carlo axis, LO ≤ HI). Throws std::invalid_argument.
SweepAxis parse_uniform_axis(std::string_view text);

/// The runs of a sweep, in their fixed order: the grid points row-major (the first axis
/// slowest), and `samples` Monte Carlo draws at each.
struct SweepPlan {
    std::vector<SweepAxis> grid, uniform;
    std::size_t samples = 1;
    std::uint64_t seed = 0;

    /// Π n over the grid axes × samples.
    [[nodiscard]] std::size_t size() const;
    /// The axes' names: the grid's, then the uniform ones'.
    [[nodiscard]] std::vector<std::string> names() const;
    /// Run k's values in the order of names(). A Monte Carlo value is a function of (seed, k,
    /// axis) alone (SplitMix64 of a counter), so it does not depend on which thread runs k.
    void values(std::size_t run, std::span<double> out) const;
};

} // namespace phynjo::runtime
