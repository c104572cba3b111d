#include "phynjo/runtime/core/archive.hpp"

#include <boost/crc.hpp>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <memory>
#include <stdexcept>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace phynjo::runtime {

namespace {

constexpr char kMagic[4] = {'P', 'J', 'A', 'R'};
constexpr std::uint32_t kHeaderKind = 1, kSnapshotKind = 2;
constexpr std::size_t kRecordHead = 20, kRecordTail = 4;

std::uint32_t crc32(const void* data, std::size_t n, std::uint32_t crc = 0) {
    // zlib's CRC-32, continued from `crc` (a finished value, as zlib.crc32's second argument)
    boost::crc_32_type c;
    c.reset(crc ^ 0xFFFFFFFFu);
    c.process_bytes(data, n);
    return c.checksum();
}

void put_u32(std::string& s, std::uint32_t x) {
    for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>((x >> (8 * i)) & 0xFF));
}
void put_u64(std::string& s, std::uint64_t x) {
    for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>((x >> (8 * i)) & 0xFF));
}
std::uint32_t get_u32(const unsigned char* p) {
    std::uint32_t x = 0;
    for (int i = 3; i >= 0; --i) x = (x << 8) | p[i];
    return x;
}
std::uint64_t get_u64(const unsigned char* p) {
    std::uint64_t x = 0;
    for (int i = 7; i >= 0; --i) x = (x << 8) | p[i];
    return x;
}

std::string system_error(const std::string& what) { return what + ": " + std::strerror(errno); }

/// An open file, closed on every path out.
struct Fd {
    int fd = -1;
    explicit Fd(int f) : fd(f) {}
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() {
        if (fd >= 0) ::close(fd);
    }
    int release() { return std::exchange(fd, -1); }
};

/// Reads exactly n bytes at `offset` (pread), or throws.
void read_at(int fd, void* out, std::size_t n, std::uint64_t offset, const std::string& path) {
    auto* p = static_cast<char*>(out);
    while (n > 0) {
        const ssize_t r = ::pread(fd, p, n, static_cast<off_t>(offset));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw ArchiveError(system_error(path + ": cannot read at byte " + std::to_string(offset)),
                               static_cast<std::int64_t>(offset));
        }
        if (r == 0) throw ArchiveError(path + ": ends inside the record at byte " + std::to_string(offset), static_cast<std::int64_t>(offset));
        p += r;
        n -= static_cast<std::size_t>(r);
        offset += static_cast<std::uint64_t>(r);
    }
}

std::uint64_t file_size(int fd, const std::string& path) {
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw ArchiveError(system_error(path + ": cannot stat"));
    return static_cast<std::uint64_t>(st.st_size);
}

int open_for_reading(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw ArchiveError(system_error("cannot open the archive " + path));
    return fd;
}

/// True when every byte from `offset` to the end is zero (what a crash can leave after the
/// last record on some file systems: space allocated, never written).
bool zeros_to_end(int fd, std::uint64_t offset, std::uint64_t size, const std::string& path) {
    char buf[4096];
    while (offset < size) {
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(sizeof buf, size - offset));
        read_at(fd, buf, n, offset, path);
        if (std::any_of(buf, buf + n, [](char c) { return c != 0; })) return false;
        offset += n;
    }
    return true;
}

struct RecordHead {
    std::uint32_t kind = 0;
    std::uint64_t length = 0;
};

std::string where(const std::string& path, std::uint64_t offset) {
    return path + ": the record at byte " + std::to_string(offset);
}

/// The record head at `offset`, checked; nullopt when the head itself is damaged.
std::optional<RecordHead> read_head(int fd, std::uint64_t offset, const std::string& path) {
    unsigned char h[kRecordHead];
    read_at(fd, h, sizeof h, offset, path);
    if (std::memcmp(h, kMagic, 4) != 0 || get_u32(h + 16) != crc32(h, 16)) return std::nullopt;
    return RecordHead{get_u32(h + 4), get_u64(h + 8)};
}

