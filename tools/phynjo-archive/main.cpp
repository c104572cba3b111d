// phynjo-archive list|verify|extract FILE: what a simulation archive (docs/archive.md) holds,
// whether every record checks, and the world of a snapshot as CSV — from the file alone,
// without the program or the model that wrote it.
#include "phynjo/runtime/core/archive.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

using namespace phynjo::runtime;

namespace {

constexpr const char* usage_text =
    R"(usage: phynjo-archive list FILE
       phynjo-archive verify FILE
       phynjo-archive extract FILE (--step K | --at T) [-o FILE]

Reads a simulation archive (--archive of a simulator or phynjo-run, ArchivedRun of a program;
docs/archive.md).

  list     the header's fields, then every snapshot: its step, time (s), byte offset, size
           and sections
  verify   reads every record and checks both its checksums and its sections; exit 0 when all
           do (a last record cut short by a killed run is reported: the run that continues the
           archive cuts it off), 1 naming the byte offset of the first that does not
  extract  the world of the snapshot at step K, or of the latest at or before time T, as CSV
           to -o (default standard output): t, tick, the component's index, then a column per
           field (named when the header names them), %.17g, so the values read back are the
           snapshot's bit for bit. The state at a time between snapshots is the program's own
           --at T, which steps forward from there.

exit status: 0 done, 1 the archive is damaged or cannot be read, 2 usage error
)";

struct Usage {
    std::string message;
};

std::vector<std::string> split(std::string_view s, char sep) {
    std::vector<std::string> out;
    std::size_t at = 0;
    while (at <= s.size()) {
        const std::size_t end = std::min(s.find(sep, at), s.size());
        out.emplace_back(s.substr(at, end - at));
        at = end + 1;
    }
    return out;
}

int list(const std::string& path) {
    const ArchiveContents c = read_archive(path);
    std::printf("%s: %zu snapshot%s, %llu bytes of records", path.c_str(), c.snapshots.size(),
                c.snapshots.size() == 1 ? "" : "s", static_cast<unsigned long long>(c.valid_end));
    if (c.torn_at) std::printf("; a last record cut short at byte %llu (ignored)", static_cast<unsigned long long>(*c.torn_at));
    std::printf("\nheader:\n");
    for (const auto& [key, value] : c.header.fields) std::printf("  %s %s\n", key.c_str(), value.c_str());
    std::printf("snapshots:\n  %12s %24s %12s %10s  sections (bytes)\n", "step", "t (s)", "offset", "bytes");
    for (std::size_t i = 0; i < c.snapshots.size(); ++i) {
        const ArchiveIndexEntry& e = c.snapshots[i];
        const std::uint64_t end = i + 1 < c.snapshots.size() ? c.snapshots[i + 1].offset : c.valid_end;
        const ArchiveSnapshot s = read_snapshot(path, e.offset);
        std::string sections;
        for (const auto& [name, bytes] : s.sections) sections += (sections.empty() ? "" : ", ") + name + " " + std::to_string(bytes.size());
        std::printf("  %12llu %24.17g %12llu %10llu  %s\n", static_cast<unsigned long long>(e.step), e.time,
                    static_cast<unsigned long long>(e.offset), static_cast<unsigned long long>(end - e.offset), sections.c_str());
    }
    return 0;
}

int verify(const std::string& path) {
    const ArchiveContents c = read_archive(path); // every record's two checksums
    for (const ArchiveIndexEntry& e : c.snapshots) {
        const ArchiveSnapshot s = read_snapshot(path, e.offset); // and its sections' lengths
        if (s.step != e.step) throw ArchiveError(path + ": the snapshot at byte " + std::to_string(e.offset) + " reads otherwise twice");
    }
    std::printf("%s: good: the header and %zu snapshot%s, every checksum checks", path.c_str(), c.snapshots.size(),
                c.snapshots.size() == 1 ? "" : "s");
    if (c.torn_at)
        std::printf("; a last record cut short at byte %llu (a run killed while writing it: ignored, cut off when the run "
                    "continues)",
                    static_cast<unsigned long long>(*c.torn_at));
    std::printf("\n");
    return 0;
}

