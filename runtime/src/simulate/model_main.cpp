// The command-line driver every generated simulator links (model_main.hpp).
#include "phynjo/runtime/simulate/model_main.hpp"

#include "phynjo/runtime/core/archive.hpp"
#include "phynjo/runtime/simulate/archived_run.hpp"
#include "phynjo/runtime/simulate/ensemble.hpp"
#include "phynjo/runtime/simulate/events.hpp"
#include "phynjo/runtime/simulate/integrator_registry.hpp"
#include "phynjo/runtime/view/recorder.hpp"

#include "strict_numbers.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <optional>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

namespace phynjo::runtime {

namespace {

using detail::whole_number;
std::optional<double> number(std::string_view s) { return detail::finite_number(s); }

/// A time for a message on the page: "%.10g".
std::string seconds(double t) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", t);
    return buf;
}

struct UsageError {
    std::string message;
};

/// An integrator's lines in --help: its name, its order, then its help line wrapped at 92 columns.
std::string help_line(const IntegratorEntry& e) {
    std::string text = std::string(e.name) + ": order " + std::string(e.order) + (e.symplectic ? ", symplectic" : "") +
                       (e.adaptive ? ", adaptive" : "") + ". " + std::string(e.help);
    constexpr std::size_t indent = 25, width = 92;
    std::string out;
    while (!text.empty()) {
        std::size_t cut = text.size();
        if (indent + cut > width) {
            cut = text.rfind(' ', width - indent);
            if (cut == std::string::npos || cut == 0) cut = text.find(' ');
            if (cut == std::string::npos) cut = text.size();
        }
        out += std::string(indent, ' ') + text.substr(0, cut) + "\n";
        text.erase(0, cut == text.size() ? cut : cut + 1);
    }
    return out;
}

void help(const char* prog, const ModelCommandLine& model, const LagrangianSystem& sys) {
    std::string params, coords;
    for (const auto& [name, set] : model.parameters) params += (params.empty() ? "" : ", ") + std::string(name);
    for (const auto& n : sys.coordinate_names) coords += (coords.empty() ? "" : ", ") + n;
    std::string events;
    for (const auto& n : sys.event_names) events += (events.empty() ? "" : ", ") + n;
    std::string names, lines;
    for (const IntegratorEntry& e : integrator_registry()) {
        names += (names.empty() ? "" : "|") + std::string(e.name);
        lines += help_line(e);
    }
    const std::string tolerances = integrator_names([](const IntegratorEntry& e) { return e.tolerances; });
    std::printf("usage: %s [--t-end T] [--dt DT] [--integrator %s] [--every K]\n"
                "          [--param NAME=VALUE]... [--init NAME=VALUE[,NAME'=VALUE]...]... [--output FILE]\n"
                "          [--energy-tolerance TOL [--fail-on-drift]] [--project-initial]\n"
                "          [--projection-tolerance TOL] [--rtol R] [--atol A]\n"
                "          [--events FILE] [--rest-speed V] [--max-events-per-step N] [--shapes FILE]\n"
                "          [--html FILE [--html-fps F]] [--archive FILE [--archive-every K|Xs]]\n"
                "       %s [the options of the run] --resume FILE\n"
                "       %s [the options of the run] --archive FILE --at T [--output FILE]\n"
                "       %s --grid NAME=LO:HI:N... [--uniform NAME=LO:HI... --samples K [--seed S]]\n"
                "          --summary FILE [--trajectories DIR [--every K]] [--threads N] [--no-lanes] [the options of one run]\n"
                "Simulates the model %.*s from its initial state and writes CSV: t, q..., q'..., E\n"
                "(and, for a model with constraints, their multipliers lambda_NAME...).\n"
                "  --t-end T              end time in s (default 10); the run ends exactly at T\n"
                "  --dt DT                step in s (default 0.001); the last step is shortened to end at T\n"
                "  --integrator NAME      the integrator (default %s; docs/generated-code.md compares them):\n"
                "%s"
                "  --rtol R, --atol A     %s: relative and absolute tolerances\n"
                "  --every K              write every K-th step (default: about 5000 rows); the first and\n"
                "                         the last row are always written; t is exactly k*DT\n"
                "  --param NAME=VALUE     set a parameter (repeatable); parameters: %s\n"
                "  --init NAME=VALUE      set an initial value: NAME a coordinate, NAME' its velocity\n"
                "                         (repeatable, or comma-separated); coordinates: %s\n"
                "  --energy-tolerance TOL report on stderr when |E(t) - E(0)| exceeds TOL*max(1, |E(0)|)\n"
                "                         (meaningful for conservative models; default: no check)\n"
                "  --fail-on-drift        with --energy-tolerance: exit 3 when it is exceeded\n"
                "  --project-initial      constraints: project the initial state onto them (Gauss-Newton on\n"
                "                         the positions, then the velocities) and print what changed;\n"
                "                         without it, initial values violating a constraint by more than\n"
                "                         1e-9 (relative) stop the run with an error naming it\n"
                "  --projection-tolerance TOL  constraints: the relative tolerance of the projections\n"
                "                         the integrators make after each step (default 1e-12)\n"
                "  --output FILE, -o FILE write the CSV to FILE (default: standard output)\n"
                "  --events FILE          write the events that fired as CSV to FILE: t, event, then the\n"
                "                         coordinates and velocities just after the event's actions\n"
                "                         (a stop event ends the run at its crossing, with a last row\n"
                "                         in the output); the model's events: %s\n"
                "  --shapes FILE          write the model's shapes at every output row as CSV to FILE:\n"
                "                         t, then NAME_x, NAME_y, NAME_z of each sphere's centre,\n"
                "                         NAME_x1 … NAME_z2 of each segment's or capsule's ends (m), and\n"
                "                         NAME_x … NAME_z, NAME_qw … NAME_qz of each box's centre and\n"
                "                         orientation quaternion\n"
                "  --html FILE            write the run as a 3-D animation: one HTML page that plays offline\n"
                "                         (the shapes, or the coordinates as beads; plots of q, q', E - E(0)\n"
                "                         and the constraint residuals; the events); docs/viewer.md\n"
                "  --html-fps F           frames per simulated second in the page (default 60)\n"
                "  --archive FILE         keep a snapshot of the run every K steps in FILE (a new file): the\n"
                "                         state and all the integrator, the events and the output carry to\n"
                "                         the next step, each record checksummed and on the disk before the\n"
                "                         run goes on (docs/archive.md). cvode, ida and bdf restart their\n"
                "                         history at each snapshot (the run with --archive is that run)\n"
                "  --archive-every K|Xs   a snapshot every K steps, or every X s of wall time (default: 1s;\n"
                "                         cvode, ida, bdf: about 100 in the run, by steps only)\n"
                "  --resume FILE          continue the run archived in FILE (killed, or finished and run\n"
                "                         further with a later --t-end) from its last snapshot, with the\n"
                "                         same options: --output and --shapes are cut to that snapshot and\n"
                "                         continued, byte for byte what the run without a stop writes; an\n"
                "                         archive of another model, parameters or options is refused\n"
                "  --at T                 with --archive FILE of a run: the state at time T, s, as one CSV\n"
                "                         row (the last row a run to --t-end T writes), from the snapshot\n"
                "                         before T integrated forward: bit for bit the run's state\n"
                "  --rest-speed V         the Zeno remedy: a velocity an event resets to below V becomes 0\n"
                "                         and is held (a ball comes to rest) until a free step would\n"
                "                         leave the event's guard on its armed side (default: off)\n"
                "  --max-events-per-step N  more events than N in one step DT is an error (Zeno;\n"
                "                         default 100); so are geometrically shrinking intervals\n"
                "Sweeps: many runs from other parameters or initial values, one summary row each.\n"
                "  --grid NAME=LO:HI:N    N values LO + i (HI - LO)/(N - 1) of NAME (repeatable: the\n"
                "                         runs are the grid's points, the first axis slowest); NAME is a\n"
                "                         parameter or input, a coordinate (its initial value) or NAME'\n"
                "                         (its initial velocity)\n"
                "  --uniform NAME=LO:HI   Monte Carlo: NAME uniform on [LO, HI) (repeatable), --samples K\n"
                "                         draws (at each grid point), reproducible from --seed S (default 0)\n"
                "  --summary FILE         one CSV row per run, in run order: run, the swept values, status\n"
                "                         (finished, stopped by an event, failed), t at the end, the state\n"
                "                         there (end_...), when each event first fired (empty: never), the\n"
                "                         largest relative energy error, the reason of a stop or failure.\n"
                "                         The same bytes for any --threads. Run again with the same\n"
                "                         options, a summary interrupted (killed) goes on from its last\n"
                "                         complete row; a summary of other options is refused\n"
                "  --trajectories DIR     also write each run's trajectory to DIR/run_K.csv (the folder is\n"
                "                         made if missing): t, q..., q'..., E, every K-th step (--every K;\n"
                "                         default: about 5000 rows), the first and the last always\n"
                "  --threads N            run the sweep on N threads (default 1)\n"
                "  --no-lanes             step the runs one at a time; by default (--lanes) a thread steps\n"
                "                         them two or four at a time in SIMD registers (models of one or\n"
                "                         two coordinates, rk4) with libmvec's sines and cosines: a row is\n"
                "                         then the same run's --output to rounding, not bit for bit (a\n"
                "                         sweep of that one point gives its bits); with --no-lanes, bit\n"
                "                         for bit, more slowly\n"
                "Under mpirun (phynjo_add_model's simulators, when built with MPI) a sweep is shared\n"
                "among the ranks, each on --threads N threads; rank 0 writes the summary, the same bytes\n"
                "for any number of ranks.\n"
                "Exit status: 0 done (also when a stop event ended the run), 1 the run failed (the message\n"
                "says why and when), 2 usage error,\n"
                "3 energy drift beyond the tolerance (with --fail-on-drift).\n",
                prog, names.c_str(), prog, prog, prog, static_cast<int>(model.model_name.size()), model.model_name.data(),
                std::string(integrator_registry().front().name).c_str(), lines.c_str(), tolerances.c_str(), params.empty() ? "(none)" : params.c_str(),
                coords.c_str(), events.empty() ? "(none)" : events.c_str());
}

/// The CSV of one run (--output: t, q…, q'…, E, λ…; --shapes: t and every shape's points), a
/// row at a time, and the largest energy drift |E − E(0)| the rows saw.
class RunOutput {
public:
    explicit RunOutput(const LagrangianSystem& sys) : sys_(sys), acc_(sys.dof), lambda_(sys.n_constraints) {}
    RunOutput(const RunOutput&) = delete;
    RunOutput& operator=(const RunOutput&) = delete;
    ~RunOutput() { close(); }

