#pragma once
/// \file
/// The archive of a run of any World stepped by a Stepper in steps of one dt (docs/archive.md,
/// *Worlds of the runtime*): rigid worlds, scenes (the contacts' warm-start cache is a field of
/// the world), N-body — every world whose step is a pure function (dt, world) → world. A
/// snapshot holds three sections:
///
///     world   save_world: every field, the time, the tick, bit for bit
///     clock   the Stepper's clock: t₀, dt, the steps since t₀, the time the last step ended
///             (so a continued run's times are t₀ + k·dt exactly, as the uninterrupted run's,
///             not t_snapshot + j·dt, which rounds differently)
///     output  the length of every output file of the run, flushed (and synced) before
///
/// A run continued from its latest snapshot (ArchivedRun::resume) therefore writes the same
/// bytes as the run that was never stopped; a state at any step is the latest snapshot before
/// it stepped forward (ArchivedRun::restore). Where the snapshots fall changes nothing in the
/// run, so they may be spaced by wall time (REBOUND's rule): ArchiveSpacing.
#include "phynjo/runtime/core/archive.hpp"
#include "phynjo/runtime/core/workflow.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// When a run writes its snapshots: after every `steps`-th step when steps > 0, else after the
/// first step that ends `seconds` of wall time after the previous snapshot (or the start).
struct ArchiveSpacing {
    std::uint64_t steps = 0;
    double seconds = 1.0; ///< wall time, s
    /// From text: "K" (steps, K ≥ 1) or "Xs" (seconds of wall time, X > 0); nullopt otherwise.
    static std::optional<ArchiveSpacing> parse(const std::string& text);
};

/// When a run's next snapshot is due (ArchiveSpacing): after every K-th step, or after the
/// first step that ends `seconds` of wall time after the last snapshot (or the start) — the
/// clock read every 64 steps only, a small world's step being shorter than the read.
class SnapshotSchedule {
public:
    explicit SnapshotSchedule(ArchiveSpacing spacing) : spacing_(spacing), since_(std::chrono::steady_clock::now()) {}
    /// Whether a snapshot is due after step `step` (counted from the run's start).
    [[nodiscard]] bool due(std::uint64_t step) const;
    /// A snapshot was written now: the wall time counts from here.
    void taken() { since_ = std::chrono::steady_clock::now(); }

private:
    ArchiveSpacing spacing_;
    std::chrono::steady_clock::time_point since_;
};

/// The names of a world's fields, comma-separated (an archive header's `world.fields`).
[[nodiscard]] std::string field_names(const World& w);

/// A Stepper's clock as a snapshot's section "clock" (file comment).
void save_clock(ArchiveBytes& out, const Stepper& stepper);
void restore_clock(ArchiveReader& in, Stepper& stepper);

/// A run of a World, archived (file comment). Typical use:
///
///     auto run = resume ? ArchivedRun::resume(path, header, w, stepper, spacing, {csv})
///                       : ArchivedRun::create(path, header, w, spacing, {csv});
///     for (std::uint64_t k = run.step(); k < steps; ++k) {
///         stepper.step(w, dt);
///         std::fprintf(run.output(0), …);   // the rows of step k + 1
///         run.stepped(w, stepper);           // a snapshot when one is due
///     }
///     run.finish(w, stepper);                // the last snapshot: a later resume continues past the end
class ArchivedRun {
public:
    /// A new archive at `path` for the run `header` names, starting from `world` at step 0;
    /// `outputs` are created (truncated) and opened for writing. The header gains the world's
    /// shape (fields `world.fields`, `world.components`): an archive of another world is refused
    /// when continued. ArchiveError when `path` exists or a file cannot be opened.
    static ArchivedRun create(const std::string& path, ArchiveHeader header, const World& world, ArchiveSpacing spacing,
                              const std::vector<std::string>& outputs = {}, bool sync = true);
    /// Continues the run archived at `path` (whose header must be `header` and `world`'s shape:
    /// ArchiveError naming the first difference): `world` and `stepper` are set to its latest
    /// snapshot, `outputs` cut to their lengths there and opened for appending; without a
    /// snapshot the run starts again from step 0 (`world` as given, `outputs` truncated).
    static ArchivedRun resume(const std::string& path, ArchiveHeader header, World& world, Stepper& stepper,
                              ArchiveSpacing spacing, const std::vector<std::string>& outputs = {}, bool sync = true);
    /// Reads the archive at `path` (header checked as resume) and sets `world` and `stepper` to
    /// its latest snapshot at or before step `up_to`; returns that snapshot's step, 0 (and
    /// `world` untouched) when there is none. Nothing is written.
    static std::uint64_t restore(const std::string& path, ArchiveHeader header, World& world, Stepper& stepper,
                                 std::uint64_t up_to = std::numeric_limits<std::uint64_t>::max());

    ArchivedRun(ArchivedRun&&) noexcept;
    ArchivedRun& operator=(ArchivedRun&&) noexcept;
    ArchivedRun(const ArchivedRun&) = delete;
    ArchivedRun& operator=(const ArchivedRun&) = delete;
    ~ArchivedRun(); ///< closes the outputs (flushed)

    /// The steps taken: where the run continues (the snapshot's step after resume).
    [[nodiscard]] std::uint64_t step() const noexcept { return step_; }
    /// Output file i, open for writing at its end.
    [[nodiscard]] std::FILE* output(std::size_t i) const { return outputs_.at(i).file; }
    /// Counts a step that left `world`; writes a snapshot when one is due (ArchiveSpacing).
    void stepped(const World& world, const Stepper& stepper);
    /// A snapshot now (unless the last one, or the one continued from, is at this step), the
    /// outputs flushed and synced.
    void finish(const World& world, const Stepper& stepper);
    /// Flushes and closes the outputs (ArchiveError when that fails: a full disk); the
    /// destructor closes them too, but cannot report a failure.
    void close();
    /// Snapshots written by this process.
    [[nodiscard]] std::uint64_t snapshots() const noexcept { return written_; }

private:
    struct Output {
        std::string path;
        std::FILE* file = nullptr;
    };
    ArchivedRun(ArchiveWriter writer, ArchiveSpacing spacing, std::vector<Output> outputs, std::uint64_t step, bool sync);
    void snapshot(const World& world, const Stepper& stepper);
    void close_quietly() noexcept;

    ArchiveWriter writer_;
    SnapshotSchedule schedule_;
    std::vector<Output> outputs_;
    std::uint64_t step_ = 0, last_snapshot_ = 0, written_ = 0;
    bool sync_ = true;
};

} // namespace phynjo::runtime
