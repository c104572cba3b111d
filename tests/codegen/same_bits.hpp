#pragma once
// Bit-for-bit comparisons of the tests of generated code's kernels and of runs
// (test_kernels.cpp, test_lanes.cpp).
#include "phynjo/runtime/simulate/ensemble.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <span>

namespace phynjo::test {

inline bool same_bits(std::span<const double> a, std::span<const double> b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// Two runs' summaries: the same status and reason, the same bits everywhere else.
inline void same_summary(const runtime::RunSummary& a, const runtime::RunSummary& b) {
    CHECK(a.status == b.status);
    CHECK(a.reason == b.reason);
    CHECK(same_bits(a.t, b.t));
    CHECK(same_bits(a.q, b.q));
    CHECK(same_bits(a.qdot, b.qdot));
    CHECK(same_bits(a.first_event, b.first_event));
    CHECK(same_bits(a.max_energy_error, b.max_energy_error));
}

} // namespace phynjo::test
