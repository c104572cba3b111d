#pragma once
/// \file
/// Inputs that vary in time, from outside the model (a table sampled in time, a signal): the
/// model's functions see each input at the time they are evaluated at.
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <functional>

namespace phynjo::runtime {

/// `system` with `set_inputs(t)` called before each of its functions that takes a time t —
/// `set_inputs` sets the inputs of the parameters `system` reads live (kernel_live_system,
/// generated code's live_system) to their values at t. The fused kernels (rk4_step,
/// rk4_step_values, their lanes) are dropped: they evaluate internal stages the wrapper cannot
/// see, and the integrators then use the functions one by one (the same operations: constant
/// inputs give the bits of the system itself). A system of one run: the functions set shared
/// parameters, so two threads must not step it at once.
LagrangianSystem with_timed_inputs(LagrangianSystem system, std::function<void(double t)> set_inputs);

} // namespace phynjo::runtime
