// The Recorder (view/recorder.hpp): it never changes a run, keeps frames at the display rate,
// and writes into the page exactly what it read (the page decoded here by a decoder of our
// own: base64, the sections of docs/viewer.md), bodies in order, x y z in order, the last
// frame kept. The browser side of the same page: tests/viewer/test_viewer.py.
#include "phynjo/runtime/runtime.hpp"

#include "shapes.hpp"

#include <catch2/catch.hpp>

#include "scenes.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

using namespace phynjo::runtime;

namespace {

/// The text between `<script … id="ID">` and the next `</script>` of a page.
std::string script_text(const std::string& page, const std::string& id) {
    const std::size_t open = page.find("id=\"" + id + "\">");
    REQUIRE(open != std::string::npos);
    const std::size_t from = page.find('>', open) + 1, to = page.find("</script>", from);
    REQUIRE(to != std::string::npos);
    return page.substr(from, to - from);
}

/// RFC 4648 base64, written here independently of the recorder's encoder.
std::vector<unsigned char> base64_decode(const std::string& text) {
    std::vector<unsigned char> out;
    std::uint32_t acc = 0;
    int bits = 0;
    for (const char c : text) {
        int v;
        if (c >= 'A' && c <= 'Z') v = c - 'A';
        else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
        else if (c >= '0' && c <= '9') v = c - '0' + 52;
        else if (c == '+') v = 62;
        else if (c == '/') v = 63;
        else continue; // '=' and white space
        acc = (acc << 6) | static_cast<std::uint32_t>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<unsigned char>((acc >> bits) & 0xFF));
        }
    }
    return out;
}

long json_int(const std::string& meta, const std::string& key) {
    std::smatch m;
    REQUIRE(std::regex_search(meta, m, std::regex("\"" + key + "\":([0-9]+)")));
    return std::stol(m[1]);
}

/// The page's sections (docs/viewer.md, *The file*).
struct Decoded {
    std::string meta;
    std::vector<double> times;
    std::vector<std::vector<double>> series;
    std::vector<float> positions;
    std::vector<std::int16_t> orientations;
};

template <class T>
std::vector<T> take(const std::vector<unsigned char>& bytes, std::size_t& at, std::size_t n) {
    std::vector<T> v(n);
    REQUIRE(at + n * sizeof(T) <= bytes.size());
    if (n) std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
    at += n * sizeof(T);
    return v;
}

Decoded decode_page(const std::string& page, std::size_t n_series, std::size_t floats_per_frame, std::size_t quaternions) {
    Decoded d;
    d.meta = script_text(page, "phynjo-meta");
    const auto bytes = base64_decode(script_text(page, "phynjo-frames"));
    const auto frames = static_cast<std::size_t>(json_int(d.meta, "frames"));
    std::size_t at = 0;
    d.times = take<double>(bytes, at, frames);
    for (std::size_t s = 0; s < n_series; ++s) d.series.push_back(take<double>(bytes, at, frames));
    d.positions = take<float>(bytes, at, frames * floats_per_frame);
    d.orientations = take<std::int16_t>(bytes, at, frames * 4 * quaternions);
    CHECK(at == bytes.size());
    return d;
}

/// Three rigid spheres on known paths: body b at step k is at (k + b, 2k − b, 3k + 10b)·1e-3 m,
/// turned by k·0.01·(b + 1) rad about z.
World three_bodies() {
    Registry reg;
    for (const char* n : {"a", "b", "c"}) reg.add(n);
    return make_rigid_world(reg, std::vector<RigidBody>(3, RigidBody::solid_sphere(1, 0.1)));
}
void place(World& w, int k, double dt) {
    w.time = k * dt;
    for (Index b = 0; b < 3; ++b) {
        const double s = static_cast<double>(b);
        set_position(w, b, Eigen::Vector3d(k + s, 2.0 * k - s, 3.0 * k + 10 * s) * 1e-3);
        const double angle = k * 0.01 * (s + 1);
        set_orientation(w, b, Quaternion{std::cos(angle / 2), 0, 0, std::sin(angle / 2)});
    }
}

} // namespace

