// Sweeps over MPI ranks (mpi_sweep.hpp).
#include "phynjo/mpi/mpi_sweep.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <cstring>
#include <stdexcept>

namespace phynjo::mpi {

namespace {
constexpr int kRowsTag = 17; // a batch's summary rows, worker -> rank 0
} // namespace

bool launched_by_mpi() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}

MpiSweepProcesses::MpiSweepProcesses(MPI_Comm comm) : comm_(comm) {
    int r = 0, s = 1;
    MPI_Comm_rank(comm_, &r);
    MPI_Comm_size(comm_, &s);
    rank_ = static_cast<unsigned>(r);
    size_ = static_cast<unsigned>(s);
}

MpiSweepProcesses::~MpiSweepProcesses() { flush(); }

void MpiSweepProcesses::broadcast(std::span<std::uint64_t> values) {
    MPI_Bcast(values.data(), static_cast<int>(values.size()), MPI_UINT64_T, 0, comm_);
}

void MpiSweepProcesses::send(std::uint64_t batch, std::string rows) {
    // forget the sends already delivered, so the list stays as short as the pipeline
    for (auto it = outgoing_.begin(); it != outgoing_.end();) {
        int done = 0;
        MPI_Test(&it->request, &done, MPI_STATUS_IGNORE);
        it = done ? outgoing_.erase(it) : std::next(it);
    }
    if (rows.size() > static_cast<std::size_t>(INT32_MAX) - 8) throw std::length_error("a sweep batch's rows exceed MPI's count");
    Outgoing& o = outgoing_.emplace_back();
    o.bytes.resize(8 + rows.size());
    std::memcpy(o.bytes.data(), &batch, 8);
    std::memcpy(o.bytes.data() + 8, rows.data(), rows.size());
    MPI_Isend(o.bytes.data(), static_cast<int>(o.bytes.size()), MPI_BYTE, 0, kRowsTag, comm_, &o.request);
}

std::optional<std::pair<std::uint64_t, std::string>> MpiSweepProcesses::receive(bool wait) {
    MPI_Status status;
    if (wait) MPI_Probe(MPI_ANY_SOURCE, kRowsTag, comm_, &status);
    else {
        int arrived = 0;
        MPI_Iprobe(MPI_ANY_SOURCE, kRowsTag, comm_, &arrived, &status);
        if (!arrived) return std::nullopt;
    }
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    incoming_.resize(static_cast<std::size_t>(count));
    MPI_Recv(incoming_.data(), count, MPI_BYTE, status.MPI_SOURCE, kRowsTag, comm_, MPI_STATUS_IGNORE);
    std::uint64_t batch = 0;
    std::memcpy(&batch, incoming_.data(), 8);
    return std::pair{batch, incoming_.substr(8)};
}

void MpiSweepProcesses::flush() {
    for (Outgoing& o : outgoing_) MPI_Wait(&o.request, MPI_STATUS_IGNORE);
    outgoing_.clear();
}

void MpiSweepProcesses::abort(int status) {
    MPI_Abort(comm_, status);
    std::exit(status); // MPI_Abort does not return; this keeps [[noreturn]] honest
}

int model_main(int argc, char** argv, const runtime::ModelCommandLine& model) {
    if (!launched_by_mpi()) return runtime::model_main(argc, argv, model);
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    int status = 0;
    try {
        MpiSweepProcesses ranks(MPI_COMM_WORLD);
        status = runtime::model_main(argc, argv, model, &ranks);
    } catch (const std::exception& e) { // a rank that cannot go on must not leave the others waiting
        std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
    return status;
}

} // namespace phynjo::mpi
