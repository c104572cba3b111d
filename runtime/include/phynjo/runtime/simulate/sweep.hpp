#pragma once
/// \file
/// A sweep as the simulators run it: the plan's runs spread over threads (and MPI ranks),
/// summarized one CSV row per run in run order, resumable (run_sweep).
#include "phynjo/runtime/simulate/model_main.hpp"
#include "phynjo/runtime/simulate/runs.hpp"
#include "phynjo/runtime/simulate/sweep_plan.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace phynjo::runtime {

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
