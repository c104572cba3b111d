#pragma once
/// \file
/// Sweeps over MPI ranks. The simulators phynjo_add_model(… MAIN) builds call model_main
/// below when phynjo is built with MPI (PHYNJO_MPI): started by `mpirun -np K` (or `srun`),
/// a sweep's batches of runs are dealt round robin to the K ranks, each running its batches
/// on its own --threads; rank 0 writes the summary in run order, byte-identical to one
/// process's. Started without a launcher, the simulator never initializes MPI.
#include "phynjo/runtime/simulate/ensemble.hpp"
#include "phynjo/runtime/simulate/model_main.hpp"

#include <mpi.h>

#include <cstdint>
#include <list>
#include <optional>
#include <span>
#include <string>
#include <utility>

namespace phynjo::mpi {

/// Whether an MPI launcher started this process (Open MPI's mpirun, a PMI or PMIx launcher
/// such as MPICH's mpiexec or SLURM's srun): its environment says so.
[[nodiscard]] bool launched_by_mpi();

/// The ranks of a communicator as the sweep driver's processes. MPI must be initialized
/// (MPI_THREAD_FUNNELED is enough: only the thread that calls run_sweep uses MPI).
class MpiSweepProcesses final : public runtime::SweepProcesses {
public:
    explicit MpiSweepProcesses(MPI_Comm comm = MPI_COMM_WORLD);
    ~MpiSweepProcesses() override;
    MpiSweepProcesses(const MpiSweepProcesses&) = delete;
    MpiSweepProcesses& operator=(const MpiSweepProcesses&) = delete;

    [[nodiscard]] unsigned rank() const override { return rank_; }
    [[nodiscard]] unsigned size() const override { return size_; }
    void broadcast(std::span<std::uint64_t> values) override;
    void send(std::uint64_t batch, std::string rows) override;
    std::optional<std::pair<std::uint64_t, std::string>> receive(bool wait) override;
    void flush() override;
    [[noreturn]] void abort(int status) override;

private:
    struct Outgoing {
        std::string bytes; ///< the batch's index (8 bytes), then its rows
        MPI_Request request = MPI_REQUEST_NULL;
    };
    MPI_Comm comm_;
    unsigned rank_ = 0, size_ = 1;
    std::list<Outgoing> outgoing_; ///< sends not known to be delivered
    std::string incoming_;
};

/// The simulator (runtime::model_main) on MPI's ranks when a launcher started it: initializes
/// MPI, shares a sweep among the ranks, finalizes. Every rank returns the same exit status.
int model_main(int argc, char** argv, const runtime::ModelCommandLine& model);

} // namespace phynjo::mpi
