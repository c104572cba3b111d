#pragma once
/// \file
/// Leapfrog (Störmer–Verlet) in its two symmetric forms. Order 2, symplectic,
/// time-reversible. (source: integrators/leapfrog.cpp)
#include "phynjo/runtime/core/splitting.hpp"

namespace phynjo::runtime {

/// Leapfrog, drift-kick-drift (Störmer–Verlet). Order 2, symplectic, time-reversible.
NumericWorkflow leapfrog_dkd(const Splitting& s);
/// Leapfrog, kick-drift-kick (velocity Verlet). Order 2, symplectic, time-reversible.
NumericWorkflow leapfrog_kdk(const Splitting& s);

} // namespace phynjo::runtime