    /// `t` (or `t,event`), then the coordinates and their velocities: both CSVs' header.
    static void state_header(std::FILE* f, const LagrangianSystem& sys, const char* first) {
        std::fprintf(f, "%s", first);
        for (const auto& n : sys.coordinate_names) std::fprintf(f, ",%s", n.c_str());
        for (const auto& n : sys.coordinate_names) std::fprintf(f, ",%s'", n.c_str());
    }
    /// Opens both files (the output "": standard output; the shapes "": none) and writes their
    /// headers; false (after a message naming the file) when one cannot be written. With
    /// `resumed` (a snapshot's "output" section, save()), the files are instead cut to the
    /// length they had at the snapshot and continued.
    bool open(const std::string& output, const std::string& shapes, const char* program, const World& w,
              const std::string* resumed = nullptr) {
        const LagrangianSystem& sys = sys_;
        if (resumed) {
            ArchiveReader in(*resumed, "the snapshot's output section");
            const std::uint64_t out_at = in.u64(), shapes_at = in.u64();
            e0_ = in.f64();
            drift_ = in.f64();
            in.finish();
            if ((out_at == kNoFile) != output.empty() || (shapes_at == kNoFile) != shapes.empty())
                throw ArchiveError("the archived run wrote its rows elsewhere (to standard output or not, --shapes or not)");
            out_ = output.empty() ? stdout : reopen(output, out_at, program);
            if (!shapes.empty()) shapes_file_ = reopen(shapes, shapes_at, program);
            if (!out_ || (!shapes.empty() && !shapes_file_)) return false;
            if (!shapes.empty()) shape_points_.resize(sys.n_shape_values());
            return true;
        }
        out_ = output.empty() ? stdout : std::fopen(output.c_str(), "w");
        if (!out_) {
            std::fprintf(stderr, "%s: cannot write %s\n", program, output.c_str());
            return false;
        }
        state_header(out_, sys, "t");
        std::fprintf(out_, ",E");
        for (const auto& n : sys.constraint_names) std::fprintf(out_, ",lambda_%s", n.c_str());
        std::fprintf(out_, "\n");
        // --shapes: the points of every shape, one row per output row
        if (!shapes.empty()) {
            shapes_file_ = std::fopen(shapes.c_str(), "w");
            if (!shapes_file_) {
                std::fprintf(stderr, "%s: cannot write %s\n", program, shapes.c_str());
                return false;
            }
            std::fprintf(shapes_file_, "t");
            for (std::size_t k = 0; k < sys.n_shapes; ++k) {
                const char* n = sys.shape_names[k].c_str();
                if (sys.shape_kinds[k] == ModelShape::sphere) std::fprintf(shapes_file_, ",%s_x,%s_y,%s_z", n, n, n);
                else if (sys.shape_kinds[k] == ModelShape::box)
                    std::fprintf(shapes_file_, ",%s_x,%s_y,%s_z,%s_qw,%s_qx,%s_qy,%s_qz", n, n, n, n, n, n, n);
                else std::fprintf(shapes_file_, ",%s_x1,%s_y1,%s_z1,%s_x2,%s_y2,%s_z2", n, n, n, n, n, n);
            }
            shape_points_.resize(sys.n_shape_values());
            std::fprintf(shapes_file_, "\n");
        }
        e0_ = sys.energy(0, w.field(kGQ), w.field(kGV));
        return true;
    }
    /// A row of each file at the world's state.
    void row(const World& w) {
        const LagrangianSystem& sys = sys_;
        const std::size_t dof = sys.dof;
        const double e = sys.energy(w.time, w.field(kGQ), w.field(kGV));
        drift_ = std::max(drift_, std::fabs(e - e0_));
        std::fprintf(out_, "%.17g", w.time);
        for (std::size_t i = 0; i < dof; ++i) std::fprintf(out_, ",%.17g", w.at(kGQ, static_cast<Index>(i)));
        for (std::size_t i = 0; i < dof; ++i) std::fprintf(out_, ",%.17g", w.at(kGV, static_cast<Index>(i)));
        std::fprintf(out_, ",%.17g", e);
        if (sys.n_constraints > 0) {
            sys.accelerations_and_multipliers(w.time, w.field(kGQ), w.field(kGV), acc_, lambda_);
            for (double l : lambda_) std::fprintf(out_, ",%.17g", l);
        }
        std::fprintf(out_, "\n");
        if (shapes_file_) {
            if (!shape_points_.empty()) sys.shape_positions(w.time, w.field(kGQ), shape_points_);
            std::fprintf(shapes_file_, "%.17g", w.time);
            for (double x : shape_points_) std::fprintf(shapes_file_, ",%.17g", x);
            std::fprintf(shapes_file_, "\n");
        }
    }
    /// For a snapshot: the files flushed (with `sync`, on the disk), then their lengths, E(0)
    /// and the drift so far — what open(…, resumed) continues from.
    [[nodiscard]] std::string save(bool sync) const {
        ArchiveBytes out;
        out.u64(length(out_, out_ != stdout, sync)).u64(length(shapes_file_, true, sync));
        out.f64(e0_).f64(drift_);
        return out.take();
    }
    /// Closes the files (standard output stays open).
    void close() {
        if (out_ && out_ != stdout) std::fclose(out_);
        if (shapes_file_) std::fclose(shapes_file_);
        out_ = shapes_file_ = nullptr;
    }
    [[nodiscard]] double e0() const { return e0_; }
    [[nodiscard]] double drift() const { return drift_; }

private:
    static constexpr std::uint64_t kNoFile = ~std::uint64_t{0};
    /// A file's length after its rows were flushed (kNoFile for standard output, or none);
    /// ArchiveError when they cannot be written.
    static std::uint64_t length(std::FILE* f, bool file, bool sync) {
        if (!f) return kNoFile;
        if (std::fflush(f) != 0) throw ArchiveError(std::string("cannot write the output: ") + std::strerror(errno));
        if (!file) return kNoFile;
        if (sync && ::fdatasync(::fileno(f)) != 0 && errno != EINVAL)
            throw ArchiveError(std::string("cannot sync the output: ") + std::strerror(errno));
        const long at = std::ftell(f);
        if (at < 0) throw ArchiveError(std::string("cannot tell the output's length: ") + std::strerror(errno));
        return static_cast<std::uint64_t>(at);
    }
    /// `path` cut to `length` bytes and opened for appending (null after a message when it
    /// cannot be, or is shorter: not the archived run's file).
    static std::FILE* reopen(const std::string& path, std::uint64_t length, const char* program) {
        std::FILE* f = std::fopen(path.c_str(), "r+");
        if (!f) {
            std::fprintf(stderr, "%s: --resume: cannot continue %s: %s\n", program, path.c_str(), std::strerror(errno));
            return nullptr;
        }
        struct stat st {};
        if (::fstat(::fileno(f), &st) != 0 || static_cast<std::uint64_t>(st.st_size) < length) {
            std::fprintf(stderr,
                         "%s: --resume: %s has %lld bytes, fewer than the %llu the archived run had written there: "
                         "not that run's file\n",
                         program, path.c_str(), static_cast<long long>(st.st_size), static_cast<unsigned long long>(length));
            std::fclose(f);
            return nullptr;
        }
        if (::ftruncate(::fileno(f), static_cast<off_t>(length)) != 0 || std::fseek(f, 0, SEEK_END) != 0) {
            std::fprintf(stderr, "%s: --resume: cannot continue %s: %s\n", program, path.c_str(), std::strerror(errno));
            std::fclose(f);
            return nullptr;
        }
        return f;
    }

