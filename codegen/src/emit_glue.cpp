// The runtime glue in the generated source: the model as a LagrangianSystem bound to its
// parameters, a world of its coordinates, and its workflows.
#include "emit_detail.hpp"
#include "signatures.hpp"

#include <sstream>

namespace phynjo::codegen::detail {

std::string emit_glue(const Model& m, bool mass_depends_on_velocities) {
    std::ostringstream s;
    s << "namespace {\n"
      << "/// The model with its parameters from `get()`: a copy (system) or live ones (live_system);\n"
      << "/// `held` points to them (and owns the copy).\n"
      << "template <typename Get>\n"
      << "phynjo::runtime::LagrangianSystem make_system(Get get, std::shared_ptr<const Parameters> held) {\n"
      << "    phynjo::runtime::LagrangianSystem s;\n"
      << "    s.dof = dof;\n"
      << "    for (auto n : coordinate_names) s.coordinate_names.emplace_back(n);\n"
      << "    s.accelerations = [get](double t, std::span<const double> q, std::span<const double> v, std::span<double> a) {\n"
      << "        accelerations(get(), t, q, v, a);\n    };\n"
      << "    s.mass_matrix = [get](double t, std::span<const double> q, std::span<const double> v, std::span<double> M) {\n"
      << (mass_depends_on_velocities ? "        mass_matrix(get(), t, q, v, M);\n" : "        (void)v;\n        mass_matrix(get(), t, q, M);\n")
      << "    };\n"
      << "    s.mass_depends_on_velocities = " << (mass_depends_on_velocities ? "true" : "false") << ";\n"
      << "    s.momenta = [get](double t, std::span<const double> q, std::span<const double> v, std::span<double> p) {\n"
      << "        momenta(get(), t, q, v, p);\n    };\n"
      << "    s.generalized_forces = [get](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                               std::span<double> F) { generalized_forces(get(), t, q, v, F); };\n"
      << "    s.energy = [get](double t, std::span<const double> q, std::span<const double> v) { return energy(get(), t, q, v); };\n"
      << "    s.rk4_step = [get](double t, double h, std::span<double> q, std::span<double> v, std::span<const double> a) {\n"
      << "        rk4_step(get(), t, h, q, v, a);\n    };\n"
      << "    s.accelerations_energy_guards = [get](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                          std::span<double> a, double& E, std::span<double> g) {\n"
      << "        return accelerations_energy_guards(get(), t, q, v, a, E, g);\n    };\n"
      << "    s.rk4_step_values = [get](double t, double h, double t1, std::span<double> q, std::span<double> v,\n"
      << "                              std::span<double> a, double& E, std::span<double> g) {\n"
      << "        return rk4_step_values(get(), t, h, t1, q, v, a, E, g);\n    };\n"
      << (has_lane_kernel(m) ? "    s.lane_width = phynjo::runtime::lanes::kWidth;\n"
                               "    s.rk4_step_values_lanes_each = &rk4_step_values_lanes_each;\n"
                               "    s.parameters = held;\n"
                               "    s.parameters_type = &typeid(Parameters);\n"
                             : "    (void)held;\n")
      << "    s.initial_state = [get](std::span<double> q, std::span<double> v) { initial_state(get(), q, v); };\n"
      << "    s.n_constraints = n_constraints;\n"
      << "    for (auto n : constraint_names) s.constraint_names.emplace_back(n);\n"
      << "    s.constraint_holonomic = {";
    for (std::size_t k = 0; k < m.constraints.size(); ++k) s << (k ? ", " : "") << (m.constraints[k].holonomic ? 1 : 0);
    s << "};\n"
      << "    s.constraint_residuals = [get](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                 std::span<double> phi) { constraint_residuals(get(), t, q, v, phi); };\n"
      << "    s.constraint_velocity_residuals = [get](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                          std::span<double> psi) { constraint_velocity_residuals(get(), t, q, v, psi); };\n"
      << "    s.constraint_scales = [get](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                              std::span<double> scale) { constraint_scales(get(), t, q, v, scale); };\n"
      << "    s.constraint_matrix = [get](double t, std::span<const double> q, std::span<double> G) {\n"
      << "        constraint_matrix(get(), t, q, G);\n    };\n"
      << "    s.accelerations_and_multipliers = [get](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                          std::span<double> a, std::span<double> lambda) {\n"
      << "        accelerations_and_multipliers(get(), t, q, v, a, lambda);\n    };\n"
      << "    s.rhs_jacobian = [get](double t, std::span<const double> q, std::span<const double> v, std::span<double> J) {\n"
      << "        rhs_jacobian(get(), t, q, v, J);\n    };\n"
      << "    s.canonical_jacobian = [get](double t, std::span<const double> q, std::span<const double> v, std::span<double> p,\n"
      << "                                 std::span<double> F, std::span<double> dp, std::span<double> dF) {\n"
      << "        canonical_jacobian(get(), t, q, v, p, F, dp, dF);\n    };\n"
      << "    s.n_events = n_events;\n"
      << "    for (auto n : event_names) s.event_names.emplace_back(n);\n"
      << "    s.event_directions.assign(event_directions.begin(), event_directions.end());\n"
      << "    s.event_stops.assign(event_stops.begin(), event_stops.end());\n"
      << "    s.event_guards = [get](double t, std::span<const double> q, std::span<const double> v, std::span<double> g) {\n"
      << "        event_guards(get(), t, q, v, g);\n    };\n"
      << "    s.apply_event = [get](std::size_t k, double t, std::span<double> q, std::span<double> v) {\n"
      << "        apply_event(get(), k, t, q, v);\n    };\n"
      << "    s.n_shapes = n_shapes;\n"
      << "    for (auto n : shape_names) s.shape_names.emplace_back(n);\n"
      << "    for (auto k : shape_kinds) s.shape_kinds.push_back(static_cast<phynjo::runtime::ModelShape>(k));\n"
      << "    s.n_spheres = n_spheres;\n"
      << "    s.n_capsules = n_capsules;\n"
      << "    s.n_boxes = n_boxes;\n"
      << "    s.shape_positions = [get](double t, std::span<const double> q, std::span<double> X) {\n"
      << "        shape_positions(get(), t, q, X);\n    };\n"
      << "    s.sphere_jacobians = [get](double t, std::span<const double> q, std::span<double> J) {\n"
      << "        sphere_jacobians(get(), t, q, J);\n    };\n"
      << "    s.sphere_radii = [get](std::span<double> r) { sphere_radii(get(), r); };\n"
      << "    s.capsule_jacobians = [get](double t, std::span<const double> q, std::span<double> J) {\n"
      << "        capsule_jacobians(get(), t, q, J);\n    };\n"
      << "    s.capsule_radii = [get](std::span<double> r) { capsule_radii(get(), r); };\n"
      << "    s.box_jacobians = [get](double t, std::span<const double> q, std::span<double> J) {\n"
      << "        box_jacobians(get(), t, q, J);\n    };\n"
      << "    s.box_half_extents = [get](std::span<double> h) { box_half_extents(get(), h); };\n"
      << "    return s;\n}\n\n"
      << "phynjo::runtime::NumericWorkflow workflow_of(const phynjo::runtime::LagrangianSystem& s,\n"
      << "                                             const phynjo::runtime::World& world, std::string_view integrator) {\n"
      << "    return phynjo::runtime::integrator_workflow(s, world, integrator, \"" << m.name << "::workflow\");\n"
      << "}\n} // namespace\n\n"
      << definition(signature(mass_depends_on_velocities, "system"))
      << "    auto held = std::make_shared<const Parameters>(P);\n"
      << "    return make_system([held]() -> const Parameters& { return *held; }, held);\n}\n\n"
      << definition(signature(mass_depends_on_velocities, "live_system"))
      << "    if (!P) throw std::invalid_argument(\"" << m.name << "::live_system: null parameters\");\n"
      << "    return make_system([P]() -> const Parameters& { return *P; }, std::shared_ptr<const Parameters>(std::shared_ptr<const Parameters>(), P));\n}\n\n"
      << definition(signature(mass_depends_on_velocities, "make_world"))
      << "    return phynjo::runtime::make_lagrangian_world(system(P));\n}\n\n"
      << definition(signature(mass_depends_on_velocities, "workflow"))
      << "    return workflow_of(system(P), world, integrator);\n"
      << "}\n\n"
      << definition(signature(mass_depends_on_velocities, "live_workflow"))
      << "    return workflow_of(live_system(P), world, integrator);\n"
      << "}\n\n} // namespace " << m.name << "\n";
    return s.str();
}

} // namespace phynjo::codegen::detail
