#pragma once
/// \file
/// The runs of an ensemble: one run to its end with a summary (run_one), and many on one
/// thread (run_many), in SIMD lanes where the model has the kernels for it.
#include "phynjo/runtime/simulate/events.hpp"
#include "phynjo/runtime/system/constraint_projection.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace phynjo::runtime {

/// What one run ended with.
struct RunSummary {
    enum class Status { finished, stopped, failed };
    Status status = Status::finished;
    std::string reason;            ///< why it stopped or failed (empty when finished)
    double t = 0;                  ///< where it ended, s
    std::vector<double> q, qdot;   ///< the state there
    std::vector<double> first_event; ///< per event: when it first fired, NaN if never
    double max_energy_error = 0;   ///< max over the steps of |E − E(0)| / max(1, |E(0)|)
    std::vector<EventRecord> events; ///< every event that fired, in order (with RunSettings::event_log)
};

/// How every run of a sweep is stepped.
struct RunSettings {
    double t_end = 10, dt = 1e-3;
    std::string integrator = "rk4"; ///< an integrator that runs in sweeps (integrator_registry.hpp)
    EventOptions events;
    ProjectionOptions projection;
    long every = 1; ///< a trajectory's rows: every `every`-th step (the first and last always)
    /// The adaptive integrators' tolerances (dopri: its defaults when unset).
    std::optional<double> rtol, atol;
    /// Keep every event that fired (time, which, the state after it) in RunSummary::events.
    bool event_log = false;
    /// A controller, sampled: called with t and the state at the start of every
    /// `control_every`-th run step (t = 0 first), it sets inputs of the parameters the system
    /// reads live (kernel_live_system), which hold until its next call (zero-order hold). What
    /// it throws fails the run like any error. Runs with it take the integrators' general path
    /// (no fused kernels).
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot)> control;
    long control_every = 1;
    /// run_many (a sweep's runs) steps lane_width runs at a time in the lanes of SIMD registers
    /// where the model has lane kernels (the default; simulators: --no-lanes turns it off). A
    /// run's sines are then libmvec's, so its summary agrees with run_one's (one run's
    /// --output) to rounding, not bit for bit; it is still the same bits whatever runs share
    /// its registers, the thread count and the ranks. Off: run_one's bits, more slowly.
    bool lanes = true;
};

/// One run from the system's initial state with the initial values `q0` and `v0` set
/// (coordinate index, value) to t_end, with the model's events. Never throws for a failing
/// run: a thrown error, a non-finite state or a constraint violated at the start are a
/// `failed` summary with the reason; a `stop` event is a `stopped` one. With `trajectory`, the
/// run's rows are appended to it as CSV lines `t,q…,q'…,E` (%.17g; the simulator's --output
/// without its header): t = 0, every `settings.every`-th step, and the last step. With
/// `values`, the same rows as numbers (t, q…, q'…, E: 2·dof + 2 a row), the bits the text prints.
/// std::invalid_argument when `settings.integrator` does not run in sweeps.
RunSummary run_one(const LagrangianSystem& system, std::span<const std::pair<std::size_t, double>> q0,
                   std::span<const std::pair<std::size_t, double>> v0, const RunSettings& settings,
                   std::string* trajectory = nullptr, std::vector<double>* values = nullptr);

/// One run of run_many: its initial values (as run_one's q0 and v0), optionally the string its
/// trajectory rows are appended to, and its own system (the same model with other parameters;
/// null: run_many's).
struct RunStart {
    std::span<const std::pair<std::size_t, double>> q0, v0;
    std::string* trajectory = nullptr;
    const LagrangianSystem* system = nullptr;
};

/// The runs `starts` on this thread (each of `system` or of its own, RunStart::system), their
/// summaries in `out` (same size), as run_one gives them — but, with `settings.lanes` and when
/// every run's system has the generated lane kernels of one model (`rk4_step_values_lanes_each`:
/// rk4, no constraints, one or two coordinates), lane_width runs at a time in the lanes of SIMD
/// registers (runtime/system/detail/lanes.hpp), each with its own parameters: then a run's sines and
/// cosines are libmvec's, so its summary agrees with run_one's to rounding, not bit for bit.
/// Either way a run's summary depends on that run alone: not on the other runs, their order,
/// or which of them shared its registers. `finished(k)`, when given, is called as soon as run
/// k is over (runs end out of order): its trajectory is complete.
void run_many(const LagrangianSystem& system, std::span<const RunStart> starts, const RunSettings& settings,
              std::span<RunSummary> out, const std::function<void(std::size_t)>& finished = {});

} // namespace phynjo::runtime
