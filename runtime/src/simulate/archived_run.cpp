#include "phynjo/runtime/simulate/archived_run.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <unistd.h>

namespace phynjo::runtime {

namespace {

ArchiveHeader with_world(ArchiveHeader header, const World& w) {
    header.add("world.fields", field_names(w));
    header.add("world.components", std::to_string(w.size()));
    return header;
}

std::string errno_text(const std::string& what) { return what + ": " + std::strerror(errno); }

/// The latest snapshot at or before step `up_to`, read; nullopt when there is none.
std::optional<ArchiveSnapshot> latest(const std::string& path, const ArchiveContents& contents, std::uint64_t up_to) {
    for (auto it = contents.snapshots.rbegin(); it != contents.snapshots.rend(); ++it)
        if (it->step <= up_to) return read_snapshot(path, it->offset);
    return std::nullopt;
}

void restore_state(const ArchiveSnapshot& snap, World& world, Stepper& stepper) {
    ArchiveReader w(snap.section("world"), "the snapshot's world");
    restore_world(w, world);
    w.finish();
    ArchiveReader c(snap.section("clock"), "the snapshot's clock");
    restore_clock(c, stepper);
    c.finish();
}

} // namespace

std::optional<ArchiveSpacing> ArchiveSpacing::parse(const std::string& text) {
    if (text.empty()) return std::nullopt;
    char* end = nullptr;
    errno = 0;
    if (text.back() == 's') {
        const std::string number = text.substr(0, text.size() - 1);
        const double x = std::strtod(number.c_str(), &end);
        if (number.empty() || *end != '\0' || errno != 0 || !(x > 0) || !std::isfinite(x)) return std::nullopt;
        return ArchiveSpacing{0, x};
    }
    if (text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
    const unsigned long long k = std::strtoull(text.c_str(), &end, 10);
    if (*end != '\0' || errno != 0 || k == 0) return std::nullopt;
    return ArchiveSpacing{k, 0};
}

bool SnapshotSchedule::due(std::uint64_t step) const {
    if (spacing_.steps > 0) return step % spacing_.steps == 0;
    if ((step & 63) != 0) return false;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since_).count() >= spacing_.seconds;
}

std::string field_names(const World& w) {
    std::string s;
    for (const auto& f : w.layout().fields) s += (s.empty() ? "" : ",") + f;
    return s;
}

void save_clock(ArchiveBytes& out, const Stepper& stepper) {
    const Stepper::Clock c = stepper.clock();
    out.f64(c.origin).f64(c.dt).f64(c.last_time).u64(c.count);
}

void restore_clock(ArchiveReader& in, Stepper& stepper) {
    Stepper::Clock c;
    c.origin = in.f64();
    c.dt = in.f64();
    c.last_time = in.f64();
    c.count = in.u64();
    stepper.set_clock(c);
}

ArchivedRun::ArchivedRun(ArchiveWriter writer, ArchiveSpacing spacing, std::vector<Output> outputs, std::uint64_t step,
                         bool sync)
    : writer_(std::move(writer)), schedule_(spacing), outputs_(std::move(outputs)), step_(step), last_snapshot_(step),
      sync_(sync) {}

ArchivedRun::ArchivedRun(ArchivedRun&& o) noexcept
    : writer_(std::move(o.writer_)), schedule_(o.schedule_), outputs_(std::move(o.outputs_)), step_(o.step_),
      last_snapshot_(o.last_snapshot_), written_(o.written_), sync_(o.sync_) {
    o.outputs_.clear();
}

ArchivedRun& ArchivedRun::operator=(ArchivedRun&& o) noexcept {
    if (this != &o) {
        close_quietly();
        writer_ = std::move(o.writer_);
        schedule_ = o.schedule_;
        outputs_ = std::move(o.outputs_);
        o.outputs_.clear();
        step_ = o.step_;
        last_snapshot_ = o.last_snapshot_;
        written_ = o.written_;
        sync_ = o.sync_;
    }
    return *this;
}

ArchivedRun::~ArchivedRun() { close_quietly(); }

void ArchivedRun::close_quietly() noexcept {
    for (auto& o : outputs_)
        if (o.file) std::fclose(std::exchange(o.file, nullptr));
}

void ArchivedRun::close() {
    std::string failed;
    for (auto& o : outputs_)
        if (o.file && std::fclose(std::exchange(o.file, nullptr)) != 0 && failed.empty()) failed = errno_text("cannot write " + o.path);
    if (!failed.empty()) throw ArchiveError(failed);
}

ArchivedRun ArchivedRun::create(const std::string& path, ArchiveHeader header, const World& world, ArchiveSpacing spacing,
                                const std::vector<std::string>& outputs, bool sync) {
    ArchiveWriter writer = ArchiveWriter::create(path, with_world(std::move(header), world), sync);
    ArchivedRun run(std::move(writer), spacing, {}, 0, sync);
    for (const auto& p : outputs) {
        std::FILE* f = std::fopen(p.c_str(), "w");
        if (!f) throw ArchiveError(errno_text("cannot write " + p));
        run.outputs_.push_back({p, f});
    }
    return run;
}

ArchivedRun ArchivedRun::resume(const std::string& path, ArchiveHeader header, World& world, Stepper& stepper,
                                ArchiveSpacing spacing, const std::vector<std::string>& outputs, bool sync) {
    header = with_world(std::move(header), world);
    const ArchiveContents contents = read_archive(path);
    ArchiveWriter writer = ArchiveWriter::resume(path, contents, header, sync);
    const std::optional<ArchiveSnapshot> from = latest(path, contents, std::numeric_limits<std::uint64_t>::max());
    std::vector<std::uint64_t> lengths(outputs.size(), 0);
    if (from) {
        restore_state(*from, world, stepper);
        ArchiveReader out(from->section("output"), "the snapshot's output");
        if (out.u64() != outputs.size())
            throw ArchiveError(path + ": the snapshot's run wrote another number of output files");
        for (auto& n : lengths) n = out.u64();
        out.finish();
    }
    ArchivedRun run(std::move(writer), spacing, {}, from ? from->step : 0, sync);
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        const std::string& p = outputs[i];
        std::FILE* f = std::fopen(p.c_str(), from ? "r+" : "w");
        if (!f) throw ArchiveError(errno_text("cannot continue " + p));
        run.outputs_.push_back({p, f});
        if (!from) continue;
        if (std::fseek(f, 0, SEEK_END) != 0) throw ArchiveError(errno_text("cannot continue " + p));
        const long size = std::ftell(f);
        if (size < 0 || static_cast<std::uint64_t>(size) < lengths[i])
            throw ArchiveError(p + " is shorter (" + std::to_string(size) + " bytes) than at the snapshot (" +
                               std::to_string(lengths[i]) + "): not this run's file");
        if (::ftruncate(::fileno(f), static_cast<off_t>(lengths[i])) != 0 || std::fseek(f, 0, SEEK_END) != 0)
            throw ArchiveError(errno_text("cannot continue " + p));
    }
    return run;
}

