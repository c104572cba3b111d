// The runtime glue in the generated source: the model as a LagrangianSystem bound to its
// parameters, a world of its coordinates, and its workflows.
#include "emit_detail.hpp"

#include <sstream>

namespace phynjo::codegen::detail {

std::string emit_glue(const Model& m, bool mass_depends_on_velocities) {
    std::ostringstream s;
    s << "namespace {\n"
      << "/// The model with its parameters from `get()`: a copy (system) or live ones (live_system).\n"
      << "template <typename Get>\n"
      << "phynjo::runtime::LagrangianSystem make_system(Get get) {\n"
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
      << "    return s;\n}\n\n"
      << "phynjo::runtime::NumericWorkflow workflow_of(const phynjo::runtime::LagrangianSystem& s,\n"
      << "                                             const phynjo::runtime::World& world, std::string_view integrator) {\n"
      << "    if (integrator == \"rk4\") return phynjo::runtime::lagrangian_rk4(s, world.layout_ptr());\n"
      << "    if (integrator == \"midpoint\") return phynjo::runtime::lagrangian_midpoint(s, world.layout_ptr());\n"
      << "    if (integrator == \"rattle\") return phynjo::runtime::lagrangian_rattle(s, world.layout_ptr());\n"
      << "    if (integrator == \"cvode\") return phynjo::runtime::lagrangian_cvode(s, world.layout_ptr());\n"
      << "    if (integrator == \"ida\") return phynjo::runtime::lagrangian_ida(s, world.layout_ptr());\n"
      << "    throw std::invalid_argument(\"" << m.name
      << "::workflow: unknown integrator '\" + std::string(integrator) + \"' (rk4, midpoint, rattle, cvode or ida)\");\n"
      << "}\n} // namespace\n\n"
      << "phynjo::runtime::LagrangianSystem system(const Parameters& P) {\n"
      << "    return make_system([P]() -> const Parameters& { return P; });\n}\n\n"
      << "phynjo::runtime::LagrangianSystem live_system(const Parameters* P) {\n"
      << "    if (!P) throw std::invalid_argument(\"" << m.name << "::live_system: null parameters\");\n"
      << "    return make_system([P]() -> const Parameters& { return *P; });\n}\n\n"
      << "phynjo::runtime::World make_world(const Parameters& P) { return phynjo::runtime::make_lagrangian_world(system(P)); }\n\n"
      << "phynjo::runtime::NumericWorkflow workflow(const Parameters& P, const phynjo::runtime::World& world,\n"
      << "                                          std::string_view integrator) {\n"
      << "    return workflow_of(system(P), world, integrator);\n"
      << "}\n\n"
      << "phynjo::runtime::NumericWorkflow live_workflow(const Parameters* P, const phynjo::runtime::World& world,\n"
      << "                                               std::string_view integrator) {\n"
      << "    return workflow_of(live_system(P), world, integrator);\n"
      << "}\n\n} // namespace " << m.name << "\n";
    return s.str();
}

} // namespace phynjo::codegen::detail
