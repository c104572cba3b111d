// A model kernel (phynjo-lagc --emit=kernel; docs/command-line.md, *Kernels*): one translation
// unit holding the model's constants and Parameters, its functions in the kernel flavor
// (emit_detail.hpp, Flavor) and the C table of phynjo/runtime/system/kernel_abi.h, built into a
// shared object the runtime loads. It includes runtime/system/kernel_support.hpp alone: no
// standard header, so a small model's kernel builds in a fraction of a second.
#include "phynjo/codegen/emit.hpp"

#include "emit_detail.hpp"
#include "signatures.hpp"

#include <sstream>

namespace phynjo::codegen {

namespace detail {

namespace {

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

/// `const char* const NAME[] = {"a", "b", nullptr};` (the null closes an empty list too).
template <class Range, class Get>
std::string names(const char* name, const Range& items, Get get) {
    std::string s = std::string("const char* const ") + name + "[] = {";
    for (const auto& x : items) s += quoted(get(x)) + ", ";
    return s + "nullptr};\n";
}

template <class Range, class Get>
std::string numbers(const char* type, const char* name, const Range& items, Get get) {
    std::string s = std::string("const ") + type + " " + name + "[] = {";
    for (const auto& x : items) s += get(x) + ", ";
    return s + "0};\n";
}

} // namespace

std::string emit_kernel_table(const Model& m, bool mass_depends_on_velocities, const std::string& version) {
    std::size_t shape_values = 0;
    for (const Shape& s : m.shapes) shape_values += s.point_values();
    std::ostringstream s;
    s << "\n// ---- the C table (phynjo/runtime/system/kernel_abi.h) ----\n"
      << "namespace {\n"
      << "namespace k_ = " << m.name << ";\n"
      << "thread_local char last_error_[sizeof(phynjo::kernel::Failure::what)];\n"
      << "/// The exception being handled as a status, its message kept for last_error: one cold\n"
      << "/// function, so that each wrapper below is a catch-all.\n"
      << "[[gnu::cold, gnu::noinline]] int status_of_current() noexcept {\n"
      << "    try {\n        throw;\n"
      << "    } catch (const phynjo::kernel::Failure& e) {\n"
      << "        __builtin_memcpy(last_error_, e.what, sizeof last_error_);\n        return e.status;\n"
      << "    } catch (...) {\n"
      << "        __builtin_memcpy(last_error_, \"an unknown error\", sizeof \"an unknown error\");\n        return PHYNJO_ERROR;\n"
      << "    }\n}\n"
      << "/// f() with what it throws as a status (the message kept for last_error).\n"
      << "template <class F>\nint guarded(F&& f) noexcept {\n"
      << "    try {\n        f();\n        return PHYNJO_OK;\n"
      << "    } catch (...) {\n        return status_of_current();\n    }\n}\n"
      << "/// A predicate: 1 or 0, or −status when it throws.\n"
      << "template <class F>\nint predicate(F&& f) noexcept {\n    int r = 0;\n"
      << "    const int status = guarded([&] { r = f() ? 1 : 0; });\n    return status != 0 ? -status : r;\n}\n"
      << "const k_::Parameters& P_(const void* P) { return *static_cast<const k_::Parameters*>(P); }\n"
      << "constexpr size_t n_ = k_::dof, nc_ = k_::n_constraints, ne_ = k_::n_events, ns_ = k_::n_spheres,\n"
      << "                 nk_ = k_::n_capsules, nb_ = k_::n_boxes, nu_ = k_::n_inputs, nx_ = " << shape_values << ";\n\n";

    // the functions, each through guarded()
    auto state = [&](const std::string& fn) {
        s << "int " << fn << "_(const void* P, double t, const double* q, const double* v, double* out) {\n"
          << "    return guarded([&] { k_::" << fn << "(P_(P), t, q, v, out); });\n}\n";
    };
    auto positions = [&](const std::string& fn) {
        s << "int " << fn << "_(const void* P, double t, const double* q, double* out) {\n"
          << "    return guarded([&] { k_::" << fn << "(P_(P), t, q, out); });\n}\n";
    };
    s << "int mass_matrix_(const void* P, double t, const double* q, const double* v, double* M) {\n"
      << "    (void)v;\n    return guarded([&] { k_::mass_matrix(P_(P), t, q, " << (mass_depends_on_velocities ? "v, " : "")
      << "M); });\n}\n";
    state("forcing");
    state("accelerations");
    state("momenta");
    state("generalized_forces");
    state("constraint_residuals");
    state("constraint_velocity_residuals");
    state("constraint_scales");
    state("constraint_gamma");
    state("rhs_jacobian");
    state("input_jacobian");
    state("event_guards");
    positions("constraint_matrix");
    positions("shape_positions");
    positions("sphere_jacobians");
    positions("capsule_jacobians");
    positions("box_jacobians");
    s << "int energy_(const void* P, double t, const double* q, const double* v, double* E) {\n"
      << "    return guarded([&] { *E = k_::energy(P_(P), t, q, v); });\n}\n"
      << "int accelerations_and_multipliers_(const void* P, double t, const double* q, const double* v, double* a,\n"
      << "                                   double* lambda) {\n"
      << "    return guarded([&] { k_::accelerations_and_multipliers(P_(P), t, q, v, a, lambda); });\n}\n"
      << "int canonical_jacobian_(const void* P, double t, const double* q, const double* v, double* p, double* F, double* dp,\n"
      << "                        double* dF) {\n"
      << "    return guarded([&] { k_::canonical_jacobian(P_(P), t, q, v, p, F, dp, dF); });\n}\n"
      << "int rk4_step_(const void* P, double t, double h, double* q, double* v, const double* a) {\n"
      << "    return guarded([&] { k_::rk4_step(P_(P), t, h, q, v, a); });\n}\n"
      << "int accelerations_energy_guards_(const void* P, double t, const double* q, const double* v, double* a, double* E,\n"
      << "                                 double* g) {\n"
      << "    return predicate([&] { return k_::accelerations_energy_guards(P_(P), t, q, v, a, *E, g); });\n}\n"
      << "int rk4_step_values_(const void* P, double t, double h, double t1, double* q, double* v, double* a, double* E,\n"
      << "                     double* g) {\n"
      << "    return predicate([&] { return k_::rk4_step_values(P_(P), t, h, t1, q, v, a, *E, g); });\n}\n";
    if (has_lane_kernel(m))
        s << "int rk4_step_values_lanes_each_(const void* const* P, const double* t, const double* h, const double* t1, double* q,\n"
          << "                                double* v, double* a, double* E, double* g) {\n"
          << "    return predicate([&] { return k_::rk4_step_values_lanes_each(P, t, h, t1, q, v, a, E, g); });\n}\n";
    s << "int initial_state_(const void* P, double* q, double* v) {\n"
      << "    return guarded([&] { k_::initial_state(P_(P), q, v); });\n}\n"
      << "int apply_event_(const void* P, size_t k, double t, double* q, double* v) {\n"
      << "    return guarded([&] { k_::apply_event(P_(P), k, t, q, v); });\n}\n"
      << "int sphere_radii_(const void* P, double* r) { return guarded([&] { k_::sphere_radii(P_(P), r); }); }\n"
      << "int capsule_radii_(const void* P, double* r) { return guarded([&] { k_::capsule_radii(P_(P), r); }); }\n"
      << "int box_half_extents_(const void* P, double* h) { return guarded([&] { k_::box_half_extents(P_(P), h); }); }\n"
      << "const char* last_error() { return last_error_; }\n\n";

    // parameters: made, copied, set and read by index (file order)
    s << "void* parameters_new() {\n    try {\n        return new k_::Parameters();\n    } catch (...) {\n        return nullptr;\n    }\n}\n"
      << "void* parameters_copy(const void* P) {\n    try {\n        return new k_::Parameters(P_(P));\n    } catch (...) {\n"
      << "        return nullptr;\n    }\n}\n"
      << "void parameters_delete(void* P) { delete static_cast<k_::Parameters*>(P); }\n"
      << "void parameters_set(void* P, size_t k, double value) {\n"
      << "    auto& p = *static_cast<k_::Parameters*>(P);\n    switch (k) {\n";
    for (std::size_t j = 0; j < m.parameters.size(); ++j)
        s << "    case " << j << ": p." << m.parameters[j].name << " = value; break;\n";
    s << "    default: break;\n    }\n}\n"
      << "double parameters_get(const void* P, size_t k) {\n    const auto& p = P_(P);\n    switch (k) {\n";
    for (std::size_t j = 0; j < m.parameters.size(); ++j)
        s << "    case " << j << ": return p." << m.parameters[j].name << (m.parameters[j].derived() ? ".value()" : "") << ";\n";
    s << "    default: return 0;\n    }\n}\n"
      << "/// This kernel's Parameters type: the address of a byte of its own.\n"
      << "const char parameters_identity_ = 0;\n"
      << "const void* parameters_type() { return &parameters_identity_; }\n\n";

    // the names and flags
    s << names("coordinate_names", m.coordinates, [](const Coordinate& c) { return c.name; })
      << names("parameter_names", m.parameters, [](const Parameter& p) { return p.name; })
      << names("parameter_units", m.parameters, [](const Parameter& p) { return p.unit; })
      << numbers("double", "parameter_defaults", m.parameters, [](const Parameter& p) { return cas::double_literal(p.default_value); })
      << numbers("unsigned char", "parameter_is_input", m.parameters, [](const Parameter& p) { return std::string(p.input ? "1" : "0"); })
      << numbers("unsigned char", "parameter_is_derived", m.parameters, [](const Parameter& p) { return std::string(p.derived() ? "1" : "0"); })
      << names("constraint_names", m.constraints, [](const Constraint& c) { return c.name; })
      << numbers("unsigned char", "constraint_holonomic", m.constraints, [](const Constraint& c) { return std::string(c.holonomic ? "1" : "0"); })
      << names("event_names", m.events, [](const Event& e) { return e.name; })
      << numbers("int", "event_directions", m.events, [](const Event& e) { return std::to_string(e.direction); })
      << numbers("unsigned char", "event_stops", m.events, [](const Event& e) { return std::string(e.stop ? "1" : "0"); })
      << names("shape_names", m.shapes, [](const Shape& x) { return x.name; })
      << numbers("unsigned char", "shape_kinds", m.shapes, [](const Shape& x) { return std::to_string(x.code()); });

    s << "\nconst phynjo_kernel table = {\n"
      << "    PHYNJO_KERNEL_ABI_VERSION, sizeof(phynjo_kernel), " << quoted(m.name) << ", " << quoted(version) << ",\n"
      << "    n_, " << m.parameters.size() << ", nu_, nc_, ne_, k_::n_shapes, ns_, nk_, nb_, nx_, "
      << (has_lane_kernel(m) ? "phynjo::runtime::lanes::kWidth" : "0") << ", " << (mass_depends_on_velocities ? 1 : 0) << ",\n"
      << "    coordinate_names, parameter_names, parameter_units, parameter_defaults, parameter_is_input, parameter_is_derived,\n"
      << "    constraint_names, constraint_holonomic, event_names, event_directions, event_stops, shape_names, shape_kinds,\n"
      << "    parameters_new, parameters_copy, parameters_delete, parameters_set, parameters_get, parameters_type,\n"
      << "    mass_matrix_, forcing_, accelerations_, momenta_, generalized_forces_,\n"
      << "    constraint_residuals_, constraint_velocity_residuals_, constraint_scales_, constraint_gamma_,\n"
      << "    rhs_jacobian_, input_jacobian_, event_guards_, constraint_matrix_, shape_positions_, sphere_jacobians_,\n"
      << "    capsule_jacobians_, box_jacobians_,\n"
      << "    energy_, accelerations_and_multipliers_, canonical_jacobian_, rk4_step_, accelerations_energy_guards_,\n"
      << "    rk4_step_values_, " << (has_lane_kernel(m) ? "rk4_step_values_lanes_each_" : "nullptr")
      << ", initial_state_, apply_event_, sphere_radii_, capsule_radii_, box_half_extents_,\n"
      << "    last_error};\n"
      << "} // namespace\n\n"
      << "extern \"C\" __attribute__((visibility(\"default\"))) const phynjo_kernel* phynjo_kernel_v1(void) { return &table; }\n";
    return s.str();
}

} // namespace detail

std::string emit_kernel(const Model& m, const OptimizedEquations& opt, const EmitOptions& options, const std::string& version) {
    using namespace detail;
    const EquationsOfMotion& eom = opt.eom;
    Names names(m);
    names.piece_threshold = std::max<std::size_t>(options.piece_threshold, 1);
    names.flavor = Flavor::kernel;
    Definitions functions;
    emit_functions(m, opt, names, functions);
    emit_jacobians(m, eom, names, functions);
    std::string body;
    for (const std::string& f : functions.take()) body += f;
    std::size_t n_spheres = 0, n_capsules = 0, n_boxes = 0;
    for (const Shape& sh : m.shapes) {
        n_spheres += sh.kind == Shape::Kind::Sphere ? 1 : 0;
        n_capsules += sh.kind == Shape::Kind::Capsule ? 1 : 0;
        n_boxes += sh.kind == Shape::Kind::Box ? 1 : 0;
    }
    std::ostringstream s;
    s << "// A model kernel (phynjo-lagc --emit=kernel) of " << m.source_name << ": the model's functions and the C\n"
      << "// table of phynjo/runtime/system/kernel_abi.h, for the runtime to load (docs/command-line.md,\n"
      << "// *Kernels*). Generated; do not edit. No standard header: it compiles in a fraction of a second.\n"
      << "#include \"phynjo/runtime/system/kernel_support.hpp\"\n\n"
      << "namespace " << m.name << " {\n\n"
      << "inline constexpr size_t dof = " << m.dof() << ", n_constraints = " << m.constraints.size()
      << ", n_inputs = " << m.n_inputs() << ", n_events = " << m.events.size() << ",\n"
      << "                        n_shapes = " << m.shapes.size() << ", n_spheres = " << n_spheres << ", n_capsules = " << n_capsules
      << ", n_boxes = " << n_boxes << ";\n"
      << "/// The constraints, in file order (named in the messages of a singular G M^-1 G^T).\n"
      << "[[maybe_unused]] const char* const constraint_names[] = {";
    for (const Constraint& c : m.constraints) s << '"' << c.name << "\", ";
    s << "nullptr};\n\n" << parameters_struct(m) << "\n";
    for (const char* fn : {"mass_matrix", "forcing", "accelerations", "momenta", "generalized_forces", "accelerations_and_multipliers",
                           "constraint_residuals", "constraint_velocity_residuals", "constraint_scales", "constraint_gamma",
                           "constraint_matrix", "rhs_jacobian", "input_jacobian", "canonical_jacobian", "event_guards", "energy",
                           "rk4_step", "accelerations_energy_guards", "rk4_step_values", "apply_event", "shape_positions",
                           "sphere_jacobians", "capsule_jacobians", "box_jacobians", "sphere_radii", "capsule_radii",
                           "box_half_extents", "initial_state"})
        s << declaration(in_kernel(signature(eom.mass_depends_on_velocities, fn)));
    if (has_lane_kernel(m))
        s << declaration(in_kernel(signature(eom.mass_depends_on_velocities, "rk4_step_values_lanes_each")))
          << declaration(in_kernel(signature(eom.mass_depends_on_velocities, "rk4_step_values_lanes")));
    s << "\nnamespace {\n" << emit_derived_parameters(m, names) << emit_lane_parameters(m, names) << "} // namespace\n\n"
      << body << "} // namespace " << m.name << "\n" << emit_kernel_table(m, eom.mass_depends_on_velocities, version);
    return s.str();
}

} // namespace phynjo::codegen
