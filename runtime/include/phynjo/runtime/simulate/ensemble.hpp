#pragma once
/// \file
/// Ensembles of runs of a generated model: parameter and initial-condition sweeps (a grid, or
/// Monte Carlo samples, or both), every run from its own values to the same end, spread over
/// threads, summarized one CSV row per run in a fixed order — byte-identical whatever the
/// thread count, and resumable. The simulators' `--grid`, `--samples`, `--uniform`, `--summary`
/// (model_main.hpp) are this module.
#include "phynjo/runtime/system/constraint_projection.hpp"
#include "phynjo/runtime/simulate/events.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"
#include "phynjo/runtime/simulate/model_main.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace phynjo::runtime {

/// One swept quantity: a grid axis (n ≥ 1 values LO + i (HI − LO)/(n − 1), LO alone for n = 1)
/// or a Monte Carlo axis (n = 0: uniform on [LO, HI)).
struct SweepAxis {
    std::string name; ///< a parameter or input, a coordinate (its initial value) or NAME' (its initial velocity)
    double lo = 0, hi = 0;
    std::size_t n = 0;
};

/// "NAME=LO:HI:N" (a grid axis). Throws std::invalid_argument naming what is malformed.
SweepAxis parse_grid_axis(std::string_view text);
/// "NAME=LO:HI" (a Monte Carlo axis, LO ≤ HI). Throws std::invalid_argument.
SweepAxis parse_uniform_axis(std::string_view text);

/// The runs of a sweep, in their fixed order: the grid points row-major (the first axis
/// slowest), and `samples` Monte Carlo draws at each.
struct SweepPlan {
    std::vector<SweepAxis> grid, uniform;
    std::size_t samples = 1;
    std::uint64_t seed = 0;

    /// Π n over the grid axes × samples.
    [[nodiscard]] std::size_t size() const;
    /// The axes' names: the grid's, then the uniform ones'.
    [[nodiscard]] std::vector<std::string> names() const;
    /// Run k's values in the order of names(). A Monte Carlo value is a function of (seed, k,
    /// axis) alone (SplitMix64 of a counter), so it does not depend on which thread runs k.
    void values(std::size_t run, std::span<double> out) const;
};

/// What one run ended with.
struct RunSummary {
    enum class Status { finished, stopped, failed };
    Status status = Status::finished;
    std::string reason;            ///< why it stopped or failed (empty when finished)
    double t = 0;                  ///< where it ended, s
    std::vector<double> q, qdot;   ///< the state there
    std::vector<double> first_event; ///< per event: when it first fired, NaN if never
    double max_energy_error = 0;   ///< max over the steps of |E − E(0)| / max(1, |E(0)|)
};

/// How every run of a sweep is stepped.
struct RunSettings {
    double t_end = 10, dt = 1e-3;
    std::string integrator = "rk4"; ///< an integrator that runs in sweeps (integrator_registry.hpp)
    EventOptions events;
    ProjectionOptions projection;
    long every = 1; ///< a trajectory's rows: every `every`-th step (the first and last always)
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
/// without its header): t = 0, every `settings.every`-th step, and the last step.
/// std::invalid_argument when `settings.integrator` does not run in sweeps.
RunSummary run_one(const LagrangianSystem& system, std::span<const std::pair<std::size_t, double>> q0,
                   std::span<const std::pair<std::size_t, double>> v0, const RunSettings& settings,
                   std::string* trajectory = nullptr);

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

/// The processes a sweep is shared among: this process alone unless a SweepCommand names others
/// (MPI's ranks: phynjo/mpi/mpi_sweep.hpp). The runs go in batches of equal size, batch i to
/// rank i mod size() (round robin: the ranks' shares of a map whose runs differ in length stay
/// even); rank 0 writes every row, in run order, the others send it theirs.
class SweepProcesses {
public:
    virtual ~SweepProcesses() = default;
    [[nodiscard]] virtual unsigned rank() const = 0;
    [[nodiscard]] virtual unsigned size() const = 0;
    /// Collective: every rank returns rank 0's `values`.
    virtual void broadcast(std::span<std::uint64_t> values) = 0;
    /// A rank other than 0: batch `batch`'s rows to rank 0. May return before they are delivered.
    virtual void send(std::uint64_t batch, std::string rows) = 0;
    /// Rank 0: a batch another rank sent (its index and rows); without `wait`, nullopt when
    /// none has arrived.
    virtual std::optional<std::pair<std::uint64_t, std::string>> receive(bool wait) = 0;
    /// Every send delivered; called by every rank before it returns.
    virtual void flush() = 0;
    /// Rank 0 cannot go on (the summary cannot be written): ends every rank with `status`.
    [[noreturn]] virtual void abort(int status) = 0;
};

/// A sweep as the simulators' command line gives it (model_main collects the options).
struct SweepCommand {
    SweepPlan plan;
    RunSettings settings;
    std::string summary;   ///< the summary CSV's path
    unsigned threads = 1;
    /// The options that decide the results (not --threads), kept as the summary's first line:
    /// a resumed sweep must have the same.
    std::string signature;
    std::vector<std::pair<std::string, double>> inits; ///< --init values for every run
    /// Where each run's trajectory goes (`DIR/run_K.csv`, K zero-padded to the width of the
    /// last run's number); empty: none.
    std::string trajectories;
    /// The ranks this sweep is shared among; null: this process alone.
    SweepProcesses* processes = nullptr;
};

/// Runs a sweep of `model` and writes its summary: a first line `# phynjo sweep: SIGNATURE`,
/// the header `run,AXES…,status,t,end_Q…,end_Q'…,first_EVENT…,max_energy_error,reason`, then one row
/// per run in run order (%.17g; an event that never fired is an empty field). When the file
/// exists with the same first line, the runs it already holds are kept and the sweep goes on
/// after them (a partly written last row is dropped); another first line is refused. Runs go
/// to `threads` threads in batches; rows are written and flushed batch by batch. Progress goes
/// to stderr when it is a terminal. With `processes`, every rank calls this with the same
/// command; only rank 0 opens the summary and speaks, and every rank returns its status. Exit status: 0 done (failed runs are rows, not errors),
/// 1 the summary cannot be written, 2 a usage error (an unknown name, a summary of another
/// command).
int run_sweep(const SweepCommand& command, const ModelCommandLine& model, const char* program);

} // namespace phynjo::runtime
