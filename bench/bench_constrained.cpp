// Constrained models (docs/language.md, *Constraints*):
//  * compile speed: `phynjo-lagc` on the N-link pendulum in Cartesian coordinates (2N
//    coordinates, N rod constraints; the .lag written by this program) against SymPy's
//    LagrangesMethod with hol_coneqs + mass_matrix_full / forcing_full + cse + C printing
//    (bench/sympy_constrained_compile.py), N = 3, 5, 10: `ratio lagc_constrained_N`;
//  * the KKT solve: the generated accelerations_and_multipliers of the four-bar linkage
//    against a straightforward hand-written solve — the same generated M, f, G and γ
//    evaluated, then Eigen's dense LU of [[M, -Gᵀ], [G, 0]] — both -O3: `ratio kkt_four_bar`;
//  * a closed five-bar linkage (chaotic) run to t = 1000 s with RATTLE and with the implicit
//    midpoint rule (symmetric projection): the largest position and velocity constraint
//    residuals, the energy error early and late, and the wall time (figures only).
//   usage: bench_constrained [--sympy-max-n N]   (default 10)
#include "five_bar.hpp"
#include "bench_four_bar.hpp"

#include <Eigen/Dense>

#include "bench_util.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>


namespace {

using namespace phynjo::runtime;

/// The N-link pendulum in Cartesian coordinates, as a .lag file.
std::string cartesian_chain(int n) {
    std::string s = "model chain_" + std::to_string(n) + "\ncoordinates ";
    for (int i = 1; i <= n; ++i) s += (i > 1 ? ", " : "") + ("x" + std::to_string(i)) + ", y" + std::to_string(i);
    s += "\nparameters g = 9.81";
    for (int i = 1; i <= n; ++i) s += ", m" + std::to_string(i) + " = 1, l" + std::to_string(i) + " = 1";
    s += "\nlagrangian (";
    for (int i = 1; i <= n; ++i) {
        const std::string k = std::to_string(i);
        s += (i > 1 ? " + " : "") + ("1/2*m" + k) + "*(x" + k + "'^2 + y" + k + "'^2) - g*m" + k + "*y" + k;
    }
    s += ")\nconstraint rod1: x1^2 + y1^2 = l1^2\n";
    for (int i = 2; i <= n; ++i) {
        const std::string k = std::to_string(i), j = std::to_string(i - 1);
        s += "constraint rod" + k + ": (x" + k + " - x" + j + ")^2 + (y" + k + " - y" + j + ")^2 = l" + k + "^2\n";
    }
    s += "initial ";
    for (int i = 1; i <= n; ++i) s += (i > 1 ? ", x" : "x") + std::to_string(i) + " = " + std::to_string(i);
    return s + "\n";
}

using phynjo::bench::run_seconds;

void compile_speed(int sympy_max_n) {
    const bool have_sympy = std::system("python3 -c 'import sympy' >/dev/null 2>&1") == 0;
    const std::string tmp = "/tmp/phynjo_bench_constrained_" + std::to_string(::getpid());
    std::printf("bench_constrained: the N-link pendulum in Cartesian coordinates (2N coordinates, N rods), .lag to C++\n");
    if (!have_sympy) std::printf("  SymPy not available (python3 with sympy): phynjo figures only, no ratio\n");
    for (int n : {3, 5, 10}) {
        const std::string model = tmp + "_chain.lag";
        std::ofstream(model) << cartesian_chain(n);
        double best = 1e300;
        for (int rep = 0; rep < 7; ++rep) best = std::min(best, run_seconds({PHYNJO_LAGC, model, "-o", tmp + ".cpp"}));
        std::printf("N = %d\n    phynjo-lagc: %.4f s (best of 7 runs, process end to end)\n", n, best);
        if (!have_sympy || n > sympy_max_n) continue;
        const std::string cmd = "python3 " PHYNJO_SOURCE_DIR "/bench/sympy_constrained_compile.py " + std::to_string(n);
        FILE* p = popen(cmd.c_str(), "r");
        double s_time = -1;
        char line[256];
        while (p && std::fgets(line, sizeof line, p))
            if (std::string(line).rfind("seconds ", 0) == 0) s_time = std::atof(line + 8);
        if (p) pclose(p);
        if (s_time < 0) {
            std::printf("    sympy: failed to run\n");
            continue;
        }
        std::printf("    sympy LagrangesMethod + cse + ccode: %.3f s\n", s_time);
        std::printf("ratio lagc_constrained_%d = %.1f\n", n, s_time / best);
    }
    for (const char* ext : {"_chain.lag", ".cpp", ".hpp"}) std::remove((tmp + ext).c_str());
}

/// The hand-written reference: the generated M, f, G, γ, then a dense KKT solve by Eigen.
__attribute__((noinline)) void kkt_by_hand(const four_bar::Parameters& P, const double* q, const double* v, double* a,
                                           double* lambda) {
    constexpr int n = 3, m = 2;
    double M[n * n], f[n], G[m * n], gamma[m];
    four_bar::mass_matrix(P, 0.0, {q, n}, M);
    four_bar::forcing(P, 0.0, {q, n}, {v, n}, f);
    four_bar::constraint_matrix(P, 0.0, {q, n}, G);
    four_bar::constraint_gamma(P, 0.0, {q, n}, {v, n}, gamma);
    Eigen::Matrix<double, n + m, n + m> K = Eigen::Matrix<double, n + m, n + m>::Zero();
    Eigen::Matrix<double, n + m, 1> b;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) K(i, j) = M[i * n + j];
        b(i) = f[i];
    }
    for (int k = 0; k < m; ++k) {
        for (int j = 0; j < n; ++j) {
            K(n + k, j) = G[k * n + j];
            K(j, n + k) = -G[k * n + j];
        }
        b(n + k) = gamma[k];
    }
    const Eigen::Matrix<double, n + m, 1> x = K.partialPivLu().solve(b);
    for (int i = 0; i < n; ++i) a[i] = x(i);
    for (int k = 0; k < m; ++k) lambda[k] = x(n + k);
}