    const LagrangianSystem& sys_;
    std::FILE* out_ = nullptr;
    std::FILE* shapes_file_ = nullptr;
    std::vector<double> shape_points_, acc_, lambda_;
    double e0_ = 0, drift_ = 0;
};

/// The simulator: its options read (parse) and checked together (check), then a sweep
/// (sweep_runs) or one run (run).
struct Simulator {
    int argc;
    char** argv;
    const ModelCommandLine& model;
    SweepProcesses* processes;
    const bool speaks; // of several ranks, rank 0 alone prints
    double t_end = 10, dt = 1e-3;
    std::optional<double> energy_tolerance;
    bool fail_on_drift = false, project_initial = false;
    ProjectionOptions projection;
    std::string integrator{integrator_registry().front().name}, output, events_output, shapes_output, html_output;
    double html_fps = 60;
    const IntegratorEntry* entry = nullptr;
    EventOptions event_options;
    std::optional<double> rtol, atol;
    long every = 0;
    std::vector<std::pair<std::string, double>> inits, params;
    // the archive (docs/archive.md): written (--archive), continued (--resume), read (--at)
    std::string archive;
    bool resume = false;
    long archive_every = 0;     ///< a snapshot every K steps (0: by wall time, or the default)
    double archive_seconds = 0; ///< … or every X s of wall time
    std::optional<double> at;
    // a sweep (sweep.hpp): its options, and the others that decide its results
    SweepCommand sweep;
    bool sweeping = false, single_run_output = false;

