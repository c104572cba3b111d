// A long run of a world of the runtime kept in an archive (docs/archive.md, *Worlds of the
// runtime*): killed at any moment, it continues from its latest snapshot to the same bytes as
// the run never stopped; any instant of it is recovered bit for bit from the snapshot before.
// Three worlds:
//   pile    n³ spheres (r = 5 cm, 1 kg) dropped into a walled box, e = 0.5, μ = 0.5, the
//           contacts warm-started from the previous step (the cache fields of the world)
//   scene   a .lag double pendulum (examples/models/striker.lag) swinging into 400 spheres
//   nbody   n bodies of a cold cluster, G = 1, total mass 1, Plummer softening 0.01, leapfrog
// Each writes a row every --every steps: t, the energy (J), the world's hash (every field,
// bit for bit: World::hash), so two runs agree on their rows only if they agree on every bit.
#include "phynjo/runtime/runtime.hpp"
#include "phynjo/runtime/simulate/archived_run.hpp"
#include "striker.hpp"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

using namespace phynjo::runtime;

namespace {

const char* const kUsage =
    "usage: %s pile|scene|nbody [--n N] [--t-end T] [--every K] [--threads P] [-o FILE]\n"
    "          [--archive FILE [--archive-every K|Xs]] [--resume FILE] [--archive FILE --at T]\n"
    "  pile                   n^3 spheres dropped into a box (n = --n, default 10), dt = 1/240 s\n"
    "  scene                  a .lag double pendulum swinging into 400 spheres, dt = 1/240 s\n"
    "  nbody                  a cluster of --n bodies (default 512), G = 1, dt = 1e-3\n"
    "  --t-end T              s (default: 3 for pile and scene, 10 for nbody)\n"
    "  --every K              a row t,energy,hash every K steps (default 10) to -o (default stdout)\n"
    "  --full                 rows of the full state instead: t, then every body's position and\n"
    "                         velocity (and a rigid body's spin and orientation), %%.17g\n"
    "  --threads P            threads of the scene and the N-body sum (results do not depend on P)\n"
    "  --archive FILE         keep the run in an archive: a snapshot after every K-th step, or\n"
    "                         every X seconds of wall time (--archive-every; default 1s)\n"
    "  --resume FILE          continue the archived run (killed or finished) from its latest snapshot\n"
    "  --at T                 with --archive FILE: the row at time T, from the snapshot before it\n"
    "see docs/archive.md\n";

struct Usage {
    std::string message;
};

struct Options {
    std::string world, output, archive, resume, archive_every = "1s";
    long n = 0, every = 10;
    unsigned threads = 1;
    bool full = false;
    std::optional<double> t_end, at;
};

Options parse(int argc, char** argv) {
    Options o;
    auto value = [&](int& i) -> std::string {
        if (i + 1 >= argc) throw Usage{std::string(argv[i]) + " needs a value"};
        return argv[++i];
    };
    auto number = [&](int& i) {
        const std::string name = argv[i], v = value(i);
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !std::isfinite(x)) throw Usage{name + ": not a number: " + v};
        return x;
    };
    auto whole = [&](int& i) {
        const std::string name = argv[i];
        const double x = number(i);
        if (!(x >= 1) || x != std::floor(x) || x > 1e12) throw Usage{name + " must be a whole number ≥ 1"};
        return static_cast<long>(x);
    };
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--n") o.n = whole(i);
        else if (a == "--t-end") o.t_end = number(i);
        else if (a == "--every") o.every = whole(i);
        else if (a == "--full") o.full = true;
        else if (a == "--threads") o.threads = static_cast<unsigned>(whole(i));
        else if (a == "-o" || a == "--output") o.output = value(i);
        else if (a == "--archive") o.archive = value(i);
        else if (a == "--resume") o.resume = value(i);
        else if (a == "--archive-every") o.archive_every = value(i);
        else if (a == "--at") o.at = number(i);
        else if (!a.empty() && a[0] != '-' && o.world.empty()) o.world = a;
        else throw Usage{"unknown argument " + a};
    }
    if (o.world != "pile" && o.world != "scene" && o.world != "nbody") throw Usage{"the world is pile, scene or nbody"};
    if (o.world == "scene" && o.n > 0) throw Usage{"--n is the size of a pile or a cluster; the scene has one size"};
    if (o.t_end && !(*o.t_end > 0)) throw Usage{"--t-end must be positive"};
    if (o.at && !(*o.at >= 0)) throw Usage{"--at must not be negative"};
    if (o.at && o.archive.empty()) throw Usage{"--at T reads a run's archive: --archive FILE --at T"};
    if (!o.archive.empty() && !o.resume.empty()) throw Usage{"--archive starts an archive, --resume continues one: not both"};
    if (!o.archive.empty() && !o.at && std::filesystem::exists(o.archive))
        throw Usage{o.archive + " exists: an archive is continued (--resume), never overwritten"};
    if (!ArchiveSpacing::parse(o.archive_every)) throw Usage{"--archive-every is a step count K or seconds Xs (e.g. 2s)"};
    if (o.threads > 64) throw Usage{"--threads: at most 64"};
    return o;
}