/// The payload of the record at `offset` (its head read as `head`), its checksum checked.
std::string read_payload(int fd, std::uint64_t offset, const RecordHead& head, const std::string& path) {
    std::string payload(static_cast<std::size_t>(head.length), '\0');
    read_at(fd, payload.data(), payload.size(), offset + kRecordHead, path);
    unsigned char t[kRecordTail];
    read_at(fd, t, sizeof t, offset + kRecordHead + head.length, path);
    if (get_u32(t) != crc32(payload.data(), payload.size()))
        throw ArchiveError(where(path, offset) + " is damaged: its checksum fails (a changed byte in bytes " +
                               std::to_string(offset + kRecordHead) + " to " +
                               std::to_string(offset + kRecordHead + head.length + kRecordTail - 1) + ")",
                           static_cast<std::int64_t>(offset));
    return payload;
}

ArchiveHeader parse_header(const std::string& payload, const std::string& path) {
    ArchiveHeader h;
    std::size_t at = 0;
    bool first = true;
    while (at < payload.size()) {
        std::size_t end = payload.find('\n', at);
        if (end == std::string::npos) end = payload.size();
        const std::string line = payload.substr(at, end - at);
        at = end + 1;
        const std::size_t space = line.find(' ');
        const std::string key = line.substr(0, space), value = space == std::string::npos ? "" : line.substr(space + 1);
        if (first) {
            if (key != "format") throw ArchiveError(path + ": not a phynjo archive (its header has no format)", 0);
            if (value != std::to_string(kArchiveFormatVersion))
                throw ArchiveError(path + ": an archive of format " + value + "; this phynjo reads format " +
                                       std::to_string(kArchiveFormatVersion),
                                   0);
            first = false;
            continue;
        }
        h.fields.emplace_back(key, value);
    }
    if (first) throw ArchiveError(path + ": not a phynjo archive (an empty header)", 0);
    return h;
}

std::string header_payload(const ArchiveHeader& h) {
    std::string s = "format " + std::to_string(kArchiveFormatVersion) + "\n";
    for (const auto& [k, v] : h.fields) s += k + " " + v + "\n";
    return s;
}

std::string snapshot_payload(const ArchiveSnapshot& s) {
    ArchiveBytes b;
    b.u64(s.step).f64(s.time).u64(s.sections.size());
    for (const auto& [name, data] : s.sections) b.str(name).str(data);
    return b.take();
}

/// Syncs the folder holding `path`, so that a new file's name survives a crash too.
void sync_folder(const std::string& path) {
    const std::size_t slash = path.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return; // (best effort: the file's own data is synced regardless)
    (void)::fsync(fd);
    ::close(fd);
}

} // namespace

// ---- header and snapshot ------------------------------------------------------------------

ArchiveHeader& ArchiveHeader::add(std::string key, std::string value) {
    if (key.empty() || key.find_first_of(" \n") != std::string::npos)
        throw std::invalid_argument("ArchiveHeader::add: the key '" + key + "' must be one word");
    if (value.find('\n') != std::string::npos)
        throw std::invalid_argument("ArchiveHeader::add: the value of '" + key + "' must be one line");
    fields.emplace_back(std::move(key), std::move(value));
    return *this;
}

std::optional<std::string_view> ArchiveHeader::get(std::string_view key) const {
    for (const auto& [k, v] : fields)
        if (k == key) return std::string_view(v);
    return std::nullopt;
}

std::string ArchiveHeader::difference(const ArchiveHeader& other, std::string_view what_this,
                                      std::string_view what_other) const {
    const auto show = [](std::optional<std::string_view> v) { return v ? "'" + std::string(*v) + "'" : std::string("none"); };
    for (const auto& [k, v] : fields)
        if (const auto o = other.get(k); !o || *o != v)
            return k + ": " + show(v) + " in " + std::string(what_this) + ", " + show(o) + " in " + std::string(what_other);
    for (const auto& [k, v] : other.fields)
        if (!get(k)) return k + ": none in " + std::string(what_this) + ", '" + v + "' in " + std::string(what_other);
    return {};
}

