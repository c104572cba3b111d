// _phynjo: the Python package's compiled half (python/phynjo/__init__.py is the other). A
// model is a kernel (jit/compile.hpp) loaded into the runtime (runtime/system/kernel.hpp):
// the functions of the kernel's table over NumPy arrays, batched over leading axes; runs
// through the runtime's run_one; the simulator's command line through model_main — the code
// paths of phynjo-run and of CMake-built simulators, not a second engine. The GIL is released
// while C++ computes.
#include "phynjo/jit/compile.hpp"
#include "phynjo/jit/document.hpp"
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/simulate/integrator_registry.hpp"
#include "phynjo/runtime/simulate/model_main.hpp"
#include "phynjo/runtime/simulate/runs.hpp"
#include "phynjo/runtime/system/kernel.hpp"
#include "phynjo/runtime/system/timed_inputs.hpp"
#include "phynjo/runtime/view/recorder.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace py = pybind11;
using namespace phynjo;
using runtime::KernelParameters;
using runtime::ModelKernel;

namespace {

/// A compiled and loaded model.
struct Kernel {
    std::shared_ptr<const ModelKernel> kernel;
    jit::CompiledModel compiled;
    [[nodiscard]] const phynjo_kernel& table() const { return kernel->table(); }
};

Kernel load(const jit::CompiledModel& c) { return Kernel{ModelKernel::load(c.kernel_path), c}; }

jit::JitOptions options_of(const std::string& cache_dir, bool verbose, bool quick) {
    jit::JitOptions o;
    o.cache_dir = cache_dir;
    o.verbose = verbose;
    o.quick = quick;
    return o;
}

/// The parameters of one call: the file's values, then `params` (name → value).
KernelParameters parameters_of(const Kernel& k, const py::dict& params) {
    KernelParameters P(k.kernel);
    for (const auto& [name, value] : params) P.set(py::cast<std::string>(name), py::cast<double>(value));
    return P;
}

/// The model functions a batched call evaluates, each with the shape of one result.
enum class Fn { accelerations, mass_matrix, forcing, energy, momenta, generalized_forces, rhs_jacobian, input_jacobian,
                constraint_residuals };

std::vector<py::ssize_t> result_shape(const phynjo_kernel& t, Fn f) {
    const auto n = static_cast<py::ssize_t>(t.dof);
    switch (f) {
    case Fn::accelerations:
    case Fn::forcing:
    case Fn::momenta:
    case Fn::generalized_forces: return {n};
    case Fn::mass_matrix: return {n, n};
    case Fn::energy: return {};
    case Fn::rhs_jacobian: return {2 * n, 2 * n};
    case Fn::input_jacobian: return {2 * n, static_cast<py::ssize_t>(t.n_inputs)};
    case Fn::constraint_residuals: return {static_cast<py::ssize_t>(t.n_constraints)};
    }
    return {};
}

std::string shape_text(const std::vector<py::ssize_t>& s) {
    std::string out = "(";
    for (std::size_t i = 0; i < s.size(); ++i) out += (i ? ", " : "") + std::to_string(s[i]);
    return out + (s.size() == 1 ? ",)" : ")");
}

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// True when the bytes of `a` and `b` meet.
bool overlap(const py::array& a, const py::array& b) {
    const auto* a0 = static_cast<const char*>(a.data());
    const auto* b0 = static_cast<const char*>(b.data());
    return a0 < b0 + b.nbytes() && b0 < a0 + a.nbytes();
}

/// `f` at every state of q and q' (shape (..., dof) each): shape (..., result).
py::array evaluate(const Kernel& k, Fn f, const Array& q, const Array& qd, double t, const py::dict& params,
                   const py::object& out_arg) {
    const phynjo_kernel& tab = k.table();
    const std::size_t n = tab.dof;
    if (q.ndim() < 1 || static_cast<std::size_t>(q.shape(q.ndim() - 1)) != n)
        throw py::value_error("q must have shape (..., " + std::to_string(n) + ") (the model's " + std::to_string(n) +
                              " coordinates), not " + shape_text({q.shape(), q.shape() + q.ndim()}));
    if (qd.ndim() != q.ndim() || !std::equal(q.shape(), q.shape() + q.ndim(), qd.shape()))
        throw py::value_error("qd must have the shape of q, " + shape_text({q.shape(), q.shape() + q.ndim()}) + ", not " +
                              shape_text({qd.shape(), qd.shape() + qd.ndim()}));
    if (!std::isfinite(t)) throw py::value_error("t must be finite");
    std::vector<py::ssize_t> shape(q.shape(), q.shape() + q.ndim() - 1);
    const std::size_t states = static_cast<std::size_t>(q.size()) / std::max<std::size_t>(n, 1);
    const std::vector<py::ssize_t> one = result_shape(tab, f);
    shape.insert(shape.end(), one.begin(), one.end());
    std::size_t m = 1;
    for (const py::ssize_t s : one) m *= static_cast<std::size_t>(s);

    py::array_t<double> out;
    if (out_arg.is_none()) out = py::array_t<double>(shape);
    else {
        if (!py::isinstance<py::array_t<double>>(out_arg) || !py::array(out_arg).dtype().is(py::dtype::of<double>()))
            throw py::type_error("out must be a NumPy array of float64");
        out = py::reinterpret_borrow<py::array_t<double>>(out_arg);
        if (!std::equal(shape.begin(), shape.end(), out.shape(), out.shape() + out.ndim()) ||
            static_cast<std::size_t>(out.ndim()) != shape.size())
            throw py::value_error("out must have shape " + shape_text(shape) + ", not " +
                                  shape_text({out.shape(), out.shape() + out.ndim()}));
        if (!(out.flags() & py::array::c_style)) throw py::value_error("out must be C-contiguous");
        if (!out.writeable()) throw py::value_error("out is read-only");
        if (overlap(out, q) || overlap(out, qd)) throw py::value_error("out must not share memory with q or qd");
    }
    const KernelParameters P = parameters_of(k, params);
    const double* qp = q.data();
    const double* vp = qd.data();
    double* op = out.mutable_data();
    int status = PHYNJO_OK;
    {
        py::gil_scoped_release release;
        const void* p = P.data();
        phynjo_state_fn g = nullptr;
        switch (f) {
        case Fn::accelerations: g = tab.accelerations; break;
        case Fn::mass_matrix: g = tab.mass_matrix; break;
        case Fn::forcing: g = tab.forcing; break;
        case Fn::momenta: g = tab.momenta; break;
        case Fn::generalized_forces: g = tab.generalized_forces; break;
        case Fn::rhs_jacobian: g = tab.rhs_jacobian; break;
        case Fn::input_jacobian: g = tab.input_jacobian; break;
        case Fn::constraint_residuals: g = tab.constraint_residuals; break;
        case Fn::energy: break;
        }
        if (f == Fn::energy)
            for (std::size_t i = 0; i < states && status == PHYNJO_OK; ++i) status = tab.energy(p, t, qp + i * n, vp + i * n, op + i);
        else
            for (std::size_t i = 0; i < states && status == PHYNJO_OK; ++i) status = g(p, t, qp + i * n, vp + i * n, op + i * m);
    }
    k.kernel->check(status);
    return out;
}

/// A vector as a NumPy array that owns it (no copy).
py::array_t<double> numpy_of(std::vector<double>&& v, std::vector<py::ssize_t> shape) {
    auto* held = new std::vector<double>(std::move(v));
    py::capsule owner(held, [](void* p) { delete static_cast<std::vector<double>*>(p); });
    return py::array_t<double>(shape, held->data(), owner);
}

const char* status_name(runtime::RunSummary::Status s) {
    switch (s) {
    case runtime::RunSummary::Status::finished: return "finished";
    case runtime::RunSummary::Status::stopped: return "stopped";
    case runtime::RunSummary::Status::failed: return "failed";
    }
    return "failed";
}

/// An input given as a table sampled in time: piecewise linear between the samples, held
/// beyond them.
struct TimedInput {
    std::size_t index; ///< the parameter's index in the kernel's table
    std::vector<double> times, values;
    [[nodiscard]] double at(double t) const {
        if (t <= times.front()) return values.front();
        if (t >= times.back()) return values.back();
        const auto i = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
        const double s = (t - times[i - 1]) / (times[i] - times[i - 1]);
        return values[i - 1] + s * (values[i] - values[i - 1]);
    }
};

/// The index of input `name`, or std::invalid_argument naming the model's inputs.
std::size_t input_index(const Kernel& k, const std::string& name) {
    const phynjo_kernel& t = k.table();
    for (std::size_t i = 0; i < t.n_parameters; ++i)
        if (t.parameter_is_input[i] && name == t.parameter_names[i]) return i;
    std::string names;
    for (std::size_t i = 0; i < t.n_parameters; ++i)
        if (t.parameter_is_input[i]) names += (names.empty() ? "" : ", ") + std::string(t.parameter_names[i]);
    std::string message = "'"; // (appended: GCC 12 misreads a chain of + here as an overflow)
    message.append(name).append("' is not an input of ").append(t.model_name).append(" (inputs: ");
    message.append(names.empty() ? "none" : names).append(")");
    throw std::invalid_argument(message);
}

/// One run (runtime/simulate/runs.hpp's run_one): its rows t, q…, q'…, E as one array and its
/// summary. `inputs`: name → (times, values), each input at every evaluation time;
/// `control`: a callable (t, q, q') → {input: value} every `control_every` steps.
py::dict simulate(const Kernel& k, double t_end, double dt, const std::string& integrator, const py::dict& params,
                  const std::vector<std::pair<std::size_t, double>>& q0, const std::vector<std::pair<std::size_t, double>>& v0,
                  long every, std::optional<double> rtol, std::optional<double> atol,
                  const std::vector<std::tuple<std::string, std::vector<double>, std::vector<double>>>& inputs,
                  const py::object& control, long control_every) {
    if (!(std::isfinite(t_end) && t_end >= 0)) throw py::value_error("t_end must be finite and >= 0");
    if (!(std::isfinite(dt) && dt > 0)) throw py::value_error("dt must be finite and > 0");
    if (every < 1) throw py::value_error("every must be >= 1");
    for (const auto& tol : {rtol, atol})
        if (tol && !(std::isfinite(*tol) && *tol > 0)) throw py::value_error("rtol and atol must be finite and > 0");
    const runtime::IntegratorEntry* entry = runtime::find_integrator(integrator);
    if (entry && (rtol || atol) && !entry->tolerances)
        throw py::value_error("rtol and atol go with an adaptive integrator (dopri), not " + integrator);
    const std::size_t n = k.table().dof;
    for (const auto& [i, v] : q0)
        if (i >= n || !std::isfinite(v)) throw py::value_error("initial values: a coordinate index or value is wrong");
    for (const auto& [i, v] : v0)
        if (i >= n || !std::isfinite(v)) throw py::value_error("initial values: a velocity index or value is wrong");
    std::vector<TimedInput> timed;
    for (const auto& [name, times, values] : inputs) {
        TimedInput in{input_index(k, name), times, values};
        if (times.empty() || times.size() != values.size())
            throw py::value_error("inputs['" + name + "']: times and values of one length, at least one sample");
        for (std::size_t i = 0; i < times.size(); ++i) {
            if (!std::isfinite(times[i]) || !std::isfinite(values[i]))
                throw py::value_error("inputs['" + name + "']: times and values must be finite");
            if (i > 0 && !(times[i] > times[i - 1]))
                throw py::value_error("inputs['" + name + "']: times must increase");
        }
        timed.push_back(std::move(in));
    }
    if (control_every < 1) throw py::value_error("control_every must be >= 1");
    if (!control.is_none() && !PyCallable_Check(control.ptr())) throw py::type_error("control must be callable: (t, q, qd) -> {input: value}");
    KernelParameters P = parameters_of(k, params);
    runtime::RunSettings s;
    s.t_end = t_end;
    s.dt = dt;
    s.integrator = integrator;
    s.every = every;
    s.rtol = rtol;
    s.atol = atol;
    s.event_log = true;
    // what the control function raised (or its result's misuse), raised again here; run_one
    // sees a plain error (no Python object leaves the interpreter's lock)
    std::exception_ptr control_error;
    // what the controller set, when (t, input index, value): Result.html shows the run's shapes
    // with the inputs they had
    std::vector<std::tuple<double, std::size_t, double>> control_log;
    const std::size_t n_state = k.table().dof;
    if (!control.is_none()) {
        s.control_every = control_every;
        s.control = [&](double t, std::span<const double> q, std::span<const double> v) {
            py::gil_scoped_acquire acquire;
            try {
                const py::object set = control(t, py::array_t<double>(static_cast<py::ssize_t>(n_state), q.data()),
                                               py::array_t<double>(static_cast<py::ssize_t>(n_state), v.data()));
                if (!py::isinstance<py::dict>(set))
                    throw py::type_error("control must return a dict {input: value}, not " +
                                         std::string(py::str(py::type::of(set).attr("__name__"))));
                for (const auto& [name, value] : py::reinterpret_borrow<py::dict>(set)) {
                    const std::size_t i = input_index(k, py::cast<std::string>(name));
                    const double x = py::cast<double>(value);
                    if (!std::isfinite(x))
                        throw py::value_error("control returned " + py::cast<std::string>(name) + " = " + std::to_string(x) +
                                              " at t = " + std::to_string(t));
                    P.set(i, x);
                    control_log.emplace_back(t, i, x);
                }
            } catch (...) {
                control_error = std::current_exception();
                throw std::runtime_error("the control function failed");
            }
        };
    }
    runtime::RunSummary r;
    std::vector<double> rows;
    {
        py::gil_scoped_release release;
        runtime::LagrangianSystem sys = runtime::kernel_live_system(&P);
        if (!timed.empty())
            sys = runtime::with_timed_inputs(std::move(sys), [&P, &timed](double t) {
                for (const TimedInput& in : timed) P.set(in.index, in.at(t));
            });
        r = runtime::run_one(sys, q0, v0, s, nullptr, &rows);
    }
    if (control_error) std::rethrow_exception(control_error);
    const std::size_t width = 2 * n + 2;
    const auto count = static_cast<py::ssize_t>(rows.size() / width);
    py::dict d;
    d["rows"] = numpy_of(std::move(rows), {count, static_cast<py::ssize_t>(width)});
    d["status"] = status_name(r.status);
    d["reason"] = r.reason;
    d["t"] = r.t;
    d["q"] = r.q;
    d["qdot"] = r.qdot;
    d["first_event"] = r.first_event;
    d["max_energy_error"] = r.max_energy_error;
    py::list events;
    for (const runtime::EventRecord& e : r.events)
        events.append(py::make_tuple(e.time, std::string(k.table().event_names[e.event]), e.q, e.qdot));
    d["events"] = events;
    d["control_log"] = control_log;
    return d;
}

/// The 3-D page (runtime/view/recorder.hpp) of a run's rows (t, q…, q'…, E as simulate gives
/// them): the model's shapes at each row, the inputs at their values of that time (`inputs` as
/// simulate's, `control_log` what its controller set), the events marked, the stop reason.
/// The rows are the run's own states: nothing is integrated again.
std::string html_of_rows(const Kernel& k, const py::dict& params, const py::array_t<double, py::array::c_style | py::array::forcecast>& rows,
                         const std::vector<std::tuple<std::string, std::vector<double>, std::vector<double>>>& inputs,
                         const std::vector<std::tuple<double, std::size_t, double>>& control_log, double fps,
                         const std::string& title, const std::vector<std::pair<double, std::string>>& events,
                         const std::string& stop_reason) {
    const std::size_t n = k.table().dof, width = 2 * n + 2;
    if (rows.ndim() != 2 || static_cast<std::size_t>(rows.shape(1)) != width || rows.shape(0) < 1)
        throw py::value_error("rows: expected shape (rows, " + std::to_string(width) + ") with at least one row");
    if (!(std::isfinite(fps) && fps > 0)) throw py::value_error("fps must be finite and > 0");
    runtime::check_three_js();
    std::vector<TimedInput> timed;
    for (const auto& [name, times, values] : inputs) timed.push_back(TimedInput{input_index(k, name), times, values});
    KernelParameters P = parameters_of(k, params);
    runtime::RecorderOptions options;
    options.fps = fps;
    options.title = title;
    runtime::Recorder recorder(options);
    {
        py::gil_scoped_release release;
        const runtime::LagrangianSystem sys = runtime::kernel_live_system(&P);
        runtime::World w = runtime::make_lagrangian_world(sys);
        recorder.add_model(sys);
        const double* r = rows.data();
        std::size_t next_control = 0;
        for (py::ssize_t i = 0; i < rows.shape(0); ++i, r += width) {
            const double t = r[0];
            for (const TimedInput& in : timed) P.set(in.index, in.at(t));
            for (; next_control < control_log.size() && std::get<0>(control_log[next_control]) <= t; ++next_control)
                P.set(std::get<1>(control_log[next_control]), std::get<2>(control_log[next_control]));
            w.time = t;
            std::copy_n(r + 1, n, w.field(runtime::kGQ).begin());
            std::copy_n(r + 1 + n, n, w.field(runtime::kGV).begin());
            recorder.capture(w);
        }
        recorder.capture_last(w); // as the simulator's --html: the end kept whether or not a frame was due
        for (const auto& [t, name] : events) recorder.mark_event(t, name);
        recorder.set_stop_reason(stop_reason);
    }
    return recorder.html();
}

/// The simulator's command line on this kernel (phynjo-run's main without the compile):
/// `args` are the options after the model; the exit status.
int run(const Kernel& k, const std::string& program, const std::vector<std::string>& args) {
    py::gil_scoped_release release;
    KernelParameters P(k.kernel);
    const phynjo_kernel& t = k.table();
    runtime::ModelCommandLine model{t.model_name, {}, [&P] { return runtime::kernel_system(P); }};
    for (std::size_t i = 0; i < t.n_parameters; ++i)
        model.parameters.emplace_back(t.parameter_names[i], [&P, i](double v) { P.set(i, v); });
    std::vector<std::string> words{program};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    const int status = runtime::model_main(static_cast<int>(words.size()), argv.data(), model);
    std::fflush(nullptr); // what it printed reaches the files before Python reads them
    std::cout.flush();
    std::cerr.flush();
    return status;
}

/// Raises phynjo's Python exception `name` (python/phynjo/_errors.py) with `message`.
void raise_as(const char* name, const char* message) {
    const py::object cls = py::module_::import("phynjo._errors").attr(name);
    PyErr_SetObject(cls.ptr(), py::str(message).ptr());
}

} // namespace