/// A world, the step that advances it, its energy.
struct Model {
    double dt = 0, t_end = 0;
    long n = 0; // spheres along an edge (pile) or bodies (nbody)
    std::optional<Scene> scene; // for the scene
    std::optional<World> world;
    std::unique_ptr<Executor> executor;
    std::unique_ptr<Stepper> stepper;
    std::function<double(const World&)> energy;
};

std::vector<Eigen::Vector3d> lattice(int nx, int ny, int nz, double a, double r, double x0, double sx, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.45 * (a - 2 * r), 0.45 * (a - 2 * r));
    std::vector<Eigen::Vector3d> p;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            for (int k = 0; k < nz; ++k)
                p.emplace_back(x0 + sx * (i + 0.5) * a + jitter(rng), (j + 0.5) * a + jitter(rng), (k + 0.5) * a + jitter(rng));
    return p;
}

Model make(const Options& o) {
    Model m;
    m.executor = std::make_unique<Executor>(o.threads);
    Executor* ex = o.threads > 1 ? m.executor.get() : nullptr;
    const double r = 0.05, a = r * std::cbrt(16 * std::numbers::pi / 3);
    const ContactMaterial material{restitution_curve(0.5, 0.2), constant_curve(0.5)};
    if (o.world == "pile") {
        const int n = static_cast<int>(o.n > 0 ? o.n : 10);
        m.n = n;
        const double side = n * a;
        m.dt = 1.0 / 240;
        m.t_end = 3;
        Registry reg;
        std::vector<RigidInit> init;
        for (const Eigen::Vector3d& p : lattice(n, n, n, a, r, 0, 1, 20261123)) {
            reg.add("s" + std::to_string(init.size()));
            init.push_back(RigidInit{});
            init.back().position = p;
        }
        m.world.emplace(make_rigid_world(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_sphere(1, r)), init,
                                   contact_cache_fields()));
        const std::vector<Plane> planes{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -side},
                                        Plane{{0, 0, 1}, 0}, Plane{{0, 0, -1}, -side}};
        m.stepper = std::make_unique<Stepper>(
            rigid_contact_step(Force3D::gravity(9.81), all_bodies(*m.world), planes, material, {}, m.world->layout_ptr()), ex);
        m.energy = [](const World& w) { return rigid_kinetic_energy(w); };
    } else if (o.world == "scene") {
        const double length = 3, depth = 5 * a;
        m.dt = 1.0 / 240;
        m.t_end = 3;
        Registry reg;
        std::vector<RigidInit> init;
        for (const Eigen::Vector3d& p : lattice(10, 8, 5, a, r, length, -1, 20261202)) {
            reg.add("s" + std::to_string(init.size()));
            init.push_back(RigidInit{});
            init.back().position = p;
        }
        striker::Parameters P;
        P.m1 = 5, P.m2 = 20, P.l1 = 0.6, P.l2 = 0.6, P.px = 1.2, P.py = 1.35, P.pz = depth / 2;
        m.scene.emplace(make_scene(reg, std::vector<RigidBody>(init.size(), RigidBody::solid_sphere(1, r)), init,
                                   {ModelInstance{"striker", striker::system(P)}}, contact_cache_fields()));
        set_model_state(*m.scene, 0, std::vector<double>{-1.2, -1.2}, std::vector<double>{0, 0});
        const std::vector<Plane> walls{Plane::ground(), Plane{{1, 0, 0}, 0}, Plane{{-1, 0, 0}, -length},
                                       Plane{{0, 0, 1}, 0}, Plane{{0, 0, -1}, -depth}};
        m.stepper = std::make_unique<Stepper>(scene_step(*m.scene, Force3D::gravity(9.81), walls, material, {}), ex);
        m.world.emplace(m.scene->world);
        const Scene* scene = &*m.scene;
        m.energy = [scene](const World& w) {
            Scene s = *scene; // scene_energy reads the scene's world: this one
            s.world = w;
            return scene_energy(s);
        };
    } else {
        const long n = o.n > 0 ? o.n : 512;
        m.n = n;
        m.dt = 1e-3;
        m.t_end = 10;
        const NBodyGravity g{1.0, 0.01};
        const int partitions = 2; // the pair sum's split: fixed, so the bits do not depend on --threads
        Registry reg;
        for (long i = 0; i < n; ++i) reg.add("b" + std::to_string(i));
        m.world.emplace(make_particles(reg, partitions));
        World& w = *m.world;
        std::mt19937 rng(20261204);
        std::uniform_real_distribution<double> u(-1, 1);
        for (Index i = 0; i < w.size(); ++i) {
            double x, y, z;
            do {
                x = u(rng), y = u(rng), z = u(rng);
            } while (x * x + y * y + z * z > 1);
            w.at(kX, i) = x, w.at(kY, i) = y, w.at(kZ, i) = z;
            w.at(kVX, i) = 0.1 * u(rng), w.at(kVY, i) = 0.1 * u(rng), w.at(kVZ, i) = 0.1 * u(rng);
            w.at(kMass, i) = 1.0 / static_cast<double>(n);
        }
        m.stepper = std::make_unique<Stepper>(nbody_leapfrog(g, w.layout_ptr(), partitions), ex);
        m.energy = [g](const World& world) { return nbody_energy(world, g); };
    }
    if (o.t_end) m.t_end = *o.t_end;
    return m;
}

