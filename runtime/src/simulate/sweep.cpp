// The sweep driver of the simulators: runs on threads and ranks, the summary, resume (sweep.hpp).
#include "phynjo/runtime/simulate/sweep.hpp"

#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/executor.hpp"
#include "phynjo/runtime/simulate/integrator_registry.hpp"

#include <algorithm>
#include <memory>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unistd.h>

#include "csv_text.hpp"
#include "strict_numbers.hpp"

namespace phynjo::runtime {

using detail::append_number;
using detail::csv_field;

namespace {

/// Where each swept name goes: a parameter (its setter), an initial value, an initial velocity.
struct Target {
    enum Kind { parameter, position, velocity } kind;
    std::size_t index; // into model.parameters, or a coordinate
};

/// A sweep under way (run_sweep): the command, what each swept name sets, the summary, and
/// the scratch of one batch of runs.
struct Sweep {
    const SweepCommand& cmd;
    const ModelCommandLine& model;
    const char* program;
    SweepProcesses* const processes;
    const unsigned rank, ranks;
    const LagrangianSystem base;
    const std::vector<std::string>& coords;
    const std::vector<std::string> names;
    const std::size_t total;
    const std::string first_line;
    const unsigned threads;
    std::vector<Target> targets;
    bool parameters_swept = false;
    std::vector<std::pair<std::size_t, double>> fixed_q, fixed_v; // the --init values
    std::string header, trajectory_header;
    std::FILE* out = nullptr;
    std::uint64_t shared[3]; // status, done, batch
    std::size_t done = 0, batch = 0, batches = 0;
    int width = 1; // a trajectory file's run number, zero-padded to the last one's width
    // one batch's scratch
    Executor executor;
    std::vector<LagrangianSystem> systems;
    std::vector<std::vector<std::pair<std::size_t, double>>> q0s, v0s;
    std::vector<RunSummary> results;
    std::vector<double> values;
    std::vector<std::vector<double>> batch_values;
    std::vector<std::string> trajectory_failed; // a file a thread could not write
    // rank 0's rows waiting for their turn
    std::map<std::size_t, std::string> pending;
    std::size_t next = 0; // the first batch not written
    const bool progress = ::isatty(STDERR_FILENO) != 0;
    const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    std::chrono::steady_clock::time_point last_report = start;

    Sweep(const SweepCommand& c, const ModelCommandLine& m, const char* p)
        : cmd(c), model(m), program(p), processes(c.processes), rank(processes ? processes->rank() : 0),
          ranks(processes ? processes->size() : 1), base(m.system()), coords(base.coordinate_names),
          names(c.plan.names()), total(c.plan.size()), first_line("# phynjo sweep: " + c.signature),
          threads(std::max(1u, c.threads)), shared{0, 0, std::max<std::uint64_t>(64, 16 * std::uint64_t{threads})},
          executor(threads), trajectory_failed(threads) {}

