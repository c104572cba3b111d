// Model kernels (system/kernel.hpp): dlopen, the table checked, and a LagrangianSystem whose
// functions call the kernel's, each status turned back into the typed error.
#include "phynjo/runtime/system/kernel.hpp"

#include <dlfcn.h>

#include <cmath>
#include <stdexcept>
#include <typeinfo>
#include <vector>

namespace phynjo::runtime {

std::shared_ptr<const ModelKernel> ModelKernel::load(const std::string& path) {
    // RTLD_LOCAL: two kernels of models with the same name do not see each other's symbols
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char* why = ::dlerror();
        throw KernelError("cannot load the kernel " + path + ": " + (why ? why : "dlopen failed"));
    }
    auto entry = reinterpret_cast<phynjo_kernel_entry>(::dlsym(handle, PHYNJO_KERNEL_ENTRY));
    if (!entry) {
        ::dlclose(handle);
        throw KernelError(path + " is not a phynjo kernel (no " + std::string(PHYNJO_KERNEL_ENTRY) + ")");
    }
    const phynjo_kernel* table = entry();
    if (!table || table->abi_version != PHYNJO_KERNEL_ABI_VERSION || table->table_size != sizeof(phynjo_kernel)) {
        const unsigned version = table ? table->abi_version : 0;
        ::dlclose(handle);
        throw KernelError(path + " is a kernel of ABI version " + std::to_string(version) + "; this phynjo loads version " +
                          std::to_string(PHYNJO_KERNEL_ABI_VERSION) + " (compile the model again)");
    }
    return std::shared_ptr<const ModelKernel>(new ModelKernel(path, handle, table));
}

ModelKernel::~ModelKernel() {
    if (handle_) ::dlclose(handle_);
}

std::size_t ModelKernel::parameter_index(std::string_view name) const {
    for (std::size_t k = 0; k < table_->n_parameters; ++k)
        if (name == table_->parameter_names[k]) return k;
    std::string known;
    for (std::size_t k = 0; k < table_->n_parameters; ++k) known += (k ? ", " : "") + std::string(table_->parameter_names[k]);
    throw std::invalid_argument("model " + std::string(this->name()) + " has no parameter '" + std::string(name) +
                                "' (its parameters: " + (known.empty() ? "none" : known) + ")");
}

void ModelKernel::check(int status) const {
    if (status == PHYNJO_OK) return;
    const std::string message = table_->last_error();
    switch (status) {
    case PHYNJO_SINGULAR_MASS_MATRIX: throw SingularMassMatrix(message);
    case PHYNJO_SINGULAR_CONSTRAINTS: throw SingularConstraints(message, {});
    case PHYNJO_NON_FINITE: throw NonFiniteResult(message);
    case PHYNJO_INVALID_ARGUMENT: throw std::invalid_argument(message);
    case PHYNJO_OUT_OF_RANGE: throw std::out_of_range(message);
    default: throw Error(message);
    }
}

KernelParameters::KernelParameters(std::shared_ptr<const ModelKernel> kernel) : kernel_(std::move(kernel)) {
    if (!kernel_) throw std::invalid_argument("KernelParameters: no kernel");
    const phynjo_kernel& t = kernel_->table();
    void* p = t.parameters_new();
    if (!p) throw std::bad_alloc();
    object_ = std::shared_ptr<void>(p, [k = kernel_](void* q) { k->table().parameters_delete(q); });
}

KernelParameters::KernelParameters(const KernelParameters& other) : kernel_(other.kernel_) {
    void* p = kernel_->table().parameters_copy(other.object_.get());
    if (!p) throw std::bad_alloc();
    object_ = std::shared_ptr<void>(p, [k = kernel_](void* q) { k->table().parameters_delete(q); });
}

KernelParameters& KernelParameters::operator=(const KernelParameters& other) {
    if (this != &other) *this = KernelParameters(other);
    return *this;
}