    Simulator(int c, char** v, const ModelCommandLine& m, SweepProcesses* p)
        : argc(c), argv(v), model(m), processes(p), speaks(!p || p->rank() == 0) {}

    /// Reads the options; false when --help was asked for (and printed). Throws UsageError.
    bool parse();
    /// What the options mean together. Throws UsageError.
    void check();
    /// A sweep (--grid, --uniform): run_sweep with these options.
    int sweep_runs();
    /// One run from the initial state to --t-end, its CSV written: the exit status.
    int run();
    /// The --init values set in `w` and, for a model with constraints, the initial state
    /// checked (first projected with --project-initial): an exit status when that fails.
    std::optional<int> set_initial_state(const LagrangianSystem& sys, World& w) const;
    /// What identifies this run in an archive: the model (its name, and a fingerprint of its
    /// functions at `w0`, the initial state), every option that decides the states or the rows.
    [[nodiscard]] ArchiveHeader archive_header(const LagrangianSystem& sys, const World& w0) const;
    /// --events: the event log as CSV.
    int write_events(const LagrangianSystem& sys, const EventMonitor& monitor) const;
};

bool Simulator::parse() {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* opt) -> std::string {
            if (i + 1 >= argc) throw UsageError{std::string(opt) + " needs a value"};
            return argv[++i];
        };
        auto num = [&](const char* opt) {
            const std::string v = value(opt);
            if (auto x = number(v)) return *x;
            throw UsageError{std::string(opt) + ": '" + v + "' is not a number"};
        };
        auto assignment = [&](const char* opt, const std::string& kv) {
            const auto eq = kv.find('=');
            if (eq == std::string::npos || eq == 0) throw UsageError{std::string(opt) + ": expected NAME=VALUE, got '" + kv + "'"};
            const auto v = number(std::string_view(kv).substr(eq + 1));
            if (!v) throw UsageError{std::string(opt) + ": '" + kv.substr(eq + 1) + "' is not a number (in '" + kv + "')"};
            return std::pair{kv.substr(0, eq), *v};
        };
        if (a == "--grid" || a == "--uniform") {
            const std::string v = value(a.c_str());
            try {
                (a == "--grid" ? sweep.plan.grid : sweep.plan.uniform)
                    .push_back(a == "--grid" ? parse_grid_axis(v) : parse_uniform_axis(v));
            } catch (const std::invalid_argument& e) {
                throw UsageError{a + ": " + e.what()};
            }
            sweeping = true;
        } else if (a == "--samples" || a == "--seed" || a == "--threads") {
            const std::string v = value(a.c_str());
            const auto k = whole_number(v);
            if (!k || *k < (a == "--seed" ? 0 : 1)) throw UsageError{a + ": '" + v + "' is not a " + (a == "--seed" ? "non-negative" : "positive") + " whole number"};
            if (a == "--samples") sweep.plan.samples = static_cast<std::size_t>(*k);
            else if (a == "--seed") sweep.plan.seed = static_cast<std::uint64_t>(*k);
            else sweep.threads = static_cast<unsigned>(std::min<long>(*k, 1024));
            sweeping = sweeping || a != "--threads";
        } else if (a == "--summary") {
            sweep.summary = value("--summary");
            sweeping = true;
        } else if (a == "--lanes" || a == "--no-lanes") {
            sweep.settings.lanes = a == "--lanes";
        } else if (a == "--trajectories") {
            sweep.trajectories = value("--trajectories");
            if (sweep.trajectories.empty()) throw UsageError{"--trajectories needs a folder"};
            sweeping = true;
        } else if (a == "--t-end") t_end = num("--t-end");
        else if (a == "--dt") dt = num("--dt");
        else if (a == "--integrator") integrator = value("--integrator");
        else if (a == "--rtol" || a == "--atol") {
            const double v = num(a == "--rtol" ? "--rtol" : "--atol");
            if (!(v > 0)) throw UsageError{a + " must be positive"};
            (a == "--rtol" ? rtol : atol) = v;
        }
        else if (a == "--every") {
            const std::string v = value("--every");
            const auto k = whole_number(v);
            if (!k || *k <= 0) throw UsageError{"--every: '" + v + "' is not a positive whole number"};
            every = *k;
        } else if (a == "--output" || a == "-o") output = value("--output"), single_run_output = true;
        else if (a == "--energy-tolerance") {
            energy_tolerance = num("--energy-tolerance");
            if (!(*energy_tolerance > 0)) throw UsageError{"--energy-tolerance must be positive"};
        } else if (a == "--fail-on-drift") fail_on_drift = true;
        else if (a == "--events") events_output = value("--events"), single_run_output = true;
        else if (a == "--shapes") shapes_output = value("--shapes"), single_run_output = true;
        else if (a == "--html") {
            html_output = value("--html"), single_run_output = true;
            if (html_output.empty()) throw UsageError{"--html needs a file name"};
        } else if (a == "--html-fps") {
            html_fps = num("--html-fps");
            if (!(html_fps > 0) || html_fps > 1e6) throw UsageError{"--html-fps must be positive (and at most 1e6)"};
        }
        else if (a == "--rest-speed") {
            event_options.rest_speed = num("--rest-speed");
            if (!(event_options.rest_speed > 0)) throw UsageError{"--rest-speed must be positive"};
        } else if (a == "--max-events-per-step") {
            const std::string v = value("--max-events-per-step");
            const auto k = whole_number(v);
            if (!k || *k <= 0) throw UsageError{"--max-events-per-step: '" + v + "' is not a positive whole number"};
            event_options.max_events_per_step = static_cast<std::size_t>(*k);
        }
        else if (a == "--archive" || a == "--resume") {
            if (!archive.empty()) throw UsageError{"--archive and --resume name one archive, once"};
            archive = value(a.c_str());
            if (archive.empty()) throw UsageError{a + " needs a file name"};
            resume = a == "--resume";
        } else if (a == "--archive-every") {
            const std::string v = value("--archive-every");
            const auto spacing = ArchiveSpacing::parse(v);
            if (!spacing) throw UsageError{"--archive-every: '" + v + "' is neither a step count K nor seconds Xs (e.g. 2s)"};
            archive_every = static_cast<long>(spacing->steps);
            archive_seconds = spacing->seconds;
        } else if (a == "--at") {
            at = num("--at");
            if (!(*at >= 0)) throw UsageError{"--at must not be negative"};
        }
        else if (a == "--project-initial") project_initial = true;
        else if (a == "--projection-tolerance") {
            projection.tolerance = num("--projection-tolerance");
            if (!(projection.tolerance > 0)) throw UsageError{"--projection-tolerance must be positive"};
        }
        else if (a == "--param") {
            const auto [name, v] = assignment("--param", value("--param"));
            bool found = false;
            for (const auto& [pname, set] : model.parameters)
                if (name == pname) {
                    set(v);
                    found = true;
                }
            if (!found) throw UsageError{"unknown parameter '" + name + "' (try --help)"};
            params.emplace_back(name, v);
        } else if (a == "--init") {
            std::string list = value("--init");
            std::size_t start = 0;
            while (start <= list.size()) {
                const std::size_t comma = list.find(',', start);
                std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
                item.erase(0, item.find_first_not_of(' '));
                item.erase(item.find_last_not_of(' ') + 1);
                inits.push_back(assignment("--init", item));
                if (comma == std::string::npos) break;
                start = comma + 1;
            }
        } else if (a == "--help" || a == "-h") {
            if (speaks) help(argv[0], model, model.system());
            return 0;
        } else throw UsageError{"unknown option '" + a + "' (try --help)"};
    }
    return true;
}