const std::string& ArchiveSnapshot::section(std::string_view name) const {
    for (const auto& [n, data] : sections)
        if (n == name) return data;
    throw ArchiveError("the snapshot at step " + std::to_string(step) + " has no section '" + std::string(name) + "'");
}

// ---- reading ------------------------------------------------------------------------------

ArchiveContents read_archive(const std::string& path) {
    Fd fd(open_for_reading(path));
    const std::uint64_t size = file_size(fd.fd, path);
    ArchiveContents c;
    std::uint64_t at = 0;
    while (at < size) {
        // a head that does not fit, or nothing but zeros to the end: the last record, cut short
        if (size - at < kRecordHead + kRecordTail || zeros_to_end(fd.fd, at, size, path)) {
            if (at == 0) throw ArchiveError(path + ": not a phynjo archive (too short for a header)", 0);
            c.torn_at = at;
            break;
        }
        const auto head = read_head(fd.fd, at, path);
        if (!head) {
            if (at == 0) throw ArchiveError(path + ": not a phynjo archive", 0);
            throw ArchiveError(where(path, at) + " is damaged: its head's checksum fails", static_cast<std::int64_t>(at));
        }
        if (head->length > size - at - kRecordHead - kRecordTail) { // whole in its head, cut short after it
            if (at == 0) throw ArchiveError(path + ": its header record is cut short", 0);
            c.torn_at = at;
            break;
        }
        if ((at == 0) != (head->kind == kHeaderKind) || (at != 0 && head->kind != kSnapshotKind))
            throw ArchiveError(at == 0 ? path + ": not a phynjo archive (it does not begin with a header)"
                                       : where(path, at) + " is of an unknown kind " + std::to_string(head->kind),
                               static_cast<std::int64_t>(at));
        const std::string payload = read_payload(fd.fd, at, *head, path);
        if (at == 0) {
            c.header = parse_header(payload, path);
        } else {
            ArchiveReader r(payload, where(path, at));
            ArchiveIndexEntry e;
            e.offset = at;
            e.step = r.u64();
            e.time = r.f64();
            c.snapshots.push_back(e);
        }
        at += kRecordHead + head->length + kRecordTail;
        c.valid_end = at;
    }
    if (size == 0) throw ArchiveError(path + ": empty, not a phynjo archive", 0);
    return c;
}

ArchiveSnapshot read_snapshot(const std::string& path, std::uint64_t offset) {
    Fd fd(open_for_reading(path));
    const std::uint64_t size = file_size(fd.fd, path);
    if (offset == 0 || offset + kRecordHead + kRecordTail > size)
        throw ArchiveError(path + ": no snapshot at byte " + std::to_string(offset), static_cast<std::int64_t>(offset));
    const auto head = read_head(fd.fd, offset, path);
    if (!head || head->kind != kSnapshotKind || head->length > size - offset - kRecordHead - kRecordTail)
        throw ArchiveError(path + ": no snapshot at byte " + std::to_string(offset), static_cast<std::int64_t>(offset));
    const std::string payload = read_payload(fd.fd, offset, *head, path);
    ArchiveReader r(payload, where(path, offset));
    ArchiveSnapshot s;
    s.step = r.u64();
    s.time = r.f64();
    const std::uint64_t n = r.u64();
    for (std::uint64_t i = 0; i < n; ++i) {
        std::string name = r.str();
        std::string data = r.str();
        s.sections.emplace_back(std::move(name), std::move(data));
    }
    r.finish();
    return s;
}

