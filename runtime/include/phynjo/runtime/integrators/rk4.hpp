#pragma once
/// \file
/// Classical Runge–Kutta on NState worlds, as five rules over stage fields. Order 4, not
/// symplectic. (source: integrators/rk4.cpp)
#include "phynjo/runtime/particles/force1d.hpp"

#include <string>
#include <vector>

namespace phynjo::runtime {

/// The stage storage rk4 needs in an NState world (make_nstate(…, …, rk4_fields())).
std::vector<std::string> rk4_fields();
/// Classical Runge–Kutta on q' = p/m, p' = F(q, p): save, four stages, combine — five
/// rules over the world's stage fields. Order 4, not symplectic.
NumericWorkflow rk4(const Force1D& force, const ComponentSet& bodies, std::shared_ptr<const Layout> layout);

} // namespace phynjo::runtime