void Simulator::check() {
    if (!(dt > 0)) throw UsageError{"--dt must be positive"};
    if (!(t_end >= 0)) throw UsageError{"--t-end must not be negative"};
    entry = find_integrator(integrator);
    if (!entry) throw UsageError{"--integrator must be " + integrator_names() + ", not '" + integrator + "'"};
    if (archive_seconds > 0 && entry->restarts)
        throw UsageError{"--archive-every by wall time: --integrator " + integrator +
                         " restarts at each snapshot, so its snapshots are every K steps (--archive-every K)"};
    if ((rtol || atol) && !entry->tolerances)
        throw UsageError{"--rtol and --atol go with --integrator " +
                         integrator_names([](const IntegratorEntry& e) { return e.tolerances; })};
    if (fail_on_drift && !energy_tolerance) throw UsageError{"--fail-on-drift needs --energy-tolerance"};
    if (sweeping) {
        if (sweep.summary.empty()) throw UsageError{"a sweep (--grid, --uniform, --samples) needs --summary FILE"};
        if (sweep.plan.grid.empty() && sweep.plan.uniform.empty())
            throw UsageError{"--summary, --samples and --seed go with --grid or --uniform"};
        if (sweep.plan.uniform.empty() && sweep.plan.samples != 1) throw UsageError{"--samples needs --uniform NAME=LO:HI"};
        if (single_run_output || energy_tolerance || project_initial || rtol || atol)
            throw UsageError{"--output, --events, --shapes, --html, --energy-tolerance, --project-initial, --rtol and "
                             "--atol are for one run; a sweep writes --summary (and --trajectories)"};
        if (every > 0 && sweep.trajectories.empty()) throw UsageError{"--every goes with one run's --output or a sweep's --trajectories"};
        if (!archive.empty() || at || archive_every)
            throw UsageError{"--archive, --resume, --archive-every and --at are for one run, not a sweep"};
    } else if (processes && processes->size() > 1)
        throw UsageError{"only a sweep (--grid, --uniform) runs on several MPI ranks; run one simulation without mpirun"};
    if (!html_output.empty() && !can_write(html_output)) throw UsageError{"--html: cannot write " + html_output};
    if ((archive_every || archive_seconds > 0) && archive.empty())
        throw UsageError{"--archive-every goes with --archive FILE or --resume FILE"};
    if (at) {
        if (archive.empty() || resume) throw UsageError{"--at T reads the run's archive: --archive FILE --at T"};
        if (!events_output.empty() || !shapes_output.empty() || !html_output.empty() || archive_every || archive_seconds > 0)
            throw UsageError{"--at writes the state at T (to --output): not with --events, --shapes, --html or --archive-every"};
    } else if (resume && !html_output.empty() && output.empty()) {
        throw UsageError{"--html with --resume draws the whole run from its rows: give --output FILE"};
    } else if (!archive.empty() && !resume && ::access(archive.c_str(), F_OK) == 0) {
        throw UsageError{"--archive: " + archive + " exists (continue its run with --resume " + archive + ")"};
    }
}