std::optional<ArchiveIndexEntry> snapshot_before(const ArchiveContents& contents, double t) {
    if (contents.snapshots.empty()) return std::nullopt;
    const auto after = std::upper_bound(contents.snapshots.begin(), contents.snapshots.end(), t,
                                        [](double x, const ArchiveIndexEntry& e) { return x < e.time; });
    return after == contents.snapshots.begin() ? contents.snapshots.front() : *std::prev(after);
}

// ---- writing ------------------------------------------------------------------------------

namespace {
/// One writer at a time: a second process continuing the same archive (a run resumed while
/// the first still runs) would interleave its records with the first's. The lock goes with
/// the process, however it ends.
void lock(int fd, const std::string& path) {
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno == EWOULDBLOCK) throw ArchiveError(path + " is being written by another process (a run still going)");
        throw ArchiveError(system_error("cannot lock the archive " + path));
    }
}
} // namespace

ArchiveWriter::ArchiveWriter(std::string path, int fd, std::uint64_t size, bool sync)
    : path_(std::move(path)), fd_(fd), size_(size), sync_(sync) {}

ArchiveWriter::ArchiveWriter(ArchiveWriter&& o) noexcept
    : path_(std::move(o.path_)), fd_(std::exchange(o.fd_, -1)), size_(o.size_), sync_(o.sync_) {}

ArchiveWriter& ArchiveWriter::operator=(ArchiveWriter&& o) noexcept {
    if (this != &o) {
        if (fd_ >= 0) ::close(fd_);
        path_ = std::move(o.path_);
        fd_ = std::exchange(o.fd_, -1);
        size_ = o.size_;
        sync_ = o.sync_;
    }
    return *this;
}

ArchiveWriter::~ArchiveWriter() {
    if (fd_ >= 0) ::close(fd_);
}

ArchiveWriter ArchiveWriter::create(const std::string& path, const ArchiveHeader& header, bool sync) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) {
        if (errno == EEXIST) throw ArchiveError(path + " exists: an archive is continued, never overwritten");
        throw ArchiveError(system_error("cannot create the archive " + path));
    }
    ArchiveWriter w(path, fd, 0, sync);
    lock(fd, path);
    w.append(kHeaderKind, header_payload(header));
    if (sync) sync_folder(path);
    return w;
}

ArchiveWriter ArchiveWriter::resume(const std::string& path, const ArchiveContents& contents, const ArchiveHeader& header,
                                    bool sync) {
    if (const std::string d = contents.header.difference(header); !d.empty())
        throw ArchiveError(path + " is the archive of another run: " + d);
    Fd fd(::open(path.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC));
    if (fd.fd < 0) throw ArchiveError(system_error("cannot open the archive " + path + " to continue it"));
    lock(fd.fd, path);
    const std::uint64_t size = file_size(fd.fd, path);
    if (size < contents.valid_end) throw ArchiveError(path + " is shorter than when it was read");
    if (size > contents.valid_end) { // the record a killed run was writing: cut off, then appended after
        if (::ftruncate(fd.fd, static_cast<off_t>(contents.valid_end)) != 0)
            throw ArchiveError(system_error(path + ": cannot cut off the record cut short at byte " + std::to_string(contents.valid_end)));
        if (sync && ::fdatasync(fd.fd) != 0) throw ArchiveError(system_error(path + ": cannot sync"));
    }
    return ArchiveWriter(path, fd.release(), contents.valid_end, sync);
}

void ArchiveWriter::write(const ArchiveSnapshot& snapshot) { append(kSnapshotKind, snapshot_payload(snapshot)); }

