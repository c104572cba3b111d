// Inputs varying in time (timed_inputs.hpp).
#include "phynjo/runtime/system/timed_inputs.hpp"

#include <utility>

namespace phynjo::runtime {

namespace {

/// f with set(t) first; empty stays empty.
template <class R, class... A>
std::function<R(double, A...)> at_time(std::function<R(double, A...)> f, const std::function<void(double)>& set) {
    if (!f) return f;
    return [f = std::move(f), set](double t, A... a) -> R {
        set(t);
        return f(t, std::forward<A>(a)...);
    };
}

} // namespace

LagrangianSystem with_timed_inputs(LagrangianSystem s, std::function<void(double t)> set) {
    s.accelerations = at_time(std::move(s.accelerations), set);
    s.mass_matrix = at_time(std::move(s.mass_matrix), set);
    s.momenta = at_time(std::move(s.momenta), set);
    s.generalized_forces = at_time(std::move(s.generalized_forces), set);
    s.energy = at_time(std::move(s.energy), set);
    s.rk4_step = nullptr;
    s.accelerations_energy_guards = nullptr;
    s.rk4_step_values = nullptr;
    s.rk4_step_values_lanes_each = nullptr;
    s.lane_width = 0;
    s.constraint_residuals = at_time(std::move(s.constraint_residuals), set);
    s.constraint_velocity_residuals = at_time(std::move(s.constraint_velocity_residuals), set);
    s.constraint_scales = at_time(std::move(s.constraint_scales), set);
    s.constraint_matrix = at_time(std::move(s.constraint_matrix), set);
    s.accelerations_and_multipliers = at_time(std::move(s.accelerations_and_multipliers), set);
    s.event_guards = at_time(std::move(s.event_guards), set);
    if (s.apply_event)
        s.apply_event = [f = std::move(s.apply_event), set](std::size_t k, double t, std::span<double> q, std::span<double> v) {
            set(t);
            f(k, t, q, v);
        };
    s.shape_positions = at_time(std::move(s.shape_positions), set);
    s.sphere_jacobians = at_time(std::move(s.sphere_jacobians), set);
    s.capsule_jacobians = at_time(std::move(s.capsule_jacobians), set);
    s.box_jacobians = at_time(std::move(s.box_jacobians), set);
    s.rhs_jacobian = at_time(std::move(s.rhs_jacobian), set);
    s.canonical_jacobian = at_time(std::move(s.canonical_jacobian), set);
    return s;
}

} // namespace phynjo::runtime
