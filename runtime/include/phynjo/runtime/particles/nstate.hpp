#pragma once
/// \file
/// NState, the 1-D world of point masses: positions q (m), momenta p (kg·m/s) and
/// masses m (kg) per component, and its drift rule. Forces and the kick: force1d.hpp.
#include "phynjo/runtime/core/workflow.hpp"

#include <string>
#include <vector>

namespace phynjo::runtime {

/// Field ids of an NState world.
inline constexpr FieldId kQ = 0, kP = 1, kM = 2;

/// A 1-D world of point masses: fields q (m), p (kg·m/s) and m (kg) for every component of
/// `components`, with the given masses (all 1 kg when `masses` is empty), then the
/// `extra_fields` (for example the stage storage of rk4: rk4_fields()). Throws InvalidBody
/// for a mass that is not positive and finite, std::invalid_argument for a count mismatch.
World make_nstate(const Registry& components, const std::vector<double>& masses = {},
                  const std::vector<std::string>& extra_fields = {});

/// Lookups and updates (lookup, insert, adjust: the glossary of docs/architecture.md).
inline double lookup_pos(Index c, const World& w) { return w.at(kQ, c); }
inline double lookup_mom(Index c, const World& w) { return w.at(kP, c); }
inline void insert_pos(Index c, double q, World& w) { w.at(kQ, c) = q; }
inline void insert_mom(Index c, double p, World& w) { w.at(kP, c) = p; }

/// Kinetic energy Σ p²/(2m), J.
double kinetic_energy(const World& nstate);
/// Total momentum Σ p, kg·m/s.
double total_momentum(const World& nstate);

/// q_i ← q_i + c·dt·p_i/m_i. Domain: q of `bodies`.
NumericRule drift(const ComponentSet& bodies, double c, const std::shared_ptr<const Layout>& layout);

} // namespace phynjo::runtime
