#pragma once
/// \file
/// Forest–Ruth, the fourth-order triple-jump composition of leapfrog. Order 4, symplectic.
/// (source: integrators/forest_ruth.cpp)
#include "phynjo/runtime/core/splitting.hpp"

namespace phynjo::runtime {

/// Forest–Ruth: three leapfrog stages with θ = 1/(2 − 2^(1/3)). Order 4, symplectic.
NumericWorkflow forest_ruth(const Splitting& s);

} // namespace phynjo::runtime