int Simulator::sweep_runs() {
    sweep.settings.t_end = t_end;
    sweep.settings.dt = dt;
    sweep.settings.integrator = integrator;
    sweep.settings.events = event_options;
    sweep.settings.projection = projection;
    sweep.inits = inits;
    sweep.processes = processes;
    if (every <= 0) { // about 5000 rows per trajectory, as one run's --output
        every = std::max(1L, detail::whole_steps(t_end, dt) / 5000);
    }
    sweep.settings.every = every;
    // What decides the results (and --trajectories: a resumed sweep writes the trajectories
    // of the runs it adds where the first part wrote its own): every option but --threads
    // and --summary, in order, then --lanes when the runs go in lanes (the default; a
    // summary of --no-lanes, or of a phynjo from before lanes were the default, is not
    // resumed in lanes).
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if ((a == "--threads" || a == "--summary") && i + 1 < argc) {
            ++i;
            continue;
        }
        if (a == "--lanes" || a == "--no-lanes") continue;
        sweep.signature += (sweep.signature.empty() ? "" : " ") + a;
    }
    if (sweep.settings.lanes) sweep.signature += (sweep.signature.empty() ? "" : " ") + std::string("--lanes");
    sweep.signature = std::string(model.model_name) + (sweep.signature.empty() ? "" : " ") + sweep.signature;
    return run_sweep(sweep, model, argv[0]);
}

std::optional<int> Simulator::set_initial_state(const LagrangianSystem& sys, World& w) const {
    const std::size_t dof = sys.dof;
    for (const auto& [name, v] : inits) {
        const bool velocity = !name.empty() && name.back() == '\'';
        const std::string coord = velocity ? name.substr(0, name.size() - 1) : name;
        const auto it = std::find(sys.coordinate_names.begin(), sys.coordinate_names.end(), coord);
        if (it == sys.coordinate_names.end()) {
            std::fprintf(stderr, "%s: --init: '%s' is not a coordinate (try --help)\n", argv[0], coord.c_str());
            return 2;
        }
        w.at(velocity ? kGV : kGQ, static_cast<Index>(it - sys.coordinate_names.begin())) = v;
    }
    if (sys.n_constraints > 0) {
        std::vector<double> q0(w.field(kGQ).begin(), w.field(kGQ).end()), v0(w.field(kGV).begin(), w.field(kGV).end());
        try {
            if (project_initial) {
                project_onto_constraints(sys, 0, w.field(kGQ), w.field(kGV), projection);
                std::string changed;
                char buf[160];
                for (std::size_t i = 0; i < dof; ++i)
                    for (int level = 0; level < 2; ++level) {
                        const double before = level ? v0[i] : q0[i], after = w.at(level ? kGV : kGQ, static_cast<Index>(i));
                        if (before == after) continue;
                        std::snprintf(buf, sizeof buf, "  %s%s: %.17g -> %.17g\n", sys.coordinate_names[i].c_str(),
                                      level ? "'" : "", before, after);
                        changed += buf;
                    }
                std::fprintf(stderr, "%s: --project-initial: %s", argv[0],
                             changed.empty() ? "the initial state satisfies the constraints; nothing changed\n"
                                             : ("projected the initial state onto the constraints:\n" + changed).c_str());
            }
            check_constraints(sys, 0, w.field(kGQ), w.field(kGV));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
            return 1;
        }
    }
    return std::nullopt;
}

ArchiveHeader Simulator::archive_header(const LagrangianSystem& sys, const World& w0) const {
    // the model's functions at two states, bit for bit (another model, another build of it
    // with other defaults, other parameters: another fingerprint)
    std::uint64_t h = 1469598103934665603ULL;
    auto mix = [&](std::string_view bytes) {
        for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ULL;
    };
    auto mix_values = [&](std::span<const double> x) {
        for (double v : x) mix(std::string_view(reinterpret_cast<const char*>(&v), sizeof v));
    };
    for (const auto* names : {&sys.coordinate_names, &sys.constraint_names, &sys.event_names})
        for (const std::string& n : *names) mix(n + "\n");
    std::vector<double> q(w0.field(kGQ).begin(), w0.field(kGQ).end()), v(w0.field(kGV).begin(), w0.field(kGV).end()),
        a(sys.dof), lambda(sys.n_constraints);
    for (int probe = 0; probe < 2; ++probe) {
        const double t = probe ? 0.375 : 0.0;
        if (probe)
            for (std::size_t i = 0; i < sys.dof; ++i) q[i] += 0.125 * static_cast<double>(i + 1), v[i] -= 0.0625;
        mix_values(q);
        mix_values(v);
        try {
            const double e = sys.energy(t, q, v);
            mix_values(std::span<const double>(&e, 1));
            if (sys.n_constraints > 0) sys.accelerations_and_multipliers(t, q, v, a, lambda);
            else sys.accelerations(t, q, v, a);
            mix_values(a);
            mix_values(lambda);
        } catch (const std::exception& e) {
            mix(e.what());
        }
    }
    char fingerprint[20];
    std::snprintf(fingerprint, sizeof fingerprint, "%016llx", static_cast<unsigned long long>(h));
    auto text = [](double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.17g", x);
        return std::string(buf);
    };
    ArchiveHeader header;
    // (the parameters before the fingerprint they change: a difference is named by them)
    header.add("program", "phynjo simulator").add("model", std::string(model.model_name));
    for (const auto& [name, value] : params) header.add("param." + name, text(value));
    for (const auto& [name, value] : inits) header.add("init." + name, text(value));
    header.add("model.fingerprint", fingerprint);
    header.add("integrator", integrator).add("dt", text(dt));
    if (rtol) header.add("rtol", text(*rtol));
    if (atol) header.add("atol", text(*atol));
    header.add("project-initial", project_initial ? "yes" : "no").add("projection-tolerance", text(projection.tolerance));
    header.add("rest-speed", text(event_options.rest_speed))
        .add("max-events-per-step", std::to_string(event_options.max_events_per_step));
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.17gs", archive_seconds);
    header.add("every", std::to_string(every)).add("archive-every", archive_every > 0 ? std::to_string(archive_every) : seconds);
    header.add("output", output.empty() ? "(standard output)" : output);
    header.add("shapes", shapes_output.empty() ? "(none)" : shapes_output);
    header.add("world.fields", field_names(w0)); // for a reader of the file alone (phynjo-archive extract)
    return header;
}