// Bugs caught: a recorder that writes to the world it reads (a cache field, the time), or
// whose reading changes an operation of the step: the pile's golden hash, and the same world,
// bit for bit, as the run without it.
TEST_CASE("recorder: recording a sphere pile changes no bit of the run (golden hash)", "[view][golden][determinism]") {
    auto pile = [] {
        return phynjo::test::sphere_grid({.nx = 5, .ny = 5, .nz = 5, .origin = {0.07, 0.1, 0.07},
                                          .spacing = {0.13, 0.13, 0.13}, .jitter = 0.01, .seed = 7, .spin = true});
    };
    auto run = [&](Recorder* rec) {
        World w = pile();
        const auto planes = phynjo::test::box_walls(0.65);
        Stepper s(rigid_contact_step(Force3D::gravity(9.81), all_bodies(w), planes,
                                     ContactMaterial{restitution_curve(0.5, 0.2), constant_curve(0.4)}, {}, w.layout_ptr()));
        if (rec) {
            rec->add_rigid_bodies(w, all_bodies(w));
            rec->add_planes(planes);
            rec->capture(w);
        }
        for (int k = 0; k < 240; ++k) {
            s.step(w, 1.0 / 240);
            if (rec) rec->capture(w);
        }
        if (rec) rec->capture_last(w);
        return w;
    };
    const World plain = run(nullptr);
    Recorder rec;
    const World recorded = run(&rec);
    CHECK(recorded == plain);
    CHECK(recorded.hash() == 0xc2f20ed851fc9538ull); // tests/runtime/test_golden.cpp's pile
    CHECK(rec.frame_count() == 61);                   // 1 s at 60 frames per second, both ends
    CHECK(rec.bodies().size() == 125);
}

// Bugs caught: frames at the wrong times (a frame per step, the interval accumulated and
// drifting, a frame missed when k·dt reaches j/fps only to rounding), the first or the last
// state not kept. The oracle: the first step whose time reaches each j/fps, found by brute force.
TEST_CASE("recorder: frames at the display rate, the first and the last state kept", "[view]") {
    for (const auto& [dt, fps, steps] : {std::tuple{1e-3, 60.0, 2500}, std::tuple{1.0 / 240, 60.0, 1000},
                                         std::tuple{0.01, 30.0, 333}, std::tuple{0.05, 60.0, 40}}) {
        INFO("dt " << dt << ", fps " << fps);
        World w = three_bodies();
        Recorder rec({.fps = fps});
        rec.add_rigid_bodies(w, all_bodies(w));
        std::vector<double> expected;
        for (int k = 0; k <= steps; ++k) {
            place(w, k, dt);
            rec.capture(w);
            // due: the step is the first whose time reaches a multiple of 1/fps not yet framed
            const double t = k * dt;
            if (expected.empty() || std::floor(t * fps + 1e-6) > std::floor(expected.back() * fps + 1e-6)) expected.push_back(t);
        }
        rec.capture_last(w);
        if (expected.back() != steps * dt) expected.push_back(steps * dt);
        const auto times = rec.times();
        CHECK(std::vector<double>(times.begin(), times.end()) == expected);
    }
}

