// Ensembles (issue #17): the double pendulum's flip-time map, released from rest over a grid
// of (th1, th2) in [-3, 3]², each run until either arm first flips (|th| reaches π) or 10 s.
//  * `ratio ensemble_flipmap_hand` = trajectories per second of phynjo's sweep runs as a sweep
//    runs them by default (run_many on examples/models/flip_pendulum.lag, compiled like the
//    hand loop with -march=native: lane_width runs at a time through the generated lane kernel
//    rk4_step_values_lanes, events located on each run's step's Hermite arc, energy error
//    tracked every step) / those of a hand-written loop (closed-form accelerations with m = l = 1
//    folded in, RK4, the flip taken at the step that crosses), one thread, same dt = 1 ms.
//    Target ≥ 0.9. `ratio ensemble_flipmap_hand_no_lanes`: the same with --no-lanes (one run at
//    a time through rk4_step_values, each row bit for bit one run's --output).
//  * `ratio ensemble_flipmap_scipy` = phynjo / SymPy-lambdify + SciPy solve_ivp (RK45 with
//    rtol = atol = 1e-10, terminal events) on a sample of the same runs (bench/scipy_flipmap.py),
//    when python3 with SymPy and SciPy is present. Target ≥ 50.
//
// Usage: bench_ensemble [N]   (N × N grid, default 40)
#include "bench_flip.hpp"
#include "phynjo/runtime/simulate/ensemble.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace phynjo::runtime;

