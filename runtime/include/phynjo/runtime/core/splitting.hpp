#pragma once
/// \file
/// A splitting method's two flows, drift and kick, as rule factories: what the symplectic
/// integrators (symplectic_euler, leapfrog, forest_ruth) compose.
#include "phynjo/runtime/core/workflow.hpp"

#include <functional>

namespace phynjo::runtime {

/// The two flows a splitting method alternates: drift(c) advances positions by c·dt with
/// the momenta held, kick(c) advances momenta by c·dt with the positions held.
struct Splitting {
    std::function<NumericRule(double c)> drift;
    std::function<NumericRule(double c)> kick;
};

} // namespace phynjo::runtime
