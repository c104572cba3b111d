#pragma once
/// \file
/// The simulation archive's file (docs/archive.md): an append-only sequence of checksummed
/// records — one header that says which run it is, then snapshots, each what the run needs to
/// continue bit for bit from that step. After REBOUND's SimulationArchive (Rein & Tamayo 2017,
/// MNRAS 467, 2377): any instant is the nearest snapshot before it, integrated forward.
///
/// A record is
///
///     offset  size  what
///     0       4     "PJAR"
///     4       4     kind (u32): 1 header, 2 snapshot
///     8       8     payload length L (u64)
///     16      4     CRC-32 of bytes 0…15
///     20      L     payload
///     20 + L  4     CRC-32 of the payload
///
/// integers little-endian, CRC-32 that of zlib (IEEE 802.3, Python's zlib.crc32). A record is
/// written with one call, so a run killed mid-write leaves at most one record cut short at the
/// end: the reader ignores it (ArchiveContents::torn_at) and the writer continuing the run cuts
/// it off before appending. Anything else that does not check — a flipped bit, a record of
/// another kind, a header of another format version — is an ArchiveError naming the offset.
/// Nothing already written is ever rewritten.
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/world.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace phynjo::runtime {

/// The format this phynjo writes and reads (a header's `format`).
inline constexpr std::uint32_t kArchiveFormatVersion = 1;

/// An archive that cannot be read, or written: the message names the file, and the byte
/// offset where that applies (`offset()`, else -1).
class ArchiveError : public Error {
public:
    ArchiveError(const std::string& message, std::int64_t offset = -1) : Error(message), offset_(offset) {}
    [[nodiscard]] std::int64_t offset() const noexcept { return offset_; }

private:
    std::int64_t offset_;
};

/// What identifies a run: ordered (key, value) text fields — model, its hash, parameters,
/// integrator and its settings, dt … — compared field by field when a run continues.
/// Keys are words without spaces; values one line each.
struct ArchiveHeader {
    std::vector<std::pair<std::string, std::string>> fields;

    /// Adds a field (std::invalid_argument for a key with a space or newline, a value with a
    /// newline).
    ArchiveHeader& add(std::string key, std::string value);
    /// The value of `key`, or nullopt.
    [[nodiscard]] std::optional<std::string_view> get(std::string_view key) const;
    /// The first field in which `other` differs from this one ("parameter m2: 1 in the
    /// archive, 2 here"), or empty when they are the same run. `what_this` and `what_other`
    /// name the two sides in the message.
    [[nodiscard]] std::string difference(const ArchiveHeader& other, std::string_view what_this = "the archive",
                                         std::string_view what_other = "this run") const;
};

/// One snapshot: how many run steps were taken, the time reached, and named sections of bytes
/// (the world's fields, the integrator's state, the event monitor's, the output's …).
struct ArchiveSnapshot {
    std::uint64_t step = 0;
    double time = 0; ///< s
    std::vector<std::pair<std::string, std::string>> sections;

    /// The section `name` (ArchiveError when it is missing: a snapshot of another writer).
    [[nodiscard]] const std::string& section(std::string_view name) const;
};

/// Where each snapshot of a file is, without its sections.
struct ArchiveIndexEntry {
    std::uint64_t offset = 0; ///< of its record
    std::uint64_t step = 0;
    double time = 0;
};

/// A file read through: its header, where its snapshots are, where the complete records end.
struct ArchiveContents {
    ArchiveHeader header;
    std::vector<ArchiveIndexEntry> snapshots;
    /// Bytes of complete records (the file's size unless a record was cut short).
    std::uint64_t valid_end = 0;
    /// The offset of a last record cut short (a run killed while writing it), if any.
    std::optional<std::uint64_t> torn_at;
};

/// Reads `path` through and checks every record (ArchiveError: not an archive, another
/// format version, a checksum that fails — with its offset — or a file that cannot be read).
[[nodiscard]] ArchiveContents read_archive(const std::string& path);
/// The snapshot whose record is at `offset` (an ArchiveIndexEntry's).
[[nodiscard]] ArchiveSnapshot read_snapshot(const std::string& path, std::uint64_t offset);
/// The latest snapshot at or before time `t` (the first one when t precedes them all), or
/// nullopt when the archive has none.
[[nodiscard]] std::optional<ArchiveIndexEntry> snapshot_before(const ArchiveContents& contents, double t);

/// Appends records to an archive. Each write is whole or an ArchiveError (a full disk is an
/// error at the write that failed, naming the file and the offset); with `sync`, each record
/// reaches the disk (fdatasync) before write returns, so a machine that goes down loses
/// nothing already written, not only a killed process.
class ArchiveWriter {
public:
    /// A new archive at `path` holding `header` (ArchiveError if the file exists: continuing
    /// one is `resume`).
    static ArchiveWriter create(const std::string& path, const ArchiveHeader& header, bool sync = true);
    /// Continues the archive at `path`, read as `contents` (read_archive), whose header must be
    /// `header` (ArchiveError naming the first difference). A last record cut short is cut off.
    static ArchiveWriter resume(const std::string& path, const ArchiveContents& contents, const ArchiveHeader& header,
                                bool sync = true);

    ArchiveWriter(ArchiveWriter&& other) noexcept;
    ArchiveWriter& operator=(ArchiveWriter&& other) noexcept;
    ArchiveWriter(const ArchiveWriter&) = delete;
    ArchiveWriter& operator=(const ArchiveWriter&) = delete;
    ~ArchiveWriter();

    /// Appends `snapshot`.
    void write(const ArchiveSnapshot& snapshot);
    /// Bytes in the file.
    [[nodiscard]] std::uint64_t size() const noexcept { return size_; }
    [[nodiscard]] const std::string& path() const noexcept { return path_; }

private:
    ArchiveWriter(std::string path, int fd, std::uint64_t size, bool sync);
    void append(std::uint32_t kind, const std::string& payload);

    std::string path_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
    bool sync_ = true;
};

/// Bytes of plain values in a snapshot's sections, little-endian (docs/archive.md).
class ArchiveBytes {
public:
    ArchiveBytes& u64(std::uint64_t x);
    ArchiveBytes& f64(double x);
    ArchiveBytes& f64s(const double* x, std::size_t n);
    ArchiveBytes& str(std::string_view s); ///< its length (u64), then its bytes
    [[nodiscard]] std::string take() { return std::move(bytes_); }

private:
    std::string bytes_;
};

/// Reads what ArchiveBytes wrote; ArchiveError when a section is shorter than its reader.
class ArchiveReader {
public:
    ArchiveReader(std::string_view bytes, std::string_view what) : bytes_(bytes), what_(what) {}
    std::uint64_t u64();
    double f64();
    void f64s(double* x, std::size_t n);
    std::string str();
    /// ArchiveError unless every byte was read.
    void finish() const;

private:
    void need(std::size_t n) const;
    std::string_view bytes_;
    std::string_view what_;
    std::size_t at_ = 0;
};

/// A world's time, tick and every field of every component, bit for bit (the section
/// "world" of docs/archive.md: field count, component count, time, tick, then the values
/// field by field).
void save_world(ArchiveBytes& out, const World& w);
/// Sets `w` (whose layout must have the saved field and component counts: ArchiveError
/// otherwise) to what save_world wrote.
void restore_world(ArchiveReader& in, World& w);

} // namespace phynjo::runtime
