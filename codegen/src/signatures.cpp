// The one table of generated functions' signatures (signatures.hpp).
#include "signatures.hpp"

#include <cassert>
#include <utility>

namespace phynjo::codegen::detail {

namespace {

constexpr const char* kP = "const Parameters& P";
constexpr const char* kT = "double t";
constexpr const char* kQ = "std::span<const double> q";
constexpr const char* kQd = "std::span<const double> qdot";

Signature make(std::string returns, std::string name, std::vector<Signature::Parameter> parameters) {
    return {std::move(returns), std::move(name), std::move(parameters)};
}

/// f(P, t, q, q', OUT): the shape of most model functions.
Signature of_state(std::string name, std::string out) {
    return make("void", std::move(name), {{kP, ""}, {kT, ""}, {kQ, ""}, {kQd, ""}, {"std::span<double> " + out, ""}});
}
/// f(P, t, q, OUT): functions of the positions alone.
Signature of_positions(std::string name, std::string out) {
    return make("void", std::move(name), {{kP, ""}, {kT, ""}, {kQ, ""}, {"std::span<double> " + out, ""}});
}

} // namespace

std::string Signature::output() const {
    const std::string& d = parameters.back().declaration;
    return d.substr(d.find_last_of(' ') + 1);
}

Signature signature(bool mass_depends_on_velocities, std::string_view name) {
    const std::vector<Signature::Parameter> lanes = {{"const double* t", ""}, {"const double* h", ""}, {"const double* t1", ""},
                                                     {"double* q", ""},       {"double* qdot", ""},    {"double* qddot", ""},
                                                     {"double* E", ""},       {"double* g", ""}};
    auto with_lanes = [&](std::string fn, std::string parameters) {
        Signature s = make("bool", std::move(fn), {{std::move(parameters), ""}});
        s.parameters.insert(s.parameters.end(), lanes.begin(), lanes.end());
        return s;
    };
    if (name == "mass_matrix")
        return mass_depends_on_velocities ? of_state("mass_matrix", "M") : of_positions("mass_matrix", "M");
    for (const auto& [fn, out] : {std::pair{"forcing", "f"}, {"accelerations", "qddot"}, {"momenta", "p"},
                                  {"generalized_forces", "F"}, {"constraint_residuals", "phi"},
                                  {"constraint_velocity_residuals", "psi"}, {"constraint_scales", "scale"},
                                  {"constraint_gamma", "gamma"}, {"rhs_jacobian", "J"}, {"input_jacobian", "B"},
                                  {"event_guards", "g"}})
        if (name == fn) return of_state(fn, out);
    for (const auto& [fn, out] : {std::pair{"constraint_matrix", "G"}, {"shape_positions", "X"}, {"sphere_jacobians", "J"},
                                  {"capsule_jacobians", "J"}, {"box_jacobians", "J"}})
        if (name == fn) return of_positions(fn, out);
    if (name == "energy") return make("double", "energy", {{kP, ""}, {kT, ""}, {kQ, ""}, {kQd, ""}});
    if (name == "rk4_step")
        return make("void", "rk4_step",
                    {{kP, ""}, {kT, ""}, {"double h", ""}, {"std::span<double> q", ""}, {"std::span<double> qdot", ""},
                     {"std::span<const double> qddot", ""}});
    if (name == "accelerations_energy_guards")
        return make("bool", "accelerations_energy_guards",
                    {{kP, ""}, {kT, ""}, {kQ, ""}, {kQd, ""}, {"std::span<double> qddot", ""}, {"double& E", ""},
                     {"std::span<double> g", ""}});
    if (name == "rk4_step_values")
        return make("bool", "rk4_step_values",
                    {{kP, ""}, {kT, ""}, {"double h", ""}, {"double t1", ""}, {"std::span<double> q", ""},
                     {"std::span<double> qdot", ""}, {"std::span<double> qddot", ""}, {"double& E", ""},
                     {"std::span<double> g", ""}});
    if (name == "rk4_step_values_lanes") return with_lanes("rk4_step_values_lanes", kP);
    if (name == "rk4_step_values_lanes_each") return with_lanes("rk4_step_values_lanes_each", "const void* const* P");
    if (name == "initial_state")
        return make("void", "initial_state", {{kP, ""}, {"std::span<double> q", ""}, {"std::span<double> qdot", ""}});
    if (name == "accelerations_and_multipliers")
        return make("void", "accelerations_and_multipliers",
                    {{kP, ""}, {kT, ""}, {kQ, ""}, {kQd, ""}, {"std::span<double> qddot", ""}, {"std::span<double> lambda", ""}});
    if (name == "canonical_jacobian")
        return make("void", "canonical_jacobian",
                    {{kP, ""}, {kT, ""}, {kQ, ""}, {kQd, ""}, {"std::span<double> p", ""}, {"std::span<double> F", ""},
                     {"std::span<double> dp", ""}, {"std::span<double> dF", ""}});
    if (name == "apply_event")
        return make("void", "apply_event",
                    {{kP, ""}, {"std::size_t k", ""}, {kT, ""}, {"std::span<double> q", ""}, {"std::span<double> qdot", ""}});
    if (name == "sphere_radii" || name == "capsule_radii")
        return make("void", std::string(name), {{kP, ""}, {"std::span<double> r", ""}});
    if (name == "box_half_extents") return make("void", "box_half_extents", {{kP, ""}, {"std::span<double> h", ""}});
    if (name == "system") return make("phynjo::runtime::LagrangianSystem", "system", {{kP, "{}"}});
    if (name == "live_system") return make("phynjo::runtime::LagrangianSystem", "live_system", {{"const Parameters* P", ""}});
    if (name == "make_world") return make("phynjo::runtime::World", "make_world", {{kP, "{}"}});
    if (name == "workflow" || name == "live_workflow")
        return make("phynjo::runtime::NumericWorkflow", std::string(name),
                    {{name == "workflow" ? kP : "const Parameters* P", ""},
                     {"const phynjo::runtime::World& world", ""},
                     {"std::string_view integrator", "\"rk4\""}});
    assert(!"a generated function missing from the signature table");
    return {};
}

std::string spelled(const Signature& s, bool defaults) {
    constexpr std::size_t kWidth = 110;
    std::string out = s.returns + " " + s.name + "(";
    const std::size_t indent = out.size();
    std::size_t line = out.size(); // the length of the current line
    for (std::size_t k = 0; k < s.parameters.size(); ++k) {
        const Signature::Parameter& p = s.parameters[k];
        std::string piece = p.declaration;
        if (defaults && !p.fallback.empty()) piece += " = " + p.fallback;
        piece += k + 1 == s.parameters.size() ? ")" : ",";
        if (k > 0 && line + 1 + piece.size() > kWidth) {
            out += "\n" + std::string(indent, ' ');
            line = indent;
        } else if (k > 0) {
            out += " ";
            ++line;
        }
        out += piece;
        line += piece.size();
    }
    return out;
}

std::string declaration(const Signature& s) { return spelled(s, true) + ";\n"; }

std::string definition(const Signature& s) { return spelled(s, false) + " {\n"; }

Signature in_kernel(Signature s) {
    for (Signature::Parameter& p : s.parameters) {
        std::string& d = p.declaration;
        for (const auto& [from, to] : {std::pair<std::string_view, std::string_view>{"std::span<const double> ", "const double* "},
                                       {"std::span<double> ", "double* "},
                                       {"std::size_t ", "size_t "}})
            if (d.compare(0, from.size(), from) == 0) d = std::string(to) + d.substr(from.size());
    }
    return s;
}

} // namespace phynjo::codegen::detail
