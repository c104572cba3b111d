// The viewer (docs/viewer.md) on the sphere pile of bench_pile.cpp, in one run:
//   ratio html_record_overhead_pile     the 1,000-sphere pile's run time without a recorder over
//                                       with one at the default 60 frames per simulated second
//                                       (best of seven alternating runs each, either first;
//                                       ≥ 0.95 wanted; the captures' own time is printed);
//   ratio html_size_meshcat_pile        the same frames of that pile in MeshCat's recorded-
//                                       animation encoding (msgpack of per-frame position and
//                                       quaternion keys, base64, as a static MeshCat page holds
//                                       them) over ours (bench/viewer_bench.py writes it);
//   ratio html_draw_instanced_pile_8000 the frame draw time of the 8,000-sphere pile drawn as
//                                       one three.js mesh per sphere over ours (one instanced
//                                       mesh), both in headless Chromium (bench/viewer_bench.py).
// Usage: bench_viewer [OUT_DIR]   (default: a temporary folder; the pages stay there)
#include "phynjo/runtime/runtime.hpp"
#include "pile_scene.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

using namespace phynjo::runtime;

namespace {

using Clock = std::chrono::steady_clock;

double g_capture_seconds = 0; // of the last recorded run: the captures alone

/// The pile stepped for kT seconds, recorded into `page` when given: seconds of stepping (and
/// recording), and the world's hash (the same with and without: recording is read-only).
std::pair<double, std::uint64_t> run(const Pile& s, Recorder* page) {
    Registry reg;
    for (std::size_t i = 0; i < s.start.size(); ++i) reg.add("s" + std::to_string(i));
    std::vector<RigidInit> init(s.start.size());
    for (std::size_t i = 0; i < s.start.size(); ++i) init[i].position = s.start[i];
    World w = make_rigid_world(reg, std::vector<RigidBody>(s.start.size(), RigidBody::solid_sphere(kSphereMass, kR)), init,
                               contact_cache_fields());
    Stepper st(rigid_contact_step(Force3D::gravity(kG), all_bodies(w), s.planes,
                                  ContactMaterial{restitution_curve(kE, kBounceVel), constant_curve(kMu)}, {}, w.layout_ptr()));
    const int steps = static_cast<int>(std::lround(kT / kDt));
    const auto t0 = Clock::now();
    if (page) {
        page->add_rigid_bodies(w, all_bodies(w));
        page->add_planes(s.planes);
        page->capture(w);
    }
    double capturing = 0;
    for (int k = 0; k < steps; ++k) {
        st.step(w, kDt);
        if (page) {
            const auto c0 = Clock::now();
            page->capture(w);
            capturing += std::chrono::duration<double>(Clock::now() - c0).count();
        }
    }
    if (page) g_capture_seconds = capturing;
    if (page) page->capture_last(w);
    return {std::chrono::duration<double>(Clock::now() - t0).count(), w.hash()};
}

} // namespace

int main(int argc, char** argv) {
    const std::filesystem::path out =
        argc > 1 ? std::filesystem::path(argv[1]) : std::filesystem::temp_directory_path() / "phynjo-bench-viewer";
    std::filesystem::create_directories(out);
    std::printf("viewer: the sphere pile of bench_pile (dt = 1/240 s, %.0f s), recorded at 60 frames per simulated second\n", kT);

    const Pile pile = make_pile(1000);
    double plain = 1e300, recorded = 1e300;
    std::uint64_t h_plain = 0, h_recorded = 0;
    std::optional<Recorder> kept;
    double capture = 1e300;
    for (int rep = 0; rep < 7; ++rep) { // alternating, and which goes first too
        Recorder page({.title = "bench: 1,000-sphere pile"});
        std::pair<double, std::uint64_t> with, without;
        if (rep % 2 == 0) without = run(pile, nullptr), with = run(pile, &page);
        else with = run(pile, &page), without = run(pile, nullptr);
        const auto [a, ha] = without;
        const auto [b, hb] = with;
        plain = std::min(plain, a), recorded = std::min(recorded, b), capture = std::min(capture, g_capture_seconds);
        h_plain = ha, h_recorded = hb;
        kept.emplace(std::move(page));
    }
    std::printf("  pile 1000: %.3f s without a recorder, %.3f s with one (best of 7 alternating runs each; the captures"
                " themselves %.1f ms); %zu frames, %.2f MB of frames; the same world hash: %s\n",
                plain, recorded, 1e3 * capture, kept->frame_count(), kept->frame_bytes() / 1e6, h_plain == h_recorded ? "yes" : "NO");
    std::printf("ratio html_record_overhead_pile = %.3f\n", plain / recorded);
    const auto page_1000 = out / "pile_1000.html";
    kept->write_html(page_1000.string());

    Recorder big({.title = "bench: 8,000-sphere pile"});
    run(make_pile(8000), &big);
    const auto page_8000 = out / "pile_8000.html";
    big.write_html(page_8000.string());
    std::printf("  wrote %s (%.1f MB) and %s (%.1f MB)\n", page_1000.c_str(), std::filesystem::file_size(page_1000) / 1e6,
                page_8000.c_str(), std::filesystem::file_size(page_8000) / 1e6);
    std::fflush(stdout);
    const std::string cmd = std::string("'") + PHYNJO_BENCH_PYTHON3 + "' '" + PHYNJO_BENCH_DIR + "/viewer_bench.py' '" + page_1000.string() + "' '" +
                            page_8000.string() + "'";
    return std::system(cmd.c_str()) == 0 ? 0 : 1;
}