// Bugs caught: the page's frames not what was read — two bodies swapped, y written for z, a
// quaternion's components out of order, the last frame dropped, series shifted — decoded
// from the page with a decoder of our own.
TEST_CASE("recorder: the page holds every frame as read, bodies and axes in order", "[view]") {
    const double dt = 1.0 / 60;
    World w = three_bodies();
    Recorder rec({.fps = 60, .title = "three <bodies> & a title"});
    rec.add_rigid_bodies(w, all_bodies(w));
    rec.add_series({"k", "", "steps"}, [dt](const World& now) { return now.time / dt; });
    for (int k = 0; k <= 100; ++k) {
        place(w, k, dt);
        rec.capture(w);
    }
    place(w, 100, dt); // the last state again: not a second frame
    rec.capture_last(w);
    REQUIRE(rec.frame_count() == 101);
    const std::string page = rec.html();
    const Decoded d = decode_page(page, 2, 9, 3);
    CHECK(d.meta.find("\"title\":\"three \\u003cbodies\\u003e \\u0026 a title\"") != std::string::npos);
    CHECK(page.find("<title>three &lt;bodies> &amp; a title</title>") != std::string::npos);
    CHECK(std::regex_search(d.meta, std::regex(R"("bodies":\[\{"name":"a".*"name":"b".*"name":"c")")));
    for (int k = 0; k <= 100; ++k) {
        INFO("frame " << k);
        CHECK(d.times[static_cast<std::size_t>(k)] == k * dt);
        CHECK(d.series[1][static_cast<std::size_t>(k)] == (k * dt) / dt);
        for (int b = 0; b < 3; ++b) {
            const std::size_t at = static_cast<std::size_t>(9 * k + 3 * b);
            CHECK(d.positions[at] == static_cast<float>((k + b) * 1e-3));
            CHECK(d.positions[at + 1] == static_cast<float>((2.0 * k - b) * 1e-3));
            CHECK(d.positions[at + 2] == static_cast<float>((3.0 * k + 10 * b) * 1e-3));
            const double angle = k * 0.01 * (b + 1);
            const std::size_t q = static_cast<std::size_t>(4 * (3 * k + b));
            CHECK(std::abs(d.orientations[q] / 32767.0 - std::cos(angle / 2)) < 2e-5);
            CHECK(d.orientations[q + 1] == 0);
            CHECK(d.orientations[q + 2] == 0);
            CHECK(std::abs(d.orientations[q + 3] / 32767.0 - std::sin(angle / 2)) < 2e-5);
        }
    }
}

// Bugs caught: a generated model's shapes read from the wrong q, spheres and segments out of
// file order or with y and z swapped, a box's quaternion written among the positions or its
// half extents lost; the coordinates, E − E(0) and the series' order.
// The oracle: shapes.lag's kinematics (tests/codegen/test_shapes.cpp's, by hand).
TEST_CASE("recorder: a generated model's shapes and series, against its kinematics by hand", "[view]") {
    const shapes::Parameters P;
    const LagrangianSystem sys = shapes::system(P);
    World w = shapes::make_world(P);
    Recorder rec({.fps = 10});
    rec.add_model(sys);
    Stepper stepper(shapes::workflow(P, w));
    rec.capture(w);
    for (int k = 0; k < 200; ++k) {
        stepper.step(w, 0.005);
        rec.capture(w);
    }
    rec.capture_last(w);
    REQUIRE(rec.bodies().size() == 11);
    CHECK(rec.bodies()[1].kind == ViewBody::Kind::rod);
    CHECK(rec.bodies()[1].radius == 0); // a segment: the page's thin rod
    CHECK(rec.bodies()[2].radius == 3.0 / 40);
    CHECK(rec.bodies()[6].kind == ViewBody::Kind::rod); // a capsule: a rod of its radius
    CHECK(rec.bodies()[6].radius == 3.0 / 80);
    CHECK(rec.bodies()[7].radius == 1.0 / 25);
    CHECK(rec.bodies()[8].kind == ViewBody::Kind::box); // lid: oriented, its half extents
    CHECK(rec.bodies()[8].oriented);
    CHECK(rec.bodies()[8].half_extents == std::array<double, 3>{0.05, 0.025, 0.125});
    CHECK(rec.bodies()[10].half_extents == std::array<double, 3>{0.25, 0.25, 0.125});
    const std::size_t n_series = rec.series().size();
    REQUIRE(n_series == 5); // th1, th2, th1', th2', E − E(0)
    const Decoded d = decode_page(rec.html(), n_series, 45, 3);
    REQUIRE(d.times.size() == 11);
    CHECK(d.times.back() == w.time);
    const double e0 = sys.energy(0, std::vector<double>{0.3, -0.2}, std::vector<double>{0, 0});
    for (std::size_t f = 0; f < d.times.size(); ++f) {
        const double th1 = d.series[0][f], th2 = d.series[1][f];
        const double x1 = P.l1 * std::sin(th1), y1 = -P.l1 * std::cos(th1);
        const double x2 = x1 + P.l2 * std::sin(th2) * std::cos(th1), y2 = y1 + P.l2 * std::sin(th2) * std::sin(th1),
                     z2 = -P.l2 * std::cos(th2);
        const std::vector<double> by_hand{x1, y1, 0, 0, 0, 0, x1, y1, 0, x2, y2, z2, x1, y1, 0, x2, y2, z2,
                                          1, -2, 0, P.h, P.a * std::sin(P.w * d.times[f]), 0,
                                          0, 0, 0, x1, y1, 0, x1, y1, 0, x2, y2, z2,
                                          (x1 + x2) / 2, (y1 + y2) / 2, z2 / 2, x1 / 2, y1 / 2, 0, -1, -2, 0};
        for (std::size_t i = 0; i < 45; ++i) CHECK(d.positions[45 * f + i] == Approx(by_hand[i]).margin(1e-7));
        // lid: q_z(th1) ⊗ q_y(th2) = (c1 c2, −s1 s2, c1 s2, s1 c2) of the half angles; crate: 1
        const double c1 = std::cos(th1 / 2), s1 = std::sin(th1 / 2), c2 = std::cos(th2 / 2), s2 = std::sin(th2 / 2);
        const std::array<double, 4> lid{c1 * c2, -s1 * s2, c1 * s2, s1 * c2}, crate{1, 0, 0, 0};
        for (std::size_t i = 0; i < 4; ++i) {
            CHECK(std::abs(d.orientations[12 * f + i] / 32767.0 - lid[i]) < 2e-5);
            CHECK(std::abs(d.orientations[12 * f + 8 + i] / 32767.0 - crate[i]) < 2e-5);
        }
        const double e = sys.energy(d.times[f], std::vector<double>{th1, th2}, std::vector<double>{d.series[2][f], d.series[3][f]});
        CHECK(d.series[4][f] == e - e0);
    }
}