    /// A usage error: every rank checks the same command and reaches the same verdict; rank 0
    /// says it.
    int usage(const std::string& m) const {
        if (rank == 0) std::fprintf(stderr, "%s: %s\n", program, m.c_str());
        return 2;
    }
    /// What a swept name or --init sets: a parameter, an initial value or velocity.
    std::optional<Target> resolve(const std::string& name) const {
        for (std::size_t k = 0; k < model.parameters.size(); ++k)
            if (model.parameters[k].first == name) return Target{Target::parameter, k};
        const bool vel = !name.empty() && name.back() == '\'';
        const std::string c = vel ? name.substr(0, name.size() - 1) : name;
        const auto it = std::find(coords.begin(), coords.end(), c);
        if (it == coords.end()) return std::nullopt;
        return Target{vel ? Target::velocity : Target::position, static_cast<std::size_t>(it - coords.begin())};
    }
    /// Each swept name and each fixed --init resolved once, the integrator checked; the
    /// summary's header. An exit status on a usage error.
    std::optional<int> prepare();
    /// Rank 0: the summary opened (resumed: its complete rows kept) and the trajectories'
    /// folder made; an exit status.
    int open_summary();
    /// Batch b (runs done + b·batch …) on this rank's threads: its summary rows, or nothing
    /// when a trajectory could not be written.
    std::optional<std::string> run_batch(std::size_t b);
    /// Rank 0: the pending batches that are next in run order, written; false on a failed write.
    bool write_ready();
    /// Rank 0: its own batches, and the others' as they arrive, written in run order.
    bool lead();
};

std::optional<int> Sweep::prepare() {
    for (std::size_t k = 0; k < names.size(); ++k) {
        const auto t = resolve(names[k]);
        if (!t) return usage("sweep: '" + names[k] + "' is not a parameter, an input, a coordinate or a coordinate's velocity (try --help)");
        for (std::size_t j = 0; j < k; ++j)
            if (names[j] == names[k]) return usage("sweep: '" + names[k] + "' is swept twice");
        parameters_swept = parameters_swept || t->kind == Target::parameter;
        targets.push_back(*t);
    }
    for (const auto& [name, v] : cmd.inits) {
        const auto t = resolve(name);
        if (!t || t->kind == Target::parameter) return usage("--init: '" + name + "' is not a coordinate (try --help)");
        (t->kind == Target::position ? fixed_q : fixed_v).emplace_back(t->index, v);
    }
    if (const IntegratorEntry* e = find_integrator(cmd.settings.integrator); !e || !e->sweeps)
        return usage("sweeps run with --integrator " + integrator_names([](const IntegratorEntry& x) { return x.sweeps; }) +
                     ", not '" + cmd.settings.integrator + "'");

    header = "run";
    for (const std::string& n : names) header += "," + n;
    header += ",status,t";
    for (const auto& c : coords) header += ",end_" + c;
    for (const auto& c : coords) header += ",end_" + c + "'";
    for (const auto& e : base.event_names) header += ",first_" + e;
    header += ",max_energy_error,reason";
    trajectory_header = "t";
    for (const auto& c : coords) trajectory_header += "," + c;
    for (const auto& c : coords) trajectory_header += "," + c + "'";
    trajectory_header += ",E\n";
    width = static_cast<int>(std::to_string(total > 0 ? total - 1 : 0).size());
    return std::nullopt;
}

int Sweep::open_summary() {
    // Resume: keep the complete rows of a summary this same command began.
    std::size_t kept = 0;
    if (std::FILE* old = std::fopen(cmd.summary.c_str(), "r")) {
        std::string text;
        char buf[65536];
        for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, old)) > 0;) text.append(buf, got);
        std::fclose(old);
        if (!text.empty()) {
            const auto nl = text.find('\n');
            if (nl == std::string::npos || text.substr(0, nl) != first_line)
                return usage("--summary " + cmd.summary + " was written by another command (its first line is not '" +
                             first_line + "'); remove it or choose another file");
            const auto nl2 = text.find('\n', nl + 1);
            std::size_t keep = nl2 == std::string::npos ? 0 : nl2 + 1; // after the header
            if (keep > 0) {
                if (text.substr(nl + 1, nl2 - nl - 1) != header)
                    return usage("--summary " + cmd.summary + ": its header does not match this model's");
                for (std::size_t p = keep; (p = text.find('\n', p)) != std::string::npos; ++p) {
                    ++kept;
                    keep = p + 1;
                }
            }
            if (kept > total) return usage("--summary " + cmd.summary + " holds more rows than this sweep has runs");
            if (keep < text.size() || keep == 0) { // drop a partial row (or a partial header)
                if (::truncate(cmd.summary.c_str(), static_cast<off_t>(keep)) != 0) {
                    std::fprintf(stderr, "%s: cannot truncate %s\n", program, cmd.summary.c_str());
                    return 1;
                }
            }
            if (keep == 0) kept = 0;
        }
    }
    if (!cmd.trajectories.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(cmd.trajectories, ec);
        if (ec || !std::filesystem::is_directory(cmd.trajectories)) {
            std::fprintf(stderr, "%s: --trajectories: cannot make the folder %s\n", program, cmd.trajectories.c_str());
            return 1;
        }
    }
    out = std::fopen(cmd.summary.c_str(), "a");
    if (!out) {
        std::fprintf(stderr, "%s: cannot write %s\n", program, cmd.summary.c_str());
        return 1;
    }
    std::fseek(out, 0, SEEK_END);
    if (std::ftell(out) == 0) std::fprintf(out, "%s\n%s\n", first_line.c_str(), header.c_str());
    std::fflush(out);
    if (kept > 0) std::fprintf(stderr, "%s: resuming %s after its %zu of %zu runs\n", program, cmd.summary.c_str(), kept, total);
    shared[1] = kept;
    return 0;
}

