// The archive's file (runtime/core/archive.hpp, docs/archive.md): records read back as written,
// checked against an independent reading of the documented layout (a bitwise CRC-32 beside
// Boost's table-driven one); a record cut short anywhere is ignored and cut off when the run
// continues; every flipped bit anywhere is an error naming the record; another run's or another
// format's archive is refused saying which; a write that fails is an error at that write.
#include "phynjo/runtime/core/archive.hpp"
#include "phynjo/runtime/integrators/nbody_leapfrog.hpp"
#include "phynjo/runtime/particles/particles3d.hpp"
#include "phynjo/runtime/simulate/archived_run.hpp"

#include <catch2/catch.hpp>

#include <cinttypes>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/resource.h>
#include <vector>

using namespace phynjo::runtime;
namespace fs = std::filesystem;

namespace {

/// CRC-32 (IEEE, reflected, as zlib) bit by bit: the oracle.
std::uint32_t crc32_bitwise(const std::string& s) {
    std::uint32_t c = 0xFFFFFFFFu;
    for (const unsigned char b : s) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}

std::uint64_t le(const std::string& s, std::size_t at, int bytes) {
    std::uint64_t x = 0;
    for (int i = bytes - 1; i >= 0; --i) x = (x << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
    return x;
}

std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}
void spit(const fs::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << bytes;
}

/// A fresh folder per test.
struct Folder {
    fs::path dir;
    explicit Folder(const char* name) : dir(fs::temp_directory_path() / ("phynjo-test-archive-" + std::string(name))) {
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    ~Folder() { fs::remove_all(dir); }
};

ArchiveHeader header_of(const std::string& model) {
    ArchiveHeader h;
    h.add("model", model).add("integrator", "rk4").add("dt", "0.001").add("param.m", "1.5");
    return h;
}

ArchiveSnapshot snapshot(std::uint64_t step) {
    ArchiveSnapshot s;
    s.step = step;
    s.time = 0.001 * static_cast<double>(step);
    const double q[3] = {0.1 * static_cast<double>(step), -2.5, 1e-300};
    s.sections.emplace_back("world", ArchiveBytes().f64s(q, 3).take());
    s.sections.emplace_back("integrator", std::string(step % 3, 'x'));
    return s;
}

/// An archive of `n` snapshots (steps 0, 10, 20 …): its path and the offsets of its records.
std::pair<fs::path, std::vector<std::uint64_t>> make_archive(const Folder& f, std::size_t n, const std::string& model = "pendulum") {
    const fs::path p = f.dir / "run.pjar";
    auto w = ArchiveWriter::create(p.string(), header_of(model), false);
    std::vector<std::uint64_t> offsets{0};
    for (std::size_t k = 0; k < n; ++k) {
        offsets.push_back(w.size());
        w.write(snapshot(10 * k));
    }
    return {p, offsets};
}

} // namespace

TEST_CASE("archive: records read back as written, in the documented layout") {
    // Catches: a field, section or step lost or reordered; a layout or checksum other than
    // docs/archive.md's (another program could not read it).
    Folder f("layout");
    const auto [p, offsets] = make_archive(f, 4);
    const ArchiveContents c = read_archive(p.string());
    CHECK(c.header.fields == header_of("pendulum").fields);
    CHECK_FALSE(c.torn_at);
    CHECK(c.valid_end == fs::file_size(p));
    REQUIRE(c.snapshots.size() == 4);
    for (std::size_t k = 0; k < 4; ++k) {
        CHECK(c.snapshots[k].offset == offsets[k + 1]);
        CHECK(c.snapshots[k].step == 10 * k);
        CHECK(c.snapshots[k].time == 0.001 * static_cast<double>(10 * k));
        const ArchiveSnapshot s = read_snapshot(p.string(), c.snapshots[k].offset);
        const ArchiveSnapshot want = snapshot(10 * k);
        CHECK(s.step == want.step);
        CHECK(s.time == want.time);
        CHECK(s.sections == want.sections);
        ArchiveReader r(s.section("world"), "world");
        double q[3];
        r.f64s(q, 3);
        r.finish();
        CHECK((q[0] == 0.1 * static_cast<double>(10 * k) && q[1] == -2.5 && q[2] == 1e-300));
        CHECK_THROWS_AS(s.section("events"), ArchiveError);
    }
    // the oracle's reading: PJAR, kind, length, CRC of the head, payload, CRC of the payload
    const std::string bytes = slurp(p);
    std::size_t at = 0, records = 0;
    while (at < bytes.size()) {
        REQUIRE(bytes.substr(at, 4) == "PJAR");
        CHECK(le(bytes, at + 4, 4) == (records == 0 ? 1u : 2u));
        const std::size_t len = static_cast<std::size_t>(le(bytes, at + 8, 8));
        CHECK(le(bytes, at + 16, 4) == crc32_bitwise(bytes.substr(at, 16)));
        CHECK(le(bytes, at + 20 + len, 4) == crc32_bitwise(bytes.substr(at + 20, len)));
        if (records == 0) CHECK(bytes.substr(at + 20, len) == "format 1\nmodel pendulum\nintegrator rk4\ndt 0.001\nparam.m 1.5\n");
        at += 24 + len;
        ++records;
    }
    CHECK(records == 5);
    CHECK(crc32_bitwise("123456789") == 0xCBF43926u); // the oracle is CRC-32's check value
}

TEST_CASE("archive: a last record cut short anywhere is ignored, and cut off when the run continues") {
    // Catches: a record cut short by a kill read as damage (the run could not resume), or kept
    // when the run continues (new records behind garbage); zeros a crash left at the end taken
    // for a record.
    Folder f("torn");
    const auto [p, offsets] = make_archive(f, 3);
    const std::string whole = slurp(p);
    const std::uint64_t last = offsets.back();
    for (std::uint64_t cut = last + 1; cut < whole.size(); ++cut) {
        spit(p, whole.substr(0, cut));
        const ArchiveContents c = read_archive(p.string());
        REQUIRE(c.torn_at == last);
        CHECK(c.valid_end == last);
        CHECK(c.snapshots.size() == 2);
    }
    spit(p, whole + std::string(4096, '\0')); // space a crash allocated and never wrote
    CHECK(read_archive(p.string()).torn_at == whole.size());
    spit(p, whole.substr(0, last + 7));
    const ArchiveContents c = read_archive(p.string());
    {
        auto w = ArchiveWriter::resume(p.string(), c, header_of("pendulum"), false);
        w.write(snapshot(99));
    }
    const ArchiveContents after = read_archive(p.string());
    CHECK_FALSE(after.torn_at);
    REQUIRE(after.snapshots.size() == 3);
    CHECK(after.snapshots[2].step == 99);
    CHECK(after.snapshots[2].offset == last);
    // a header cut short is no archive
    spit(p, whole.substr(0, offsets[1] - 3));
    CHECK_THROWS_WITH(read_archive(p.string()), Catch::Contains("header record is cut short"));
    spit(p, "");
    CHECK_THROWS_WITH(read_archive(p.string()), Catch::Contains("not a phynjo archive"));
}

TEST_CASE("archive: every flipped bit is an error naming its record") {
    // Catches: a checksum not checked (the head's or the payload's), a damaged length read as
    // a record cut short (silently dropping the snapshots after it).
    Folder f("flip");
    const auto [p, offsets] = make_archive(f, 3);
    const std::string whole = slurp(p);
    for (std::size_t i = 0; i < whole.size(); ++i) {
        std::string bad = whole;
        bad[i] = static_cast<char>(bad[i] ^ (1 << (i % 8)));
        spit(p, bad);
        std::uint64_t record = 0;
        for (const std::uint64_t o : offsets)
            if (o <= i) record = o;
        INFO("byte " << i << " of the record at " << record);
        try {
            (void)read_archive(p.string());
            FAIL("no error");
        } catch (const ArchiveError& e) {
            CHECK(e.offset() == static_cast<std::int64_t>(record));
            if (record > 0) CHECK_THAT(e.what(), Catch::Contains("the record at byte " + std::to_string(record)));
        }
    }
}

TEST_CASE("archive: another run's, another format's or no archive is refused, saying which") {
    // Catches: a run continued from an archive of another model or parameter set, or of a
    // format this phynjo does not read; an existing archive overwritten.
    Folder f("refuse");
    const auto [p, offsets] = make_archive(f, 2);
    const ArchiveContents c = read_archive(p.string());
    CHECK_THROWS_WITH(ArchiveWriter::resume(p.string(), c, header_of("cart"), false),
                      Catch::Contains("archive of another run: model: 'pendulum' in the archive, 'cart' in this run"));
    ArchiveHeader other = header_of("pendulum");
    other.fields[3].second = "2";
    CHECK_THROWS_WITH(ArchiveWriter::resume(p.string(), c, other, false),
                      Catch::Contains("param.m: '1.5' in the archive, '2' in this run"));
    ArchiveHeader more = header_of("pendulum");
    more.add("events", "armed");
    CHECK_THROWS_WITH(ArchiveWriter::resume(p.string(), c, more, false), Catch::Contains("events: none in the archive"));
    CHECK_THROWS_WITH(ArchiveWriter::create(p.string(), header_of("pendulum"), false), Catch::Contains("exists"));
    CHECK(fs::file_size(p) == c.valid_end);

    // format 2: a header record the oracle writes
    const std::string payload = "format 2\nmodel pendulum\n";
    std::string head = "PJAR";
    auto put = [](std::string& s, std::uint64_t x, int n) {
        for (int i = 0; i < n; ++i) s.push_back(static_cast<char>((x >> (8 * i)) & 0xFF));
    };
    put(head, 1, 4);
    put(head, payload.size(), 8);
    put(head, crc32_bitwise(head), 4);
    std::string record = head + payload;
    put(record, crc32_bitwise(payload), 4);
    spit(p, record);
    CHECK_THROWS_WITH(read_archive(p.string()), Catch::Contains("an archive of format 2; this phynjo reads format 1"));
    spit(p, "# t,q,qd\n0,1,2\n3,4,5\n7,8,9\n");
    CHECK_THROWS_WITH(read_archive(p.string()), Catch::Contains("not a phynjo archive"));
    CHECK_THROWS_WITH(read_archive((f.dir / "none.pjar").string()), Catch::Contains("cannot open the archive"));
    CHECK_THROWS_AS(ArchiveHeader().add("two words", "x"), std::invalid_argument);
    CHECK_THROWS_AS(ArchiveHeader().add("key", "two\nlines"), std::invalid_argument);
}

TEST_CASE("archive: a write that fails is an error at that write, the file still whole") {
    // Catches: a full disk ignored (a silently truncated archive), or a partial record left
    // where the next reader trips over it.
    Folder f("full");
    const fs::path p = f.dir / "run.pjar";
    auto w = ArchiveWriter::create(p.string(), header_of("pendulum"), true);
    w.write(snapshot(0));
    const std::uint64_t good = w.size();
    // the file-size limit as a full disk: the next record does not fit
    struct rlimit old {};
    REQUIRE(getrlimit(RLIMIT_FSIZE, &old) == 0);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    struct rlimit lim = old;
    lim.rlim_cur = good + 30;
    REQUIRE(setrlimit(RLIMIT_FSIZE, &lim) == 0);
    std::string message;
    std::int64_t offset = -2;
    try {
        w.write(snapshot(10));
    } catch (const ArchiveError& e) {
        message = e.what();
        offset = e.offset();
    }
    setrlimit(RLIMIT_FSIZE, &old);
    std::signal(SIGXFSZ, previous);
    CHECK_THAT(message, Catch::Contains("cannot write the record at byte " + std::to_string(good)));
    CHECK_THAT(message, Catch::Contains("File too large"));
    CHECK(offset == static_cast<std::int64_t>(good));
    const ArchiveContents c = read_archive(p.string());
    CHECK_FALSE(c.torn_at);
    CHECK(c.snapshots.size() == 1);
    CHECK(fs::file_size(p) == good);
}

TEST_CASE("archive: the snapshot before a time") {
    // Catches: --at T starting from a snapshot after T (the state could not be reached) or an
    // earlier one than the latest (slower than it need be).
    Folder f("before");
    const auto [p, offsets] = make_archive(f, 4); // t = 0, 0.01, 0.02, 0.03
    const ArchiveContents c = read_archive(p.string());
    CHECK(snapshot_before(c, 0.0)->step == 0);
    CHECK(snapshot_before(c, 0.015)->step == 10);
    CHECK(snapshot_before(c, 0.02)->step == 20);
    CHECK(snapshot_before(c, 5.0)->step == 30);
    CHECK(snapshot_before(c, -1.0)->step == 0);
    CHECK_FALSE(snapshot_before(ArchiveContents{}, 1.0));
    CHECK_THROWS_WITH(read_snapshot(p.string(), offsets[1] + 1), Catch::Contains("no snapshot at byte"));
}

TEST_CASE("archive: a world read back bit for bit, into a world of its shape only") {
    // Catches: a field or component left out of a snapshot's world, a value rounded on the
    // way (a decimal text, a float), the time or tick lost; a world of another shape filled.
    Registry r;
    for (const char* name : {"a", "b", "c"}) r.add(name);
    World w(std::make_shared<Layout>(r, std::vector<std::string>{"q", "v", "m"}));
    const double values[] = {0.1, -0.0, 1e-310, 6.02214076e23, -3.0, std::nextafter(1.0, 2.0), 2.5, 7.0, -1e-300};
    for (FieldId f = 0; f < 3; ++f)
        for (Index i = 0; i < 3; ++i) w.at(f, i) = values[3 * f + i];
    w.time = 12.345678901234567;
    w.tick = 987654321;
    ArchiveBytes out;
    save_world(out, w);
    const std::string bytes = out.take();
    REQUIRE(bytes.size() == 8 * (4 + 9));

    World back(w.layout_ptr());
    ArchiveReader in(bytes, "world");
    restore_world(in, back);
    in.finish();
    CHECK(back == w);
    CHECK(back.time == w.time);
    CHECK(back.tick == w.tick);
    CHECK(std::signbit(back.at(0, 1)));

    Registry two;
    two.add("a");
    two.add("b");
    World other(std::make_shared<Layout>(two, std::vector<std::string>{"q", "v", "m"}));
    ArchiveReader again(bytes, "world");
    CHECK_THROWS_WITH(restore_world(again, other), Catch::Contains("3 fields of 3 components") &&
                                                       Catch::Contains("this run's has 3 of 2"));
}

TEST_CASE("archive: one writer at a time") {
    // Catches: a run resumed while the first still writes the archive, the two interleaving
    // their records.
    Folder f("lock");
    const auto [p, offsets] = make_archive(f, 2);
    const ArchiveContents c = read_archive(p.string());
    {
        const auto first = ArchiveWriter::resume(p.string(), c, header_of("pendulum"), false);
        CHECK_THROWS_WITH(ArchiveWriter::resume(p.string(), c, header_of("pendulum"), false),
                          Catch::Contains("being written by another process"));
    }
    auto next = ArchiveWriter::resume(p.string(), read_archive(p.string()), header_of("pendulum"), false); // the first closed
    next.write(snapshot(20));
    CHECK(read_archive(p.string()).snapshots.size() == 3);
}

TEST_CASE("archive: a world's run continued from its snapshot is the run never stopped, its times t0 + k dt") {
    // Catches: a snapshot without the Stepper's clock (a continued run's times t_snap + j·dt,
    // which round otherwise than t0 + k·dt), the rows past the snapshot not cut back, a state
    // restored from a snapshot after the step asked for, a world of another shape continued.
    Folder f("world-run");
    const NBodyGravity g{1.0, 0.01};
    const double dt = 1e-3;
    auto make = [] {
        Registry r;
        for (const char* name : {"a", "b", "c"}) r.add(name);
        World w = make_particles(r);
        const double x[3][4] = {{0, 0, 0, 0.5}, {1, 0, 0, 0.3}, {0, 1.5, 0.2, 0.2}};
        for (Index i = 0; i < 3; ++i) {
            w.at(kX, i) = x[i][0], w.at(kY, i) = x[i][1], w.at(kZ, i) = x[i][2], w.at(kMass, i) = x[i][3];
            w.at(kVX, i) = 0.1 * static_cast<double>(i) - 0.1;
        }
        return w;
    };
    auto row = [](std::string& out, const World& w) {
        char line[64];
        std::snprintf(line, sizeof line, "%.17g,%016" PRIx64 "\n", w.time, w.hash());
        out += line;
    };
    ArchiveHeader header;
    header.add("program", "test").add("dt", "0.001");
    // the run never stopped
    World ref = make();
    Stepper ref_stepper(nbody_leapfrog(g, ref.layout_ptr()));
    std::string ref_rows;
    std::vector<double> times;
    for (int k = 0; k < 1000; ++k) {
        ref_stepper.step(ref, dt);
        row(ref_rows, ref);
        times.push_back(ref.time);
    }
    // the archived run, stopped after 700 steps (as a kill: the rows after the snapshot at 600 written)
    const std::string archive = (f.dir / "run.pjar").string(), rows = (f.dir / "rows.csv").string();
    {
        World w = make();
        Stepper stepper(nbody_leapfrog(g, w.layout_ptr()));
        ArchivedRun run = ArchivedRun::create(archive, header, w, ArchiveSpacing{300, 0}, {rows}, false);
        for (int k = 0; k < 700; ++k) {
            stepper.step(w, dt);
            std::string r;
            row(r, w);
            std::fputs(r.c_str(), run.output(0));
            run.stepped(w, stepper);
        }
        CHECK(run.snapshots() == 2);
    }
    {
        World w = make();
        Stepper stepper(nbody_leapfrog(g, w.layout_ptr()));
        ArchivedRun run = ArchivedRun::resume(archive, header, w, stepper, ArchiveSpacing{300, 0}, {rows}, false);
        REQUIRE(run.step() == 600);
        for (std::uint64_t k = run.step(); k < 1000; ++k) {
            stepper.step(w, dt);
            std::string r;
            row(r, w);
            std::fputs(r.c_str(), run.output(0));
            run.stepped(w, stepper);
        }
        run.finish(w, stepper);
        run.close();
        CHECK(w == ref);
        CHECK(w.time == ref.time);
    }
    CHECK(slurp(rows) == ref_rows);

    // the state at step 650: the snapshot at 600 (not 900) stepped on
    World w = make();
    Stepper stepper(nbody_leapfrog(g, w.layout_ptr()));
    REQUIRE(ArchivedRun::restore(archive, header, w, stepper, 650) == 600);
    World fresh_clock = w;
    for (int k = 600; k < 650; ++k) stepper.step(w, dt);
    CHECK(w.time == times[649]);
    // the clock matters: from the same world with a fresh clock, some time rounds otherwise
    Stepper fresh(nbody_leapfrog(g, fresh_clock.layout_ptr()));
    int differ = 0;
    for (int k = 600; k < 1000; ++k) {
        fresh.step(fresh_clock, dt);
        differ += fresh_clock.time != times[static_cast<std::size_t>(k)];
    }
    CHECK(differ > 0);

    // another world's shape is another run
    Registry two;
    two.add("a");
    two.add("b");
    World other = make_particles(two);
    Stepper other_stepper(nbody_leapfrog(g, other.layout_ptr()));
    CHECK_THROWS_WITH(ArchivedRun::restore(archive, header, other, other_stepper),
                      Catch::Contains("another run") && Catch::Contains("world.components"));
}

TEST_CASE("archive: the spacing of snapshots, from its text") {
    // Catches: "2s" read as 2 steps, a spacing of 0 or a negative one accepted.
    CHECK(ArchiveSpacing::parse("250")->steps == 250);
    CHECK(ArchiveSpacing::parse("2.5s")->steps == 0);
    CHECK(ArchiveSpacing::parse("2.5s")->seconds == 2.5);
    for (const char* bad : {"", "0", "-3", "0s", "-1s", "s", "1.5", "3x", "nans", "infs", "1e400s"})
        CHECK_FALSE(ArchiveSpacing::parse(bad));
}