/// The state's fields in a --full row: x, y, z, vx, vy, vz (kX … kVZ of both kinds of world),
/// then a rigid body's wx, wy, wz, qw, qx, qy, qz.
std::vector<FieldId> state_fields(const World& w) {
    std::vector<FieldId> f{kX, kY, kZ, kVX, kVY, kVZ};
    if (w.layout().fields.size() > kQZ && w.layout().fields[kQZ] == "qz")
        for (FieldId k = kWX; k <= kQZ; ++k) f.push_back(k);
    return f;
}

bool full_rows = false;

void header_line(std::FILE* f, const World& w) {
    if (!full_rows) {
        std::fprintf(f, "t,energy,hash\n");
        return;
    }
    std::fprintf(f, "t");
    const std::vector<FieldId> fields = state_fields(w);
    for (Index i = 0; i < w.size(); ++i)
        for (FieldId k : fields) std::fprintf(f, ",%s%u", w.layout().fields[k].c_str(), static_cast<unsigned>(i));
    std::fprintf(f, "\n");
}

void row(std::FILE* f, const World& w, double energy) {
    if (!full_rows) {
        std::fprintf(f, "%.17g,%.17g,%016" PRIx64 "\n", w.time, energy, w.hash());
        return;
    }
    std::fprintf(f, "%.17g", w.time);
    const std::vector<FieldId> fields = state_fields(w);
    for (Index i = 0; i < w.size(); ++i)
        for (FieldId k : fields) std::fprintf(f, ",%.17g", w.at(k, i));
    std::fprintf(f, "\n");
}