namespace {

using Clock = std::chrono::steady_clock;

/// The hand-written reference: point masses m = 1, l = 1, g = 9.81 (flip_pendulum's defaults).
struct Hand {
    static void acc(const double* y, double* d) { // y = (th1, th2, w1, w2) → d = y'
        const double g = 9.81, dl = y[0] - y[1], s = std::sin(dl), c = std::cos(dl);
        const double den = 2 - c * c; // (m1 + m2 − m2 cos²) / m2 with m = l = 1
        d[0] = y[2];
        d[1] = y[3];
        d[2] = (-g * 2 * std::sin(y[0]) - s * (y[3] * y[3] + y[2] * y[2] * c) + g * std::sin(y[1]) * c) / den;
        d[3] = (s * (2 * y[2] * y[2] + 2 * g * std::cos(y[0]) + y[3] * y[3] * c)) / den;
    }
    /// Time of the first flip (or t_end).
    static double run(double th1, double th2, double dt, double t_end) {
        double y[4] = {th1, th2, 0, 0}, k1[4], k2[4], k3[4], k4[4], t[4];
        const long steps = std::lround(t_end / dt);
        for (long n = 1; n <= steps; ++n) {
            acc(y, k1);
            for (int i = 0; i < 4; ++i) t[i] = y[i] + 0.5 * dt * k1[i];
            acc(t, k2);
            for (int i = 0; i < 4; ++i) t[i] = y[i] + 0.5 * dt * k2[i];
            acc(t, k3);
            for (int i = 0; i < 4; ++i) t[i] = y[i] + dt * k3[i];
            acc(t, k4);
            for (int i = 0; i < 4; ++i) y[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
            if (std::abs(y[0]) > M_PI || std::abs(y[1]) > M_PI) return static_cast<double>(n) * dt;
        }
        return t_end;
    }
};

} // namespace

int main(int argc, char** argv) {
    const std::size_t n = argc > 1 ? static_cast<std::size_t>(std::atoi(argv[1])) : 40;
    const double dt = 1e-3, t_end = 10;
    SweepPlan plan;
    plan.grid = {SweepAxis{"th1", -3, 3, n}, SweepAxis{"th2", -3, 3, n}};
    const LagrangianSystem sys = flip_pendulum::system({});
    RunSettings settings;
    settings.t_end = t_end;
    settings.dt = dt;
    std::vector<double> v(2);
    // a plan's runs as run_many's starts; the (th1, th2) pairs they point at live in q0s
    using Q0 = std::array<std::pair<std::size_t, double>, 2>;
    auto starts_of = [&v](const SweepPlan& p, std::vector<Q0>& q0s) {
        q0s.resize(p.size());
        std::vector<RunStart> starts(p.size());
        for (std::size_t k = 0; k < p.size(); ++k) {
            p.values(k, v);
            q0s[k] = {{{0, v[0]}, {1, v[1]}}};
            starts[k].q0 = q0s[k];
        }
        return starts;
    };
    // phynjo: the sweep's runs, one thread, as run_sweep runs them (run_many): by default in
    // lanes (two or four runs at a time in SIMD registers: `lane_width`), and with --no-lanes
    std::vector<Q0> q0s;
    const std::vector<RunStart> starts = starts_of(plan, q0s);
    struct Sweep {
        double sec = 0, flips = 0, worst = 0;
        std::vector<double> t;
    };
    auto sweep = [&](bool lanes) {
        RunSettings s = settings;
        s.lanes = lanes;
        std::vector<RunSummary> summaries(plan.size());
        Sweep out;
        const auto t0 = Clock::now();
        run_many(sys, starts, s, summaries);
        out.sec = std::chrono::duration<double>(Clock::now() - t0).count();
        for (const RunSummary& r : summaries) {
            out.t.push_back(r.t);
            out.flips += r.status == RunSummary::Status::stopped;
            out.worst = std::max(out.worst, r.max_energy_error);
        }
        return out;
    };
    const Sweep plain = sweep(false), lanes = sweep(true);
    // the hand-written loop
    double flips_h = 0;
    int disagree = 0, disagree_lanes = 0;
    const auto t1 = Clock::now();
    for (std::size_t k = 0; k < plan.size(); ++k) {
        plan.values(k, v);
        const double t = Hand::run(v[0], v[1], dt, t_end);
        flips_h += t < t_end;
        if (std::abs(t - plain.t[k]) > 2 * dt) ++disagree; // chaos: a few may part ways
        if (std::abs(t - lanes.t[k]) > 2 * dt) ++disagree_lanes;
    }
    const double sec_h = std::chrono::duration<double>(Clock::now() - t1).count();
    const double runs = static_cast<double>(plan.size());
    std::printf("bench_ensemble: flip map %zu x %zu, dt = 1 ms, 10 s cap, one thread\n", n, n);
    std::printf("    phynjo sweep runs (lanes):     %8.1f trajectories/s (%zu runs at a time; %.0f flipped; largest "
                "energy error %.1e; %d flip times differ from the hand loop's by > 2 dt)\n",
                runs / lanes.sec, sys.lane_width, lanes.flips, lanes.worst, disagree_lanes);
    std::printf("    phynjo sweep runs, --no-lanes: %8.1f trajectories/s (%.0f flipped; largest energy error %.1e)\n",
                runs / plain.sec, plain.flips, plain.worst);
    std::printf("    hand-written RK4:              %8.1f trajectories/s (%.0f flipped; %d of %zu flip times differ by > 2 dt)\n",
                runs / sec_h, flips_h, disagree, plan.size());
    std::printf("ratio ensemble_flipmap_hand = %.2f\n", sec_h / lanes.sec);
    std::printf("ratio ensemble_flipmap_hand_no_lanes = %.2f\n", sec_h / plain.sec);
    std::fflush(stdout);
    // SciPy on a sample of the same runs
    // the first python3 on the path that has SciPy and SymPy, else Debian's (as bench_stiff)
    std::string py;
    for (const char* cand : {"python3", "/usr/bin/python3"})
        if (std::system((std::string(cand) + " -c 'import scipy, sympy' >/dev/null 2>&1").c_str()) == 0) {
            py = cand;
            break;
        }
    const std::string cmd = py + " " PHYNJO_SOURCE_DIR "/bench/scipy_flipmap.py 8 2>/dev/null";
    if (std::FILE* p = py.empty() ? nullptr : ::popen(cmd.c_str(), "r")) {
        double rate = 0;
        char line[256];
        while (std::fgets(line, sizeof line, p))
            if (std::sscanf(line, "scipy trajectories/s %lf", &rate) == 1) break;
        ::pclose(p);
        if (rate > 0) {
            // phynjo's sweep (lanes, the default) on the same 8 x 8 runs
            SweepPlan small;
            small.grid = {SweepAxis{"th1", -3, 3, 8}, SweepAxis{"th2", -3, 3, 8}};
            std::vector<Q0> small_q0;
            const std::vector<RunStart> small_starts = starts_of(small, small_q0);
            std::vector<RunSummary> small_out(small.size());
            const auto t2 = Clock::now();
            run_many(sys, small_starts, settings, small_out);
            const double mine = 64 / std::chrono::duration<double>(Clock::now() - t2).count();
            std::printf("    SymPy + SciPy solve_ivp (RK45, rtol = atol = 1e-10): %.2f trajectories/s on an 8 x 8 grid "
                        "(phynjo: %.1f on the same runs)\n", rate, mine);
            std::printf("ratio ensemble_flipmap_scipy = %.1f\n", mine / rate);
        } else {
            std::printf("    (the SciPy reference failed: no ensemble_flipmap_scipy)\n");
        }
    } else {
        std::printf("    (python3 with SymPy and SciPy not found: no ensemble_flipmap_scipy)\n");
    }
}