std::optional<std::string> Sweep::run_batch(std::size_t b) {
    const std::size_t first = done + b * batch, count = std::min(batch, total - first);
    systems.clear();
    for (std::size_t j = 0; j < count; ++j) { // on this thread: the setters share the model's parameters
        cmd.plan.values(first + j, values);
        batch_values[j] = values;
        q0s[j] = fixed_q;
        v0s[j] = fixed_v;
        for (std::size_t k = 0; k < names.size(); ++k) {
            const Target& t = targets[k];
            if (t.kind == Target::parameter) model.parameters[t.index].second(values[k]);
            else (t.kind == Target::position ? q0s[j] : v0s[j]).emplace_back(t.index, values[k]);
        }
        if (parameters_swept) systems.push_back(model.system());
    }
    auto task = [&](unsigned i) {
        // this thread's runs: i, i + threads, … (run_many's results do not depend on the grouping)
        std::vector<std::size_t> mine;
        for (std::size_t j = i; j < count; j += threads) mine.push_back(j);
        std::vector<std::string> rows(cmd.trajectories.empty() ? 0 : mine.size());
        auto write = [&](std::size_t k) { // run mine[k] is over: its trajectory file
            if (rows.empty()) return;
            char name[48];
            std::snprintf(name, sizeof name, "run_%0*zu.csv", width, first + mine[k]);
            const std::string path = (std::filesystem::path(cmd.trajectories) / name).string();
            std::FILE* f = std::fopen(path.c_str(), "w");
            const bool ok = f && std::fwrite(rows[k].data(), 1, rows[k].size(), f) == rows[k].size();
            if ((f && std::fclose(f) != 0) || !ok) trajectory_failed[i] = path;
            std::string().swap(rows[k]);
        };
        std::vector<RunSummary> mine_results(mine.size());
        std::vector<RunStart> starts; // a system per run when parameters are swept
        for (std::size_t k = 0; k < mine.size(); ++k)
            starts.push_back({q0s[mine[k]], v0s[mine[k]], rows.empty() ? nullptr : &(rows[k] = trajectory_header),
                              parameters_swept ? &systems[mine[k]] : nullptr});
        run_many(base, starts, cmd.settings, mine_results, write);
        for (std::size_t k = 0; k < mine.size(); ++k) results[mine[k]] = std::move(mine_results[k]);
    };
    executor.fork_join(threads, task);
    for (const std::string& path : trajectory_failed)
        if (!path.empty()) { // this rank's own failure: it speaks, and the sweep ends
            std::fprintf(stderr, "%s: --trajectories: cannot write %s\n", program, path.c_str());
            if (ranks > 1) processes->abort(1);
            return std::optional<std::string>();
        }
    std::string rows;
    for (std::size_t j = 0; j < count; ++j) {
        const RunSummary& r = results[j];
        rows += std::to_string(first + j);
        for (double v : batch_values[j]) rows += ',', append_number(rows, v);
        rows += r.status == RunSummary::Status::finished ? ",finished," : r.status == RunSummary::Status::stopped ? ",stopped," : ",failed,";
        append_number(rows, r.t);
        for (double v : r.q) rows += ',', append_number(rows, v);
        for (double v : r.qdot) rows += ',', append_number(rows, v);
        for (double v : r.first_event) {
            rows += ',';
            if (!std::isnan(v)) append_number(rows, v);
        }
        rows += ',';
        append_number(rows, r.max_energy_error);
        rows += ',' + csv_field(r.reason) + '\n';
    }
    return std::optional<std::string>(std::move(rows));
}