/// Whole steps of dt in t (a ratio within 1e-9 of a whole number is that number).
std::uint64_t whole_steps(double t, double dt) {
    const double k = t / dt, near = std::round(k);
    return static_cast<std::uint64_t>(std::abs(k - near) <= 1e-9 * std::max(1.0, near) ? near : std::floor(k));
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    try {
        o = parse(argc, argv);
    } catch (const Usage& u) {
        if (argc == 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
            std::printf(kUsage, argv[0]);
            return 0;
        }
        std::fprintf(stderr, "%s: %s\n", argv[0], u.message.c_str());
        std::fprintf(stderr, kUsage, argv[0]);
        return 2;
    }
    Model m = make(o);
    World& w = *m.world;
    Stepper& stepper = *m.stepper;
    const double t_end = o.at ? *o.at : m.t_end;
    const std::uint64_t steps = whole_steps(t_end, m.dt);
    const double last = t_end - static_cast<double>(steps) * m.dt;
    // What identifies the run: the world, its size, dt, the rows' spacing (not the threads:
    // they change no bit, so a run may continue on another machine with other threads)
    ArchiveHeader header;
    header.add("program", "archived_world").add("world", o.world).add("n", std::to_string(m.n));
    char dt_text[32];
    std::snprintf(dt_text, sizeof dt_text, "%.17g", m.dt);
    header.add("dt", dt_text).add("every", std::to_string(o.every)).add("rows", o.full ? "full" : "hash");
    full_rows = o.full;
    try {
        const ArchiveSpacing spacing = *ArchiveSpacing::parse(o.archive_every);
        if (o.at) {
            // the state at T: the latest snapshot at or before T's last whole step, stepped on
            const std::uint64_t from = ArchivedRun::restore(o.archive, header, w, stepper, steps);
            std::fprintf(stderr, "%s: --at: continuing from the snapshot at step %" PRIu64 ", t = %.17g s\n", argv[0], from,
                         w.time);
            for (std::uint64_t k = from; k < steps; ++k) stepper.step(w, m.dt);
            if (last > 1e-9 * m.dt) stepper.step(w, last);
            std::FILE* f = o.output.empty() ? stdout : std::fopen(o.output.c_str(), "w");
            if (!f) throw ArchiveError("cannot write " + o.output);
            header_line(f, w);
            row(f, w, m.energy(w));
            if (f != stdout) std::fclose(f);
            return 0;
        }
        // rows go to -o; an archived run's rows must be a file (cut back to the snapshot's length)
        const bool archived = !o.archive.empty() || !o.resume.empty();
        if (archived && o.output.empty()) throw Usage{"an archived run writes its rows to a file: -o FILE"};
        std::optional<ArchivedRun> run;
        std::FILE* out = stdout;
        if (!o.resume.empty()) {
            run.emplace(ArchivedRun::resume(o.resume, header, w, stepper, spacing, {o.output}));
            std::fprintf(stderr, "%s: --resume: continuing from the snapshot at step %" PRIu64 ", t = %.17g s\n", argv[0],
                         run->step(), w.time);
        } else if (!o.archive.empty()) {
            run.emplace(ArchivedRun::create(o.archive, header, w, spacing, {o.output}));
        } else if (!o.output.empty()) {
            out = std::fopen(o.output.c_str(), "w");
            if (!out) throw ArchiveError("cannot write " + o.output);
        }
        if (run) out = run->output(0);
        std::uint64_t k = run ? run->step() : 0;
        if (k > steps) throw Usage{"the archived run is past --t-end already"};
        if (k == 0) {
            header_line(out, w);
            row(out, w, m.energy(w));
        }
        const auto every = static_cast<std::uint64_t>(o.every);
        for (; k < steps; ++k) {
            stepper.step(w, m.dt);
            if ((k + 1) % every == 0 || (k + 1 == steps && last <= 1e-9 * m.dt)) row(out, w, m.energy(w));
            if (run) run->stepped(w, stepper);
        }
        // the last snapshot at the last whole step; a shortened step to t_end after it (a
        // finished run continued to a later --t-end continues from the whole step)
        if (run) run->finish(w, stepper);
        if (last > 1e-9 * m.dt) {
            stepper.step(w, last);
            row(out, w, m.energy(w));
        }
        if (run) run->close();
        else if (out != stdout && std::fclose(out) != 0) throw ArchiveError("cannot write " + o.output);
    } catch (const Usage& u) {
        std::fprintf(stderr, "%s: %s\n", argv[0], u.message.c_str());
        return 2;
    } catch (const ArchiveError& e) {
        std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
        return 1;
    }
    return 0;
}