std::uint64_t ArchivedRun::restore(const std::string& path, ArchiveHeader header, World& world, Stepper& stepper,
                                   std::uint64_t up_to) {
    header = with_world(std::move(header), world);
    const ArchiveContents contents = read_archive(path);
    if (const std::string d = contents.header.difference(header); !d.empty())
        throw ArchiveError(path + " is the archive of another run: " + d);
    const std::optional<ArchiveSnapshot> from = latest(path, contents, up_to);
    if (!from) return 0;
    restore_state(*from, world, stepper);
    return from->step;
}

void ArchivedRun::stepped(const World& world, const Stepper& stepper) {
    if (schedule_.due(++step_)) snapshot(world, stepper);
}

void ArchivedRun::finish(const World& world, const Stepper& stepper) {
    if (last_snapshot_ != step_) snapshot(world, stepper); // (a run continued and stopped at once adds none)
    for (auto& o : outputs_)
        if (o.file && std::fflush(o.file) != 0) throw ArchiveError(errno_text("cannot write " + o.path));
}

void ArchivedRun::snapshot(const World& world, const Stepper& stepper) {
    // the rows up to this step on the disk before the snapshot that says they are there
    ArchiveBytes out;
    out.u64(outputs_.size());
    for (auto& o : outputs_) {
        if (std::fflush(o.file) != 0) throw ArchiveError(errno_text("cannot write " + o.path));
        if (sync_ && ::fdatasync(::fileno(o.file)) != 0 && errno != EINVAL)
            throw ArchiveError(errno_text("cannot sync " + o.path));
        const long at = std::ftell(o.file);
        if (at < 0) throw ArchiveError(errno_text("cannot tell the length of " + o.path));
        out.u64(static_cast<std::uint64_t>(at));
    }
    ArchiveSnapshot snap;
    snap.step = step_;
    snap.time = world.time;
    ArchiveBytes w, c;
    save_world(w, world);
    save_clock(c, stepper);
    snap.sections = {{"world", w.take()}, {"clock", c.take()}, {"output", out.take()}};
    writer_.write(snap);
    last_snapshot_ = step_;
    ++written_;
    schedule_.taken();
}

} // namespace phynjo::runtime