void kkt_four_bar() {
    constexpr std::size_t n = four_bar::dof, m = four_bar::n_constraints, states = 4096;
    const four_bar::Parameters P;
    // states on the linkage: the simulation's own trajectory, every 10 ms
    const LagrangianSystem sys = four_bar::system(P);
    World w = four_bar::make_world(P);
    Stepper s(four_bar::workflow(P, w, "rk4"));
    std::vector<double> q(n * states), v(n * states), a1(n * states), a2(n * states), l1(m * states), l2(m * states);
    for (std::size_t i = 0; i < states; ++i) {
        for (int k = 0; k < 10; ++k) s.step(w, 1e-3);
        for (std::size_t j = 0; j < n; ++j) {
            q[i * n + j] = w.at(kGQ, static_cast<Index>(j));
            v[i * n + j] = w.at(kGV, static_cast<Index>(j));
        }
    }
    auto time_it = [&](auto&& f) {
        double best = 1e300;
        for (int r = 0; r < 20; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            for (std::size_t i = 0; i < states; ++i) f(i);
            best = std::min(best, std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() /
                                      static_cast<double>(states));
        }
        return best;
    };
    double t_gen = 1e300, t_hand = 1e300;
    for (int round = 0; round < 5; ++round) { // interleaved
        t_hand = std::min(t_hand, time_it([&](std::size_t i) { kkt_by_hand(P, &q[i * n], &v[i * n], &a1[i * n], &l1[i * m]); }));
        t_gen = std::min(t_gen, time_it([&](std::size_t i) {
                             four_bar::accelerations_and_multipliers(P, 0.0, {&q[i * n], n}, {&v[i * n], n}, {&a2[i * n], n},
                                                                     {&l2[i * m], m});
                         }));
    }
    double diff = 0;
    for (std::size_t i = 0; i < a1.size(); ++i) diff = std::max(diff, std::fabs(a1[i] - a2[i]) / (1 + std::fabs(a1[i])));
    for (std::size_t i = 0; i < l1.size(); ++i) diff = std::max(diff, std::fabs(l1[i] - l2[i]) / (1 + std::fabs(l1[i])));
    std::printf("bench_constrained: four-bar accelerations_and_multipliers, %zu states along a trajectory\n", states);
    std::printf("    hand-written: generated M, f, G, gamma + Eigen dense KKT (partial-pivot LU): %.1f ns per call\n", t_hand);
    std::printf("    phynjo generated (one CSE pass, Schur complement):                        %.1f ns per call\n", t_gen);
    std::printf("    largest relative difference of q'' and lambda: %.2g\n", diff);
    std::printf("ratio kkt_four_bar = %.2f\n", t_hand / t_gen);
}

void five_bar_long_run(const char* integrator, const char* description) {
    const five_bar::Parameters P;
    const LagrangianSystem sys = five_bar::system(P);
    World w = five_bar::make_world(P);
    Stepper s(five_bar::workflow(P, w, integrator));
    const double dt = 1e-3, e0 = sys.energy(0, w.field(kGQ), w.field(kGV));
    const long steps = 1000000;
    std::vector<double> phi(2), psi(2);
    double worst_q = 0, worst_v = 0, de = 0, de_first = 0, de_last = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (long k = 1; k <= steps; ++k) {
        s.step(w, dt);
        if (k % 10) continue;
        sys.constraint_residuals(w.time, w.field(kGQ), w.field(kGV), phi);
        sys.constraint_velocity_residuals(w.time, w.field(kGQ), w.field(kGV), psi);
        for (int c = 0; c < 2; ++c) {
            worst_q = std::max(worst_q, std::fabs(phi[c]));
            worst_v = std::max(worst_v, std::fabs(psi[c]));
        }
        const double e = std::fabs(sys.energy(w.time, w.field(kGQ), w.field(kGV)) - e0);
        de = std::max(de, e);
        if (k <= steps / 10) de_first = std::max(de_first, e);
        if (k > steps - steps / 10) de_last = std::max(de_last, e);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("bench_constrained: closed five-bar linkage to t = 1000 s, %s, dt = 1 ms\n", description);
    std::printf("    largest |phi| (position level): %.2g m; largest |phi'| (velocity level): %.2g m/s (target <= 1e-10)\n",
                worst_q, worst_v);
    std::printf("    energy error: largest %.3g J of E = %.4g J; largest in the first 100 s %.3g J, in the last 100 s %.3g J\n",
                de, e0, de_first, de_last);
    std::printf("    wall time: %.2f s (%.2f us per step)\n", wall, wall / static_cast<double>(steps) * 1e6);
}

} // namespace

int main(int argc, char** argv) {
    int sympy_max_n = 10;
    for (int i = 1; i + 1 < argc; i += 2)
        if (std::string(argv[i]) == "--sympy-max-n") sympy_max_n = std::atoi(argv[i + 1]);
    compile_speed(sympy_max_n);
    kkt_four_bar();
    five_bar_long_run("rattle", "RATTLE (symplectic)");
    five_bar_long_run("midpoint", "implicit midpoint + symmetric projection");
    return 0;
}