void ArchiveWriter::append(std::uint32_t kind, const std::string& payload) {
    if (fd_ < 0) throw ArchiveError(path_ + ": the archive is closed");
    std::string record;
    record.reserve(kRecordHead + payload.size() + kRecordTail);
    record.append(kMagic, 4);
    put_u32(record, kind);
    put_u64(record, payload.size());
    put_u32(record, crc32(record.data(), 16));
    record += payload;
    put_u32(record, crc32(payload.data(), payload.size()));
    const char* p = record.data();
    std::size_t left = record.size();
    while (left > 0) {
        const ssize_t n = ::write(fd_, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const std::string message =
                system_error(path_ + ": cannot write the record at byte " + std::to_string(size_) + " (" +
                             std::to_string(record.size()) + " bytes)");
            (void)::ftruncate(fd_, static_cast<off_t>(size_)); // (best effort: a reader ignores a record cut short anyway)
            throw ArchiveError(message, static_cast<std::int64_t>(size_));
        }
        p += n;
        left -= static_cast<std::size_t>(n);
    }
    if (sync_ && ::fdatasync(fd_) != 0)
        throw ArchiveError(system_error(path_ + ": cannot sync the record at byte " + std::to_string(size_)),
                           static_cast<std::int64_t>(size_));
    size_ += record.size();
}

// ---- bytes --------------------------------------------------------------------------------

ArchiveBytes& ArchiveBytes::u64(std::uint64_t x) {
    put_u64(bytes_, x);
    return *this;
}
ArchiveBytes& ArchiveBytes::f64(double x) { return u64(std::bit_cast<std::uint64_t>(x)); }
ArchiveBytes& ArchiveBytes::f64s(const double* x, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) f64(x[i]);
    return *this;
}
ArchiveBytes& ArchiveBytes::str(std::string_view s) {
    u64(s.size());
    bytes_.append(s);
    return *this;
}

void ArchiveReader::need(std::size_t n) const {
    if (bytes_.size() - at_ < n)
        throw ArchiveError(std::string(what_) + ": ends early (" + std::to_string(n) + " more bytes wanted at " +
                           std::to_string(at_) + " of " + std::to_string(bytes_.size()) + ")");
}
std::uint64_t ArchiveReader::u64() {
    need(8);
    const std::uint64_t x = get_u64(reinterpret_cast<const unsigned char*>(bytes_.data() + at_));
    at_ += 8;
    return x;
}
double ArchiveReader::f64() { return std::bit_cast<double>(u64()); }
void ArchiveReader::f64s(double* x, std::size_t n) {
    need(8 * n);
    for (std::size_t i = 0; i < n; ++i) x[i] = f64();
}
std::string ArchiveReader::str() {
    const std::uint64_t n = u64();
    if (n > bytes_.size() - at_)
        throw ArchiveError(std::string(what_) + ": ends early (a string of " + std::to_string(n) + " bytes at " +
                           std::to_string(at_) + " of " + std::to_string(bytes_.size()) + ")");
    std::string s(bytes_.substr(at_, static_cast<std::size_t>(n)));
    at_ += static_cast<std::size_t>(n);
    return s;
}
void ArchiveReader::finish() const {
    if (at_ != bytes_.size())
        throw ArchiveError(std::string(what_) + ": " + std::to_string(bytes_.size() - at_) + " bytes left unread");
}

// ---- worlds -------------------------------------------------------------------------------

void save_world(ArchiveBytes& out, const World& w) {
    out.u64(w.field_count()).u64(w.size()).f64(w.time).u64(w.tick);
    for (FieldId f = 0; f < w.field_count(); ++f) out.f64s(w.field(f).data(), w.size());
}

void restore_world(ArchiveReader& in, World& w) {
    const std::uint64_t fields = in.u64(), components = in.u64();
    if (fields != w.field_count() || components != w.size())
        throw ArchiveError("the snapshot's world has " + std::to_string(fields) + " fields of " + std::to_string(components) +
                           " components; this run's has " + std::to_string(w.field_count()) + " of " +
                           std::to_string(w.size()));
    w.time = in.f64();
    w.tick = in.u64();
    for (FieldId f = 0; f < w.field_count(); ++f) in.f64s(w.field(f).data(), w.size());
}

} // namespace phynjo::runtime
