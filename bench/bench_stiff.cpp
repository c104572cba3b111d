// Stiff chains of N masses, 0..20 s at rtol 1e-8, atol 1e-10: N = 30 (bench/stiff_chain_30.lag,
// a 60×60 Jacobian; the ratios the issue names) and N = 3 (examples/models/stiff_chain.lag):
//  * CVODE with the model's exact Jacobian against CVODE with its own difference-quotient
//    Jacobian (same solver, same tolerances): `ratio cvode_jac_stiff_chain = DQ time / exact time`;
//  * phynjo's own Bdf (integrators/bdf.hpp: the NDF of SciPy's BDF, CVODE's Newton test, a
//    banded velocity Schur complement) and CVODE against SciPy's solve_ivp(method='BDF',
//    jac=...) on the SymPy-derived, lambdified right side and Jacobian
//    (bench/scipy_stiff_chain.py, integration time only), in the same run:
//    `ratio scipy_bdf_stiff_chain = SciPy time / Bdf time`, `…_cvode = SciPy time / CVODE time`
// (the N = 3 figures as `…_3`).
// Time to solution, best of 7; the final states are printed to show the runs agree.
#include "bench_stiff_chain.hpp"
#include "bench_stiff_chain_30.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

using namespace phynjo::runtime;

/// A solver's best of 7 runs from the initial state to 20 s: the time, its counters, x1..x3.
template <class Solver>
struct Run {
    double seconds = 1e300;
    typename Solver::Stats stats;
    double x[3] = {0, 0, 0};
};

template <class Solver>
Run<Solver> best_of_7(const LagrangianSystem& s, const typename Solver::Options& options) {
    Run<Solver> r;
    for (int rep = 0; rep < 7; ++rep) {
        World w = make_lagrangian_world(s);
        const auto t0 = std::chrono::steady_clock::now();
        Solver solver(s, options);
        solver.advance(w, 20.0);
        const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (sec < r.seconds) {
            r.seconds = sec;
            r.stats = solver.stats();
            for (int i = 0; i < 3; ++i) r.x[i] = w.at(kGQ, i);
        }
    }
    return r;
}

Run<Cvode> run(const LagrangianSystem& s, bool exact, Cvode::Options::LinearSolver solver = Cvode::Options::LinearSolver::second_order) {
    return best_of_7<Cvode>(s, {.rtol = 1e-8, .atol = 1e-10, .exact_jacobian = exact, .linear_solver = solver});
}

/// CVODE exact against difference quotients, then SciPy, for one chain; prints the ratios.
void compare(const LagrangianSystem& s, int n, const std::string& suffix) {
    const Run<Cvode> exact = run(s, true), dq = run(s, false),
              exact_dense = run(s, true, Cvode::Options::LinearSolver::dense);
    const Run<Bdf> bdf = best_of_7<Bdf>(s, {.rtol = 1e-8, .atol = 1e-10}); // phynjo's own BDF, same tolerances
    std::printf("bench_stiff: stiff chain of %d masses (k1 = 1e6 N/m, critically damped; soft springs 1 N/m), 0..20 s, "
                "rtol 1e-8, atol 1e-10\n", n);
    for (const auto* r : {&exact, &exact_dense, &dq})
        std::printf("    CVODE, %s: %.3f ms, %ld steps, %ld right sides (+%ld for difference quotients), %ld "
                    "Jacobians, %ld Newton failures, %ld error-test failures, %ld linear setups; x1..x3 = %.9g %.9g %.9g\n",
                    r == &exact         ? "exact Jacobian, block elimination (ours)"
                    : r == &exact_dense ? "exact Jacobian, SUNDIALS dense LU"
                                        : "difference-quotient Jacobian, SUNDIALS dense LU (reference)",
                    1e3 * r->seconds, r->stats.steps,
                    r->stats.rhs_evaluations, r->stats.difference_quotient_rhs, r->stats.jacobian_evaluations, r->stats.newton_failures,
                    r->stats.error_test_failures, r->stats.linear_setups, r->x[0],
                    r->x[1], r->x[2]);
    std::printf("    phynjo Bdf (NDF orders 1-5, exact Jacobian, banded Schur complement: %zu sub-, %zu super-diagonals): "
                "%.3f ms, %ld steps, %ld right sides, %ld Jacobians, %ld factorizations, %ld Newton iterations, %ld Newton "
                "failures, %ld error-test failures; x1..x3 = %.9g %.9g %.9g\n",
                bdf.stats.lower_bandwidth, bdf.stats.upper_bandwidth, 1e3 * bdf.seconds, bdf.stats.steps,
                bdf.stats.rhs_evaluations, bdf.stats.jacobian_evaluations, bdf.stats.factorizations,
                bdf.stats.newton_iterations, bdf.stats.newton_failures, bdf.stats.error_test_failures, bdf.x[0], bdf.x[1],
                bdf.x[2]);
    std::printf("ratio cvode_jac_stiff_chain%s = %.3f\n", suffix.c_str(), dq.seconds / exact.seconds);
    // SciPy: the first python3 on the path that has it, else Debian's
    std::string py;
    for (const char* cand : {"python3", "/usr/bin/python3"})
        if (std::system((std::string(cand) + " -c 'import scipy, sympy' >/dev/null 2>&1").c_str()) == 0) {
            py = cand;
            break;
        }
    if (py.empty()) {
        std::printf("    SciPy not available (python3 with scipy and sympy): no ratio scipy_bdf_stiff_chain%s\n", suffix.c_str());
        return;
    }
    FILE* p = popen((py + " " PHYNJO_SOURCE_DIR "/bench/scipy_stiff_chain.py " + std::to_string(n) + " 20 1e-8 1e-10").c_str(), "r");
    double seconds = -1;
    char line[512];
    while (p && std::fgets(line, sizeof line, p)) {
        if (std::string(line).rfind("seconds ", 0) == 0) seconds = std::atof(line + 8);
        if (std::string(line).rfind("steps ", 0) == 0 || std::string(line).rfind("final ", 0) == 0)
            std::printf("    SciPy BDF: %s", line);
    }
    if (p) pclose(p);
    if (seconds < 0) {
        std::printf("    SciPy run failed\n");
        return;
    }
    std::printf("    SciPy solve_ivp(BDF, jac=lambdified SymPy Jacobian): %.3f ms\n", 1e3 * seconds);
    std::printf("ratio scipy_bdf_stiff_chain%s = %.1f\n", suffix.c_str(), seconds / bdf.seconds);
    std::printf("ratio scipy_bdf_stiff_chain_cvode%s = %.1f\n", suffix.c_str(), seconds / exact.seconds);
}

} // namespace

int main() {
    compare(stiff_chain_30::system({}), 30, "");
    compare(stiff_chain::system({}), 3, "_3");
}