// Bugs caught: a page past the size a browser opens (a long run recorded whole), or thinning
// that loses the first frame or leaves the interval as it was.
TEST_CASE("recorder: a long run is thinned under max_bytes, with a warning on the page", "[view]") {
    World w = three_bodies();
    Recorder rec({.fps = 1000, .max_bytes = 64 * 1024});
    rec.add_rigid_bodies(w, all_bodies(w));
    for (int k = 0; k <= 20000; ++k) {
        place(w, k, 1e-3);
        rec.capture(w);
    }
    rec.capture_last(w);
    CHECK(rec.frame_bytes() <= 64 * 1024 + rec.frame_bytes() / rec.frame_count());
    CHECK(rec.frame_count() > 400);
    CHECK(rec.times().front() == 0);
    CHECK(rec.times().back() == 20000 * 1e-3);
    const std::string page = rec.html();
    CHECK(page.find("the run is longer than a page carries") != std::string::npos);
}

// Bugs caught: API misuse accepted silently (a body declared after frames exist, which would
// misalign every frame; a non-positive rate; an unwritable path; three.js missing) instead of
// a typed error naming what is wrong.
TEST_CASE("recorder: misuse is a typed error naming what is wrong", "[view][errors]") {
    CHECK_THROWS_AS(Recorder({.fps = 0}), std::invalid_argument);
    CHECK_THROWS_AS(Recorder({.fps = std::nan("")}), std::invalid_argument);
    World w = three_bodies();
    Recorder rec;
    rec.add_rigid_bodies(w, all_bodies(w));
    rec.capture(w);
    CHECK_THROWS_AS(rec.add_rigid_bodies(w, all_bodies(w)), std::logic_error);
    CHECK_THROWS_AS(rec.add_series({"x", "", ""}, nullptr), std::logic_error);
    CHECK_THROWS_WITH(rec.write_html("/nonexistent-folder/run.html"), Catch::Contains("/nonexistent-folder/run.html"));
    CHECK_FALSE(can_write("/nonexistent-folder/run.html"));
    CHECK_FALSE(can_write(std::filesystem::temp_directory_path().string()));
    ::setenv("PHYNJO_THREE_DIR", "/nonexistent-three", 1);
    CHECK_THROWS_AS(rec.html(), ViewerError);
    CHECK_THROWS_WITH(check_three_js(), Catch::Contains("libjs-three") && Catch::Contains("/nonexistent-three"));
    ::unsetenv("PHYNJO_THREE_DIR");
    CHECK_NOTHROW(check_three_js());
}
