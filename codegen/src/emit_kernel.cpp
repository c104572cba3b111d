// A model kernel (phynjo-lagc --emit=kernel; docs/command-line.md, *Kernels*): one translation
// unit holding the header's declarations, the model's functions and the C table of
// phynjo/runtime/system/kernel_abi.h, built into a shared object the runtime loads. It includes
// generated_functions.hpp first, so a precompiled header of it can serve every kernel.
#include "phynjo/codegen/emit.hpp"

#include "emit_detail.hpp"

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
      << "#include <exception>\n#include <new>\n#include <typeinfo>\n\n"
      << "namespace {\n"
      << "namespace k_ = " << m.name << ";\n"
      << "using phynjo::runtime::NonFiniteResult;\nusing phynjo::runtime::SingularConstraints;\n"
      << "using phynjo::runtime::SingularMassMatrix;\n"
      << "thread_local std::string last_error_;\n"
      << "/// The exception being handled as a status, its message kept for last_error: one cold\n"
      << "/// function, so that each wrapper below is a catch-all (what keeps the kernel quick to compile).\n"
      << "[[gnu::cold, gnu::noinline]] int status_of_current() noexcept {\n"
      << "    try {\n        throw;\n"
      << "    } catch (const SingularMassMatrix& e) {\n        last_error_ = e.what();\n        return PHYNJO_SINGULAR_MASS_MATRIX;\n"
      << "    } catch (const SingularConstraints& e) {\n        last_error_ = e.what();\n        return PHYNJO_SINGULAR_CONSTRAINTS;\n"
      << "    } catch (const NonFiniteResult& e) {\n        last_error_ = e.what();\n        return PHYNJO_NON_FINITE;\n"
      << "    } catch (const std::invalid_argument& e) {\n        last_error_ = e.what();\n        return PHYNJO_INVALID_ARGUMENT;\n"
      << "    } catch (const std::out_of_range& e) {\n        last_error_ = e.what();\n        return PHYNJO_OUT_OF_RANGE;\n"
      << "    } catch (const std::exception& e) {\n        last_error_ = e.what();\n        return PHYNJO_ERROR;\n"
      << "    } catch (...) {\n        last_error_ = \"an unknown error\";\n        return PHYNJO_ERROR;\n    }\n}\n"
      << "/// f() with what it throws as a status (the message kept for last_error).\n"
      << "template <class F>\nint guarded(F&& f) noexcept {\n"
      << "    try {\n        f();\n        return PHYNJO_OK;\n"
      << "    } catch (...) {\n        return status_of_current();\n    }\n}\n"
      << "/// A predicate: 1 or 0, or −status when it throws.\n"
      << "template <class F>\nint predicate(F&& f) noexcept {\n    int r = 0;\n"
      << "    const int status = guarded([&] { r = f() ? 1 : 0; });\n    return status != 0 ? -status : r;\n}\n"
      << "const k_::Parameters& P_(const void* P) { return *static_cast<const k_::Parameters*>(P); }\n"
      << "std::span<const double> in_(const double* p, std::size_t n) { return {p, n}; }\n"
      << "std::span<double> out_(double* p, std::size_t n) { return {p, n}; }\n"
      << "constexpr std::size_t n_ = k_::dof, nc_ = k_::n_constraints, ne_ = k_::n_events, ns_ = k_::n_spheres,\n"
      << "                      nk_ = k_::n_capsules, nb_ = k_::n_boxes,\n"
      << "                      nu_ = k_::n_inputs, nx_ = " << shape_values << ";\n\n";

    // the functions, each through guarded()
    auto state = [&](const std::string& fn, const std::string& size) {
        s << "int " << fn << "_(const void* P, double t, const double* q, const double* v, double* out) {\n"
          << "    return guarded([&] { k_::" << fn << "(P_(P), t, in_(q, n_), in_(v, n_), out_(out, " << size << ")); });\n}\n";
    };
    auto positions = [&](const std::string& fn, const std::string& size) {
        s << "int " << fn << "_(const void* P, double t, const double* q, double* out) {\n"
          << "    return guarded([&] { k_::" << fn << "(P_(P), t, in_(q, n_), out_(out, " << size << ")); });\n}\n";
    };
    s << "int mass_matrix_(const void* P, double t, const double* q, const double* v, double* M) {\n"
      << "    (void)v;\n    return guarded([&] { k_::mass_matrix(P_(P), t, in_(q, n_), "
      << (mass_depends_on_velocities ? "in_(v, n_), " : "") << "out_(M, n_ * n_)); });\n}\n";
    state("forcing", "n_");
    state("accelerations", "n_");
    state("momenta", "n_");
    state("generalized_forces", "n_");
    state("constraint_residuals", "nc_");
    state("constraint_velocity_residuals", "nc_");
    state("constraint_scales", "2 * nc_");
    state("constraint_gamma", "nc_");
    state("rhs_jacobian", "4 * n_ * n_");
    state("input_jacobian", "2 * n_ * nu_");
    state("event_guards", "ne_");
    positions("constraint_matrix", "nc_ * n_");
    positions("shape_positions", "nx_");
    positions("sphere_jacobians", "3 * n_ * ns_");
    positions("capsule_jacobians", "6 * n_ * nk_");
    positions("box_jacobians", "6 * n_ * nb_");
    s << "int energy_(const void* P, double t, const double* q, const double* v, double* E) {\n"
      << "    return guarded([&] { *E = k_::energy(P_(P), t, in_(q, n_), in_(v, n_)); });\n}\n"
      << "int accelerations_and_multipliers_(const void* P, double t, const double* q, const double* v, double* a,\n"
      << "                                   double* lambda) {\n"
      << "    return guarded([&] { k_::accelerations_and_multipliers(P_(P), t, in_(q, n_), in_(v, n_), out_(a, n_), out_(lambda, nc_)); });\n}\n"
      << "int canonical_jacobian_(const void* P, double t, const double* q, const double* v, double* p, double* F, double* dp,\n"
      << "                        double* dF) {\n"
      << "    return guarded([&] {\n"
      << "        k_::canonical_jacobian(P_(P), t, in_(q, n_), in_(v, n_), out_(p, n_), out_(F, n_), out_(dp, 2 * n_ * n_),\n"
      << "                               out_(dF, 2 * n_ * n_));\n    });\n}\n"
      << "int rk4_step_(const void* P, double t, double h, double* q, double* v, const double* a) {\n"
      << "    return guarded([&] { k_::rk4_step(P_(P), t, h, out_(q, n_), out_(v, n_), in_(a, n_)); });\n}\n"
      << "int accelerations_energy_guards_(const void* P, double t, const double* q, const double* v, double* a, double* E,\n"
      << "                                 double* g) {\n"
      << "    return predicate([&] { return k_::accelerations_energy_guards(P_(P), t, in_(q, n_), in_(v, n_), out_(a, n_), *E, out_(g, ne_)); });\n}\n"
      << "int rk4_step_values_(const void* P, double t, double h, double t1, double* q, double* v, double* a, double* E,\n"
      << "                     double* g) {\n"
      << "    return predicate([&] { return k_::rk4_step_values(P_(P), t, h, t1, out_(q, n_), out_(v, n_), out_(a, n_), *E, out_(g, ne_)); });\n}\n";
    if (has_lane_kernel(m))
        s << "int rk4_step_values_lanes_each_(const void* const* P, const double* t, const double* h, const double* t1, double* q,\n"
          << "                                double* v, double* a, double* E, double* g) {\n"
          << "    return predicate([&] { return k_::rk4_step_values_lanes_each(P, t, h, t1, q, v, a, E, g); });\n}\n";
    s << "int initial_state_(const void* P, double* q, double* v) {\n"
      << "    return guarded([&] { k_::initial_state(P_(P), out_(q, n_), out_(v, n_)); });\n}\n"
      << "int apply_event_(const void* P, std::size_t k, double t, double* q, double* v) {\n"
      << "    return guarded([&] { k_::apply_event(P_(P), k, t, out_(q, n_), out_(v, n_)); });\n}\n"
      << "int sphere_radii_(const void* P, double* r) { return guarded([&] { k_::sphere_radii(P_(P), out_(r, ns_)); }); }\n"
      << "int capsule_radii_(const void* P, double* r) { return guarded([&] { k_::capsule_radii(P_(P), out_(r, nk_)); }); }\n"
      << "int box_half_extents_(const void* P, double* h) {\n"
      << "    return guarded([&] { k_::box_half_extents(P_(P), out_(h, 3 * nb_)); });\n}\n"
      << "const char* last_error() { return last_error_.c_str(); }\n\n";

    // parameters: made, copied, set and read by index (file order)
    s << "void* parameters_new() { return new (std::nothrow) k_::Parameters(); }\n"
      << "void* parameters_copy(const void* P) { return new (std::nothrow) k_::Parameters(P_(P)); }\n"
      << "void parameters_delete(void* P) { delete static_cast<k_::Parameters*>(P); }\n"
      << "void parameters_set(void* P, std::size_t k, double value) {\n"
      << "    auto& p = *static_cast<k_::Parameters*>(P);\n    switch (k) {\n";
    for (std::size_t j = 0; j < m.parameters.size(); ++j)
        s << "    case " << j << ": p." << m.parameters[j].name << " = value; break;\n";
    s << "    default: break;\n    }\n}\n"
      << "double parameters_get(const void* P, std::size_t k) {\n    const auto& p = P_(P);\n    switch (k) {\n";
    for (std::size_t j = 0; j < m.parameters.size(); ++j)
        s << "    case " << j << ": return p." << m.parameters[j].name << (m.parameters[j].derived() ? ".value()" : "") << ";\n";
    s << "    default: return 0;\n    }\n}\n"
      << "const void* parameters_type() { return &typeid(k_::Parameters); }\n\n";

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
    Definitions functions;
    emit_functions(m, opt, names, functions);
    emit_jacobians(m, eom, names, functions);
    std::string body;
    for (const std::string& f : functions.take()) body += f;
    std::ostringstream s;
    s << "// A model kernel (phynjo-lagc --emit=kernel): the model's functions and the C table of\n"
      << "// phynjo/runtime/system/kernel_abi.h, for the runtime to load (docs/command-line.md).\n"
      << "#include \"phynjo/runtime/system/generated_functions.hpp\" // first: a precompiled header may serve it\n"
      << "#include \"phynjo/runtime/system/kernel_abi.h\"\n"
      << "#define PHYNJO_GENERATED_FUNCTIONS_ONLY // the header's declarations, not the runtime integration\n"
      << emit_header(m, eom.mass_depends_on_velocities) << "#undef PHYNJO_GENERATED_FUNCTIONS_ONLY\n\n"
      << source_preamble(m, "", false, false) << body << "} // namespace " << m.name << "\n"
      << emit_kernel_table(m, eom.mass_depends_on_velocities, version);
    return s.str();
}

} // namespace phynjo::codegen