void KernelParameters::set(std::size_t k, double value) {
    const phynjo_kernel& t = kernel_->table();
    if (k >= t.n_parameters) throw std::out_of_range("parameter index " + std::to_string(k) + " of " + std::string(t.model_name));
    if (!std::isfinite(value))
        throw std::invalid_argument(std::string("parameter ") + t.parameter_names[k] + " of " + t.model_name + ": " +
                                    std::to_string(value) + " is not a finite number");
    t.parameters_set(object_.get(), k, value);
}
void KernelParameters::set(std::string_view name, double value) { set(kernel_->parameter_index(name), value); }
double KernelParameters::get(std::size_t k) const {
    const phynjo_kernel& t = kernel_->table();
    if (k >= t.n_parameters) throw std::out_of_range("parameter index " + std::to_string(k) + " of " + std::string(t.model_name));
    return t.parameters_get(object_.get(), k);
}
double KernelParameters::get(std::string_view name) const { return get(kernel_->parameter_index(name)); }

namespace {

/// The system over parameters from `get()` (a held copy or live ones), as generated code's
/// make_system builds it from the model's functions.
template <class Get>
LagrangianSystem make_system(const std::shared_ptr<const ModelKernel>& kernel, Get get, std::shared_ptr<const void> held) {
    const phynjo_kernel& t = kernel->table();
    const ModelKernel* k = kernel.get();
    LagrangianSystem s;
    s.dof = t.dof;
    for (std::size_t i = 0; i < t.dof; ++i) s.coordinate_names.emplace_back(t.coordinate_names[i]);
    // every function keeps the kernel loaded
    auto state = [kernel, k, get](phynjo_state_fn f) {
        return [kernel, k, get, f](double time, std::span<const double> q, std::span<const double> v, std::span<double> out) {
            k->check(f(get(), time, q.data(), v.data(), out.data()));
        };
    };
    auto positions = [kernel, k, get](phynjo_positions_fn f) {
        return [kernel, k, get, f](double time, std::span<const double> q, std::span<double> out) {
            k->check(f(get(), time, q.data(), out.data()));
        };
    };
    auto predicate = [k](int r) {
        if (r < 0) k->check(-r);
        return r == 1;
    };
    s.accelerations = state(t.accelerations);
    s.mass_matrix = state(t.mass_matrix);
    s.mass_depends_on_velocities = t.mass_depends_on_velocities != 0;
    s.momenta = state(t.momenta);
    s.generalized_forces = state(t.generalized_forces);
    s.energy = [kernel, k, get, f = t.energy](double time, std::span<const double> q, std::span<const double> v) {
        double e = 0;
        k->check(f(get(), time, q.data(), v.data(), &e));
        return e;
    };
    s.rk4_step = [kernel, k, get, f = t.rk4_step](double time, double h, std::span<double> q, std::span<double> v,
                                                 std::span<const double> a) { k->check(f(get(), time, h, q.data(), v.data(), a.data())); };
    s.accelerations_energy_guards = [kernel, get, predicate, f = t.accelerations_energy_guards](
                                        double time, std::span<const double> q, std::span<const double> v, std::span<double> a,
                                        double& E, std::span<double> g) {
        return predicate(f(get(), time, q.data(), v.data(), a.data(), &E, g.data()));
    };
    s.rk4_step_values = [kernel, get, predicate, f = t.rk4_step_values](double time, double h, double t1, std::span<double> q,
                                                                        std::span<double> v, std::span<double> a, double& E,
                                                                        std::span<double> g) {
        return predicate(f(get(), time, h, t1, q.data(), v.data(), a.data(), &E, g.data()));
    };
    if (t.rk4_step_values_lanes_each && held) {
        s.lane_width = t.lane_width;
        s.rk4_step_values_lanes_each = [kernel, predicate, f = t.rk4_step_values_lanes_each](
                                           const void* const* P, const double* time, const double* h, const double* t1,
                                           double* q, double* v, double* a, double* E, double* g) {
            return predicate(f(P, time, h, t1, q, v, a, E, g));
        };
        s.parameters = std::move(held);
        s.parameters_type = t.parameters_type();
    }
    s.initial_state = [kernel, k, get, f = t.initial_state](std::span<double> q, std::span<double> v) {
        k->check(f(get(), q.data(), v.data()));
    };
    s.n_constraints = t.n_constraints;
    for (std::size_t i = 0; i < t.n_constraints; ++i) {
        s.constraint_names.emplace_back(t.constraint_names[i]);
        s.constraint_holonomic.push_back(t.constraint_holonomic[i]);
    }
    s.constraint_residuals = state(t.constraint_residuals);
    s.constraint_velocity_residuals = state(t.constraint_velocity_residuals);
    s.constraint_scales = state(t.constraint_scales);
    s.constraint_matrix = positions(t.constraint_matrix);
    s.accelerations_and_multipliers = [kernel, k, get, f = t.accelerations_and_multipliers](
                                          double time, std::span<const double> q, std::span<const double> v,
                                          std::span<double> a, std::span<double> lambda) {
        k->check(f(get(), time, q.data(), v.data(), a.data(), lambda.data()));
    };
    s.rhs_jacobian = state(t.rhs_jacobian);
    s.canonical_jacobian = [kernel, k, get, f = t.canonical_jacobian](double time, std::span<const double> q,
                                                                      std::span<const double> v, std::span<double> p,
                                                                      std::span<double> F, std::span<double> dp,
                                                                      std::span<double> dF) {
        k->check(f(get(), time, q.data(), v.data(), p.data(), F.data(), dp.data(), dF.data()));
    };
    s.n_events = t.n_events;
    for (std::size_t i = 0; i < t.n_events; ++i) {
        s.event_names.emplace_back(t.event_names[i]);
        s.event_directions.push_back(t.event_directions[i]);
        s.event_stops.push_back(t.event_stops[i]);
    }
    s.event_guards = state(t.event_guards);
    s.apply_event = [kernel, k, get, f = t.apply_event](std::size_t e, double time, std::span<double> q, std::span<double> v) {
        k->check(f(get(), e, time, q.data(), v.data()));
    };
    s.n_shapes = t.n_shapes;
    for (std::size_t i = 0; i < t.n_shapes; ++i) {
        s.shape_names.emplace_back(t.shape_names[i]);
        s.shape_kinds.push_back(static_cast<ModelShape>(t.shape_kinds[i]));
    }
    s.n_spheres = t.n_spheres;
    s.n_capsules = t.n_capsules;
    s.n_boxes = t.n_boxes;
    s.shape_positions = positions(t.shape_positions);
    s.sphere_jacobians = positions(t.sphere_jacobians);
    s.sphere_radii = [kernel, k, get, f = t.sphere_radii](std::span<double> r) { k->check(f(get(), r.data())); };
    s.capsule_jacobians = positions(t.capsule_jacobians);
    s.capsule_radii = [kernel, k, get, f = t.capsule_radii](std::span<double> r) { k->check(f(get(), r.data())); };
    s.box_jacobians = positions(t.box_jacobians);
    s.box_half_extents = [kernel, k, get, f = t.box_half_extents](std::span<double> h) { k->check(f(get(), h.data())); };
    return s;
}

} // namespace

LagrangianSystem kernel_system(const KernelParameters& P) {
    const KernelParameters copy(P);
    std::shared_ptr<const void> held = copy.shared(); // every function holds the copy
    return make_system(copy.kernel(), [held] { return held.get(); }, held);
}

LagrangianSystem kernel_live_system(const KernelParameters* P) {
    if (!P) throw std::invalid_argument("kernel_live_system: null parameters");
    return make_system(P->kernel(), [P] { return P->data(); }, nullptr);
}

} // namespace phynjo::runtime