int Simulator::write_events(const LagrangianSystem& sys, const EventMonitor& monitor) const {
    std::FILE* ev = std::fopen(events_output.c_str(), "w");
    if (!ev) {
        std::fprintf(stderr, "%s: cannot write %s\n", argv[0], events_output.c_str());
        return 1;
    }
    RunOutput::state_header(ev, sys, "t,event");
    std::fprintf(ev, "\n");
    for (const EventRecord& r : monitor.log()) {
        std::fprintf(ev, "%.17g,%s", r.time, sys.event_names[r.event].c_str());
        for (double x : r.q) std::fprintf(ev, ",%.17g", x);
        for (double x : r.qdot) std::fprintf(ev, ",%.17g", x);
        std::fprintf(ev, "\n");
    }
    std::fclose(ev);
    return 0;
}

int Simulator::run() {
    const LagrangianSystem sys = model.system();
    if (!entry->constraints && sys.n_constraints > 0) {
        const std::string instead = integrator_names([](const IntegratorEntry& e) { return e.constraints && e.stiff; });
        std::fprintf(stderr, "%s: --integrator %s takes models without constraints; this one has %zu (use %s)\n", argv[0],
                     integrator.c_str(), sys.n_constraints, instead.c_str());
        return 2;
    }
    World w = make_lagrangian_world(sys);
    if (const auto failed = set_initial_state(sys, w)) return *failed;
    // --at T: the state a run to T ends in
    if (at) t_end = *at;
    // Full steps, then a shortened last one: the run ends exactly at t_end (a ratio within
    // 1e-9 of a whole number counts as that number: 20 / 0.001 is 20000, not 20000.000000000004).
    const long steps = detail::whole_steps(t_end, dt);
    const double last = t_end - static_cast<double>(steps) * dt;
    const bool short_step = last > 1e-9 * dt;

    // The archive (docs/archive.md): read when continued (--resume) or questioned (--at);
    // its rows and snapshots keep their spacing (--every, --archive-every) unless given again.
    std::optional<ArchiveContents> contents;
    std::optional<ArchiveSnapshot> from; // the snapshot this run starts from
    std::optional<ArchiveWriter> writer;
    try {
        if (resume || at) {
            contents = read_archive(archive);
            if (const auto v = contents->header.get("every"); v && every <= 0) every = whole_number(*v).value_or(0);
            if (const auto v = contents->header.get("archive-every"); v && archive_every <= 0 && !(archive_seconds > 0))
                if (const auto spacing = ArchiveSpacing::parse(std::string(*v))) {
                    archive_every = static_cast<long>(spacing->steps);
                    archive_seconds = spacing->seconds;
                }
        }
        if (every <= 0) every = std::max(1L, steps / 5000);
        // by default a snapshot a second of wall time (REBOUND's rule: the archive costs the
        // same small share of any run); an integrator that restarts at each snapshot has them
        // every K steps, about 100 in the run (where they fall changes its run)
        if (archive_every <= 0 && !(archive_seconds > 0)) {
            if (entry->restarts) archive_every = std::max(1L, steps / 100);
            else archive_seconds = 1;
        }
        if (!archive.empty()) {
            ArchiveHeader header = archive_header(sys, w);
            if (at) // --at writes its row elsewhere: the run's files are the archive's
                for (auto& [key, value] : header.fields)
                    if (key == "output" || key == "shapes") value = std::string(contents->header.get(key).value_or(""));
            if (contents) {
                if (const std::string d = contents->header.difference(header); !d.empty())
                    throw ArchiveError(archive + ": the archive is of another run: " + d);
                // the latest snapshot this run reaches (--at: the one at or before T's last whole step)
                for (auto it = contents->snapshots.rbegin(); it != contents->snapshots.rend(); ++it)
                    if (static_cast<long>(it->step) <= steps) {
                        from = read_snapshot(archive, it->offset);
                        break;
                    }
                if (resume) writer.emplace(ArchiveWriter::resume(archive, *contents, header));
            } else {
                writer.emplace(ArchiveWriter::create(archive, header));
            }
        }
    } catch (const ArchiveError& e) {
        std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
        return 1;
    }

    RunOutput csv(sys);
    try {
        if (from) {
            ArchiveReader world(from->section("world"), "the snapshot's world");
            restore_world(world, w);
            world.finish();
        }
        if (!csv.open(output, shapes_output, argv[0], w, from && !at ? &from->section("output") : nullptr)) return 1;
        if (resume || at)
            std::fprintf(stderr, from ? "%s: %s: continuing from the snapshot at step %llu, t = %.17g s\n"
                                      : "%s: %s: no snapshot at or before that step in the archive; from the start\n",
                         argv[0], resume ? "--resume" : "--at", from ? static_cast<unsigned long long>(from->step) : 0ULL,
                         from ? from->time : 0.0);
    } catch (const ArchiveError& e) {
        std::fprintf(stderr, "%s: %s: %s\n", argv[0], archive.c_str(), e.what());
        return 1;
    }
    // --html: a recorder reading the world after every step (it keeps a frame when one is due)
    std::optional<Recorder> recorder;
    if (!html_output.empty()) {
        try {
            check_three_js();
        } catch (const ViewerError& e) {
            std::fprintf(stderr, "%s: --html: %s\n", argv[0], e.what());
            return 1;
        }
        RecorderOptions options;
        options.fps = html_fps;
        char title[160];
        std::snprintf(title, sizeof title, "%.*s (%s, dt = %g s)", static_cast<int>(model.model_name.size()),
                      model.model_name.data(), integrator.c_str(), dt);
        options.title = title;
        recorder.emplace(options);
        recorder->add_model(sys);
    }
    // a resumed run's page is drawn from all its rows at the end, the first part's too (with
    // --every 1, the page of the run never stopped)
    const bool html_from_rows = recorder && from && !at;
    std::string stop_reason;
    int status = 0;
    const bool with_events = sys.n_events > 0;
    EventMonitor monitor(sys, event_options);
    try {
        if (!from || at) {
            if (!at) csv.row(w);
            if (recorder) recorder->capture(w);
        }
        // step k is dt long (the last one shortened to end at t_end) and ends at exactly k·dt:
        // the time is set, not accumulated
        const long total = steps + (short_step ? 1 : 0);
        auto target_of = [&](long k) { return k <= steps ? static_cast<double>(k) * dt : t_end; };
        // step_to(target, h): one step of the integrator towards target, h long when the run
        // step is whole, and w.time where it ended. With events, the monitor watches every
        // such step; after an event the rest of the run step is taken from the event time.
        IntegratorSettings settings;
        settings.dt = dt;
        settings.projection = projection;
        settings.rtol = rtol;
        settings.atol = atol;
        const std::unique_ptr<RunIntegrator> run = entry->make(sys, w, settings, with_events);
        // a snapshot when one is due (SnapshotSchedule: every archive_every-th step, or by wall
        // time and then also at the last whole step, from which a finished run continues): the
        // world, what the integrator, the monitor and the output carry to the next step (the
        // rows up to it on the disk first)
        SnapshotSchedule schedule(ArchiveSpacing{static_cast<std::uint64_t>(std::max(0L, archive_every)), archive_seconds});
        auto snapshot_due = [&](long k) {
            return schedule.due(static_cast<std::uint64_t>(k)) || (archive_every <= 0 && k == steps);
        };
        auto snapshot = [&](long k) {
            ArchiveSnapshot snap;
            snap.step = static_cast<std::uint64_t>(k);
            snap.time = w.time;
            ArchiveBytes world, integrator_state, events;
            save_world(world, w);
            run->save(integrator_state);
            monitor.save(events);
            snap.sections = {{"world", world.take()},
                             {"integrator", integrator_state.take()},
                             {"events", events.take()},
                             {"output", csv.save(true)}};
            writer->write(snap);
            run->restart_at_snapshot();
            schedule.taken();
        };
        if (from) {
            ArchiveReader integrator_state(from->section("integrator"), "the snapshot's integrator state");
            run->restore(integrator_state);
            integrator_state.finish();
            ArchiveReader events(from->section("events"), "the snapshot's event monitor");
            monitor.restore(events);
            events.finish();
        }
        auto advance = [&](auto&& step_to, long k, double target, const EventMonitor::Extension* extension = nullptr) {
            const double h = k <= steps ? dt : last;
            if (!with_events) {
                step_to(target, h);
                w.time = target;
            } else if (!advance_with_events(monitor, w, target, h, step_to, extension)) {
                if (!at) csv.row(w); // stopped by an event: the state at it is the last row
                return false;
            }
            if (!at) {
                if (k % every == 0) csv.row(w);
                // (the snapshot before the last row a finished run adds: a run continued
                // to a later end has no row there)
                if (writer && k <= steps && snapshot_due(k)) snapshot(k);
                if (k == total && k % every != 0) csv.row(w);
            }
            if (recorder && !html_from_rows) recorder->capture(w);
            return true;
        };
        const long first = from ? static_cast<long>(from->step) + 1 : 1;
        for (long k = first; k <= total; ++k)
            if (!advance([&](double target, double h) { run->step_to(w, target, h); }, k, target_of(k), run->dense())) break;
        if (at) csv.row(w);
        if (const std::string st = run->statistics(); !st.empty()) std::fprintf(stderr, "%s\n", st.c_str());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: simulation stopped at t = %.17g: %s\n", argv[0], w.time, e.what());
        stop_reason = "the simulation failed at t = " + seconds(w.time) + " s: " + e.what();
        status = 1;
    }
    csv.close();
    if (recorder) { // what it recorded, also when the run failed or an event stopped it
        if (html_from_rows) {
            World shown = w;
            std::FILE* rows = std::fopen(output.c_str(), "r");
            std::vector<char> line(64 + 64 * (2 * sys.dof + 2 + sys.n_constraints));
            for (bool header = true; rows && std::fgets(line.data(), static_cast<int>(line.size()), rows); header = false) {
                if (header) continue;
                char* at_char = line.data();
                shown.time = std::strtod(at_char, &at_char);
                for (std::size_t i = 0; i < 2 * sys.dof; ++i)
                    shown.at(i < sys.dof ? kGQ : kGV, static_cast<Index>(i % sys.dof)) = std::strtod(at_char + 1, &at_char);
                recorder->capture(shown);
            }
            if (rows) std::fclose(rows);
            recorder->capture_last(shown);
        } else {
            recorder->capture_last(w);
        }
        for (const EventRecord& r : monitor.log()) recorder->mark_event(r.time, sys.event_names[r.event]);
        if (monitor.stopped() && !monitor.log().empty() && stop_reason.empty())
            stop_reason = "stopped by the event " + sys.event_names[monitor.log().back().event] + " at t = " +
                          seconds(monitor.log().back().time) + " s";
        recorder->set_stop_reason(stop_reason);
        try {
            recorder->write_html(html_output);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s: --html: %s\n", argv[0], e.what());
            status = status ? status : 1;
        }
    }
    if (monitor.stopped() && !monitor.log().empty()) {
        const EventRecord& last_event = monitor.log().back();
        std::fprintf(stderr, "%s: the run stopped at t = %.17g: event '%s'\n", argv[0], last_event.time,
                     sys.event_names[last_event.event].c_str());
    }
    if (!events_output.empty() && write_events(sys, monitor) != 0) return 1;
    if (status == 0 && energy_tolerance) {
        const double limit = *energy_tolerance * std::max(1.0, std::fabs(csv.e0()));
        if (csv.drift() > limit) {
            std::fprintf(stderr, "%s: the energy drifted by %.6g (beyond %.6g = %g * max(1, |E(0)|), E(0) = %.17g)\n", argv[0],
                         csv.drift(), limit, *energy_tolerance, csv.e0());
            if (fail_on_drift) status = 3;
        }
    }
    return status;
}

} // namespace

int model_main(int argc, char** argv, const ModelCommandLine& model) { return model_main(argc, argv, model, nullptr); }

int model_main(int argc, char** argv, const ModelCommandLine& model, SweepProcesses* processes) {
    Simulator simulator(argc, argv, model, processes);
    try {
        if (!simulator.parse()) return 0;
        simulator.check();
    } catch (const UsageError& e) {
        if (simulator.speaks) std::fprintf(stderr, "%s: %s\n", argv[0], e.message.c_str());
        return 2;
    }
    return simulator.sweeping ? simulator.sweep_runs() : simulator.run();
}

} // namespace phynjo::runtime
