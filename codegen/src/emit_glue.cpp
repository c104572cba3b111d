// The runtime glue in the generated source: the model as a LagrangianSystem bound to its
// parameters, a world of its coordinates, and its workflows.
#include "emit_detail.hpp"

#include <sstream>

namespace phynjo::codegen::detail {

std::string emit_glue(const Model& m, bool mass_depends_on_velocities) {
    std::ostringstream s;
    s << "phynjo::runtime::LagrangianSystem system(const Parameters& P) {\n"
      << "    phynjo::runtime::LagrangianSystem s;\n"
      << "    s.dof = dof;\n"
      << "    for (auto n : coordinate_names) s.coordinate_names.emplace_back(n);\n"
      << "    s.accelerations = [P](double t, std::span<const double> q, std::span<const double> v, std::span<double> a) {\n"
      << "        accelerations(P, t, q, v, a);\n    };\n"
      << "    s.mass_matrix = [P](double t, std::span<const double> q, std::span<const double> v, std::span<double> M) {\n"
      << (mass_depends_on_velocities ? "        mass_matrix(P, t, q, v, M);\n" : "        (void)v;\n        mass_matrix(P, t, q, M);\n")
      << "    };\n"
      << "    s.mass_depends_on_velocities = " << (mass_depends_on_velocities ? "true" : "false") << ";\n"
      << "    s.momenta = [P](double t, std::span<const double> q, std::span<const double> v, std::span<double> p) {\n"
      << "        momenta(P, t, q, v, p);\n    };\n"
      << "    s.generalized_forces = [P](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                               std::span<double> F) { generalized_forces(P, t, q, v, F); };\n"
      << "    s.energy = [P](double t, std::span<const double> q, std::span<const double> v) { return energy(P, t, q, v); };\n"
      << "    s.initial_state = [P](std::span<double> q, std::span<double> v) { initial_state(P, q, v); };\n"
      << "    s.n_constraints = n_constraints;\n"
      << "    for (auto n : constraint_names) s.constraint_names.emplace_back(n);\n"
      << "    s.constraint_holonomic = {";
    for (std::size_t k = 0; k < m.constraints.size(); ++k) s << (k ? ", " : "") << (m.constraints[k].holonomic ? 1 : 0);
    s << "};\n"
      << "    s.constraint_residuals = [P](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                 std::span<double> phi) { constraint_residuals(P, t, q, v, phi); };\n"
      << "    s.constraint_velocity_residuals = [P](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                          std::span<double> psi) { constraint_velocity_residuals(P, t, q, v, psi); };\n"
      << "    s.constraint_scales = [P](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                              std::span<double> scale) { constraint_scales(P, t, q, v, scale); };\n"
      << "    s.constraint_matrix = [P](double t, std::span<const double> q, std::span<double> G) {\n"
      << "        constraint_matrix(P, t, q, G);\n    };\n"
      << "    s.accelerations_and_multipliers = [P](double t, std::span<const double> q, std::span<const double> v,\n"
      << "                                          std::span<double> a, std::span<double> lambda) {\n"
      << "        accelerations_and_multipliers(P, t, q, v, a, lambda);\n    };\n"
      << "    return s;\n}\n\n"
      << "phynjo::runtime::World make_world(const Parameters& P) { return phynjo::runtime::make_lagrangian_world(system(P)); }\n\n"
      << "phynjo::runtime::NumericWorkflow workflow(const Parameters& P, const phynjo::runtime::World& world,\n"
      << "                                          std::string_view integrator) {\n"
      << "    if (integrator == \"rk4\") return phynjo::runtime::lagrangian_rk4(system(P), world.layout_ptr());\n"
      << "    if (integrator == \"midpoint\") return phynjo::runtime::lagrangian_midpoint(system(P), world.layout_ptr());\n"
      << "    if (integrator == \"rattle\") return phynjo::runtime::lagrangian_rattle(system(P), world.layout_ptr());\n"
      << "    throw std::invalid_argument(\"" << m.name
      << "::workflow: unknown integrator '\" + std::string(integrator) + \"' (rk4, midpoint or rattle)\");\n"
      << "}\n\n} // namespace " << m.name << "\n";
    return s.str();
}

} // namespace phynjo::codegen::detail