PYBIND11_MODULE(_phynjo, m) {
    m.doc() = "phynjo's compiled half: kernels, their functions over NumPy arrays, runs (use the phynjo package)";
    m.attr("__version__") = PHYNJO_VERSION;

    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const jit::ModelError& e) {
            raise_as("ModelError", e.what());
        } catch (const jit::BuildError& e) {
            raise_as("BuildError", e.what());
        } catch (const runtime::KernelError& e) {
            raise_as("KernelError", e.what());
        } catch (const runtime::SingularMassMatrix& e) {
            raise_as("SingularMassMatrix", e.what());
        } catch (const runtime::SingularConstraints& e) {
            raise_as("SingularConstraints", e.what());
        } catch (const runtime::NonFiniteResult& e) {
            raise_as("NonFiniteResult", e.what());
        } catch (const runtime::Error& e) {
            raise_as("PhynjoError", e.what());
        } catch (const runtime::ViewerError& e) {
            raise_as("PhynjoError", e.what());
        }
    });

    py::enum_<Fn>(m, "Fn")
        .value("accelerations", Fn::accelerations)
        .value("mass_matrix", Fn::mass_matrix)
        .value("forcing", Fn::forcing)
        .value("energy", Fn::energy)
        .value("momenta", Fn::momenta)
        .value("generalized_forces", Fn::generalized_forces)
        .value("rhs_jacobian", Fn::rhs_jacobian)
        .value("input_jacobian", Fn::input_jacobian)
        .value("constraint_residuals", Fn::constraint_residuals);

    py::class_<Kernel>(m, "Kernel")
        .def_property_readonly("name", [](const Kernel& k) { return std::string(k.table().model_name); })
        .def_property_readonly("path", [](const Kernel& k) { return k.compiled.kernel_path; })
        .def_property_readonly("key", [](const Kernel& k) { return k.compiled.key; })
        .def_property_readonly("cache_hit", [](const Kernel& k) { return k.compiled.cache_hit; })
        .def_property_readonly("compile_seconds", [](const Kernel& k) { return k.compiled.compile_seconds; })
        .def_property_readonly("quick", [](const Kernel& k) { return k.compiled.quick; })
        .def("optimized",
             [](const Kernel& k, double wait) -> std::optional<Kernel> {
                 // the optimized kernel of a quick one, once built (waiting up to `wait` s)
                 std::optional<std::string> path;
                 {
                     py::gil_scoped_release release;
                     path = jit::optimized_kernel(k.compiled, wait);
                 }
                 if (!path) return std::nullopt;
                 jit::CompiledModel c = k.compiled;
                 c.kernel_path = *path;
                 c.quick = false;
                 return load(c);
             })
        .def_property_readonly("dof", [](const Kernel& k) { return k.table().dof; })
        .def_property_readonly("coordinates", [](const Kernel& k) {
            const auto& t = k.table();
            return std::vector<std::string>(t.coordinate_names, t.coordinate_names + t.dof);
        })
        .def_property_readonly("parameters", [](const Kernel& k) {
            // (name, default, unit, is input, is derived)
            const auto& t = k.table();
            py::list out;
            for (std::size_t i = 0; i < t.n_parameters; ++i)
                out.append(py::make_tuple(std::string(t.parameter_names[i]), t.parameter_defaults[i],
                                          std::string(t.parameter_units[i]), t.parameter_is_input[i] != 0,
                                          t.parameter_is_derived[i] != 0));
            return out;
        })
        .def_property_readonly("constraints", [](const Kernel& k) {
            const auto& t = k.table();
            py::list out;
            for (std::size_t i = 0; i < t.n_constraints; ++i)
                out.append(py::make_tuple(std::string(t.constraint_names[i]), t.constraint_holonomic[i] != 0));
            return out;
        })
        .def_property_readonly("events", [](const Kernel& k) {
            const auto& t = k.table();
            py::list out;
            for (std::size_t i = 0; i < t.n_events; ++i)
                out.append(py::make_tuple(std::string(t.event_names[i]), t.event_directions[i], t.event_stops[i] != 0));
            return out;
        })
        .def_property_readonly("shapes", [](const Kernel& k) {
            const auto& t = k.table();
            py::list out;
            for (std::size_t i = 0; i < t.n_shapes; ++i)
                out.append(py::make_tuple(std::string(t.shape_names[i]),
                                          std::string(t.shape_kinds[i] == 1   ? "sphere"
                                                          : t.shape_kinds[i] == 2 ? "capsule"
                                                          : t.shape_kinds[i] == 3 ? "box"
                                                                                  : "segment")));
            return out;
        })
        .def("parameter", [](const Kernel& k, const py::dict& params, const std::string& name) {
            return parameters_of(k, params).get(name);
        })
        .def("evaluate", &evaluate, py::arg("fn"), py::arg("q"), py::arg("qd"), py::arg("t"), py::arg("params"),
             py::arg("out"))
        .def("initial_state", [](const Kernel& k, const py::dict& params) {
            const KernelParameters P = parameters_of(k, params);
            const std::size_t n = k.table().dof;
            std::vector<double> q(n), v(n);
            k.kernel->check(k.table().initial_state(P.data(), q.data(), v.data()));
            return py::make_tuple(numpy_of(std::move(q), {static_cast<py::ssize_t>(n)}),
                                  numpy_of(std::move(v), {static_cast<py::ssize_t>(n)}));
        })
        .def("simulate", &simulate)
        .def("html", &html_of_rows)
        .def("run", &run);

    m.def("compile_file", [](const std::string& path, const std::string& cache_dir, bool verbose, bool quick) {
        jit::CompiledModel c;
        {
            py::gil_scoped_release release;
            c = jit::compile_model_file(path, options_of(cache_dir, verbose, quick));
        }
        return load(c);
    });
    m.def("compile_string",
          [](const std::string& text, const std::string& name, const std::string& cache_dir, bool verbose, bool quick) {
              jit::CompiledModel c;
              {
                  py::gil_scoped_release release;
                  c = jit::compile_model(text, name, options_of(cache_dir, verbose, quick));
              }
              return load(c);
          });
    m.def("document", [](const std::string& text, const std::string& name, const std::string& kind) {
        if (kind != "latex" && kind != "equations") throw py::value_error("document: latex or equations");
        return jit::model_document(text, name, kind == "latex" ? jit::ModelDocument::latex : jit::ModelDocument::equations);
    });
    m.def("integrators", [] {
        // (name, order, symplectic, adaptive, runs in sweeps, help)
        py::list out;
        for (const runtime::IntegratorEntry& e : runtime::integrator_registry())
            out.append(py::make_tuple(std::string(e.name), std::string(e.order), e.symplectic, e.adaptive, e.sweeps,
                                      std::string(e.help)));
        return out;
    });
}
