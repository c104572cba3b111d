#pragma once
/// \file
/// Newtonian N-body gravity with Plummer softening on a 3-D particle world, as rules.
///
/// a_i = G Σ_{j≠i} m_j (r_j − r_i) / (|r_j − r_i|² + ε²)^{3/2}; every pair is visited once
/// (Newton's third law), so total momentum is conserved to round-off.
#include "phynjo/runtime/particles/particles3d.hpp"

namespace phynjo::runtime {

struct NBodyGravity {
    double G = 1.0;          ///< gravitational constant, m³/(kg·s²) (6.674e-11 in SI)
    double softening = 1e-3; ///< Plummer ε, m
};

/// a ← gravity(r): one rule (partitions = 1), or par(partial_0 … partial_{P−1}) then a
/// combine rule; partial k handles a contiguous block of rows of the pair triangle chosen so
/// that every block has the same number of pairs. The result does not depend on the thread
/// count that runs the par (only on `partitions`).
NumericWorkflow nbody_accelerations(const NBodyGravity& g, const std::shared_ptr<const Layout>& layout,
                                    int partitions = 1);

/// Energy Σ ½ m v² − Σ_{i<j} G m_i m_j / √(r² + ε²), J (the softened potential).
double nbody_energy(const World& particles, const NBodyGravity& g);
/// Total momentum Σ m v, kg·m/s.
Vec3 nbody_momentum(const World& particles);

} // namespace phynjo::runtime
