#pragma once
/// \file
/// Symplectic Euler. Order 1, symplectic. (source: integrators/symplectic_euler.cpp)
#include "phynjo/runtime/core/splitting.hpp"

namespace phynjo::runtime {

/// Symplectic Euler: kick(1) then drift(1). Order 1, symplectic.
NumericWorkflow symplectic_euler(const Splitting& s);

} // namespace phynjo::runtime