int extract(const std::string& path, std::optional<std::uint64_t> step, std::optional<double> at, const std::string& output) {
    const ArchiveContents c = read_archive(path);
    std::optional<ArchiveIndexEntry> entry;
    if (step) {
        for (const ArchiveIndexEntry& e : c.snapshots)
            if (e.step == *step) entry = e;
        if (!entry) {
            std::fprintf(stderr, "phynjo-archive: %s has no snapshot at step %llu (phynjo-archive list %s shows them)\n",
                         path.c_str(), static_cast<unsigned long long>(*step), path.c_str());
            return 1;
        }
    } else {
        entry = snapshot_before(c, *at);
        if (!entry || entry->time > *at) {
            std::fprintf(stderr, "phynjo-archive: %s has no snapshot at or before t = %.17g s\n", path.c_str(), *at);
            return 1;
        }
    }
    const ArchiveSnapshot s = read_snapshot(path, entry->offset);
    ArchiveReader in(s.section("world"), "the snapshot's world");
    const std::uint64_t fields = in.u64(), components = in.u64();
    const double t = in.f64();
    const std::uint64_t tick = in.u64();
    std::vector<double> values(fields * components);
    in.f64s(values.data(), values.size());
    in.finish();
    std::vector<std::string> names;
    if (const auto named = c.header.get("world.fields")) names = split(*named, ',');
    if (names.size() != fields) {
        names.clear();
        for (std::uint64_t f = 0; f < fields; ++f) names.push_back("field" + std::to_string(f));
    }
    std::FILE* out = output.empty() ? stdout : std::fopen(output.c_str(), "w");
    if (!out) {
        std::fprintf(stderr, "phynjo-archive: cannot write %s: %s\n", output.c_str(), std::strerror(errno));
        return 1;
    }
    std::fprintf(out, "t,tick,component");
    for (const auto& n : names) std::fprintf(out, ",%s", n.c_str());
    std::fprintf(out, "\n");
    for (std::uint64_t i = 0; i < components; ++i) {
        std::fprintf(out, "%.17g,%llu,%llu", t, static_cast<unsigned long long>(tick), static_cast<unsigned long long>(i));
        for (std::uint64_t f = 0; f < fields; ++f) std::fprintf(out, ",%.17g", values[f * components + i]);
        std::fprintf(out, "\n");
    }
    const bool failed = std::ferror(out) != 0 || (out != stdout ? std::fclose(out) : std::fflush(out)) != 0;
    if (failed) {
        std::fprintf(stderr, "phynjo-archive: cannot write %s\n", output.empty() ? "standard output" : output.c_str());
        return 1;
    }
    std::fprintf(stderr, "phynjo-archive: the snapshot at step %llu, t = %.17g s (%llu components, %llu fields)\n",
                 static_cast<unsigned long long>(s.step), t, static_cast<unsigned long long>(components),
                 static_cast<unsigned long long>(fields));
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    std::string command, path, output;
    std::optional<std::uint64_t> step;
    std::optional<double> at;
    try {
        std::vector<std::string> args(argv + 1, argv + argc);
        if (args.size() == 1 && (args[0] == "--help" || args[0] == "-h")) {
            std::fputs(usage_text, stdout);
            return 0;
        }
        for (std::size_t i = 0; i < args.size(); ++i) {
            const std::string& a = args[i];
            auto value = [&]() -> const std::string& {
                if (i + 1 >= args.size()) throw Usage{a + " needs a value"};
                return args[++i];
            };
            if (a == "--step") {
                const std::string& v = value();
                char* end = nullptr;
                const unsigned long long k = std::strtoull(v.c_str(), &end, 10);
                if (v.empty() || *end != '\0' || v[0] == '-') throw Usage{"--step: '" + v + "' is not a step count"};
                step = k;
            } else if (a == "--at") {
                const std::string& v = value();
                char* end = nullptr;
                const double x = std::strtod(v.c_str(), &end);
                if (v.empty() || *end != '\0' || !std::isfinite(x)) throw Usage{"--at: '" + v + "' is not a time"};
                at = x;
            } else if (a == "-o" || a == "--output") {
                output = value();
            } else if (!a.empty() && a[0] == '-') {
                throw Usage{"unknown option " + a};
            } else if (command.empty()) {
                command = a;
            } else if (path.empty()) {
                path = a;
            } else {
                throw Usage{"one archive at a time: '" + a + "'"};
            }
        }
        if (command != "list" && command != "verify" && command != "extract")
            throw Usage{command.empty() ? "a command: list, verify or extract" : "unknown command '" + command + "'"};
        if (path.empty()) throw Usage{"which archive?"};
        if (command == "extract" && step.has_value() == at.has_value()) throw Usage{"extract takes --step K or --at T"};
        if (command != "extract" && (step || at || !output.empty())) throw Usage{"--step, --at and -o are for extract"};
    } catch (const Usage& u) {
        std::fprintf(stderr, "phynjo-archive: %s\n%s", u.message.c_str(), usage_text);
        return 2;
    }
    try {
        if (command == "list") return list(path);
        if (command == "verify") return verify(path);
        return extract(path, step, at, output);
    } catch (const ArchiveError& e) {
        std::fprintf(stderr, "phynjo-archive: %s\n", e.what());
        return 1;
    }
}