bool Sweep::write_ready() {
    for (auto it = pending.begin(); it != pending.end() && it->first == next; it = pending.erase(it), ++next) {
        const std::string& rows = it->second;
        if (std::fwrite(rows.data(), 1, rows.size(), out) != rows.size() || std::fflush(out) != 0) {
            std::fprintf(stderr, "%s: cannot write %s\n", program, cmd.summary.c_str());
            if (ranks > 1) processes->abort(1);
            return false;
        }
        const std::size_t written = std::min(total, done + (next + 1) * batch);
        const auto now = std::chrono::steady_clock::now();
        if (progress && (now - last_report > std::chrono::milliseconds(500) || written == total)) {
            last_report = now;
            const double sec = std::chrono::duration<double>(now - start).count();
            const double rate = static_cast<double>(written - done) / std::max(sec, 1e-9);
            std::fprintf(stderr, "\r%s: %zu of %zu runs, %.1f runs/s, about %.0f s left   ", program, written, total, rate,
                         static_cast<double>(total - written) / std::max(rate, 1e-9));
            if (written == total) std::fprintf(stderr, "\n");
        }
    }
    return true;
    return true;
}

bool Sweep::lead() {
    bool ok = true;
    for (std::size_t b = 0; ok && b < batches; b += ranks) {
        auto rows = run_batch(b);
        if (!rows) {
            ok = false;
            break;
        }
        pending.emplace(b, std::move(*rows));
        if (ranks > 1)
            while (auto got = processes->receive(false)) pending.emplace(got->first, std::move(got->second));
        ok = write_ready();
    }
    while (ok && next < batches) {
        auto got = processes->receive(true);
        pending.emplace(got->first, std::move(got->second));
        ok = write_ready();
    }
    return ok;
}

} // namespace

int run_sweep(const SweepCommand& cmd, const ModelCommandLine& model, const char* program) {
    Sweep sweep(cmd, model, program);
    if (const auto failed = sweep.prepare()) return *failed;
    // Rank 0 opens the summary (resuming it) and the trajectories' folder, then tells every
    // rank the verdict, where the sweep goes on, and the batch size.
    if (sweep.rank == 0) sweep.shared[0] = static_cast<std::uint64_t>(sweep.open_summary());
    if (sweep.processes) sweep.processes->broadcast(sweep.shared);
    if (sweep.shared[0] != 0) return static_cast<int>(sweep.shared[0]);
    sweep.done = sweep.shared[1];
    sweep.batch = sweep.shared[2];
    sweep.batches = (sweep.total - sweep.done + sweep.batch - 1) / sweep.batch;
    sweep.q0s.resize(sweep.batch), sweep.v0s.resize(sweep.batch), sweep.results.resize(sweep.batch);
    sweep.values.resize(sweep.names.size()), sweep.batch_values.resize(sweep.batch);
    if (sweep.rank != 0) { // a worker: its batches, round robin, to rank 0
        for (std::size_t b = sweep.rank; b < sweep.batches; b += sweep.ranks) {
            auto rows = sweep.run_batch(b);
            sweep.processes->send(b, std::move(*rows));
        }
        sweep.processes->flush();
        return 0;
    }
    const bool ok = sweep.lead();
    std::fclose(sweep.out);
    if (sweep.processes) sweep.processes->flush();
    return ok ? 0 : 1;
}

} // namespace phynjo::runtime
