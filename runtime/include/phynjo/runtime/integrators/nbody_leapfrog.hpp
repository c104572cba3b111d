#pragma once
/// \file
/// Leapfrog (drift-kick-drift) for N-body gravity. Order 2, symplectic, time-reversible.
/// Reference: L. Verlet, Phys. Rev. 159, 98 (1967).
#include "phynjo/runtime/particles/nbody.hpp"

namespace phynjo::runtime {

/// Leapfrog DKD for N-body: drift(½) · accelerations · kick(1) · drift(½). One force
/// evaluation per step. Order 2, symplectic.
NumericWorkflow nbody_leapfrog(const NBodyGravity& g, const std::shared_ptr<const Layout>& layout, int partitions = 1);

} // namespace phynjo::runtime
