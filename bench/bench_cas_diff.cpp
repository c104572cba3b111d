// Differentiating the n-link pendulum-on-cart Lagrangian: for every coordinate q_i,
// ∂L/∂q_i', ∂L/∂q_i and d/dt(∂L/∂q_i'), against SymPy doing the same work in the same run.
//
// Honest timing: every repetition runs in a fresh Pool (no warm intern table, no memoized
// derivatives), the Lagrangian is built outside the timed region on both sides, SymPy's
// cache is cleared before each of its repetitions, and the faster of SymPy's two approaches
// (dynamicsymbols, plain symbols) is the reference. Both report their best repetition.
//
// usage: bench_cas_diff [--sympy-max-n N] [--script PATH]   (default 20: SymPy takes minutes at 40)
#include "nlink_model.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>

using namespace phynjo;
using cas::Expr;

namespace {

/// The common numeric point of the agreement check (same as point() in the SymPy script).
double value_of(const std::string& name) {
    const char k = name[0];
    const int i = std::atoi(name.c_str() + 1);
    switch (k) {
    case 'g': return 9.81;
    case 'q': return 0.1 * (i + 1);
    case 'm': return 1.0 + 0.1 * i;
    case 'l': return 1.0 - 0.01 * i;
    default: return 0;
    }
}

double check_sum(const std::vector<Expr>& out) {
    double total = 0;
    for (Expr e : out) {
        cas::Bindings<double> at;
        for (Expr v : cas::free_variables(e)) {
            const std::string name(cas::symbol_name(v));
            const int i = std::atoi(name.c_str() + 1);
            switch (cas::derivative_order(v)) {
            case 0: at[v] = value_of(name); break;
            case 1: at[v] = 0.2 - 0.03 * i; break;  // u_i
            default: at[v] = 0.3 + 0.01 * i; break; // a_i
            }
        }
        total += cas::evaluate(e, at);
    }
    return total;
}

struct Result {
    double check = 0;
    double seconds = std::numeric_limits<double>::infinity();
    std::size_t lagrangian_dag = 0, result_dag = 0, result_tree = 0;
};

Result run_phynjo(int n, int reps) {
    Result r;
    for (int rep = 0; rep < reps; ++rep) {
        cas::Pool pool; // fresh: nothing cached from the previous repetition
        cas::PoolScope scope(pool);
        const auto model = bench::nlink_cart(n);
        const auto start = std::chrono::steady_clock::now();
        std::vector<Expr> out;
        for (Expr q : model.coordinates) {
            const Expr p = cas::diff(model.lagrangian, cas::velocity(q));
            const Expr dLdq = cas::diff(model.lagrangian, q);
            const Expr dpdt = cas::total_time_derivative(p, model.coordinates);
            out.insert(out.end(), {p, dLdq, dpdt});
        }
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (s < r.seconds) r.seconds = s;
        r.lagrangian_dag = cas::dag_size(model.lagrangian);
        r.result_dag = cas::dag_size(out);
        std::size_t tree = 0;
        for (Expr e : out) tree += cas::tree_size(e);
        r.result_tree = tree;
        if (rep == 0) r.check = check_sum(out);
    }
    return r;
}

/// Runs the SymPy script; returns its best time, or a negative number if unavailable.
double run_sympy(const std::string& script, int n, int reps, double& check) {
    const std::string cmd = "python3 '" + script + "' " + std::to_string(n) + " " + std::to_string(reps) + " 2>/dev/null";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return -1;
    double best = -1;
    char line[256];
    while (std::fgets(line, sizeof line, p)) {
        char kind[32];
        double s;
        if (std::sscanf(line, "%31s %lf", kind, &s) == 2 && std::string(kind) == "check") {
            check = s;
            continue;
        }
        if (std::sscanf(line, "%31s %lf", kind, &s) == 2) {
            std::printf("    sympy (%s): %.4f s\n", kind, s);
            if (best < 0 || s < best) best = s;
        }
    }
    return pclose(p) == 0 ? best : -1;
}

} // namespace

int main(int argc, char** argv) {
    int sympy_max_n = 20;
    std::string script = PHYNJO_BENCH_DIR "/sympy_nlink_diff.py";
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--sympy-max-n") sympy_max_n = std::atoi(argv[i + 1]);
        else if (a == "--script") script = argv[i + 1];
    }
    const bool have_sympy = std::system("python3 -c 'import sympy' >/dev/null 2>&1") == 0;
    std::printf("bench_cas_diff: dL/dq', dL/dq, d/dt dL/dq' for every coordinate of nlink_cart(N)\n");
    if (!have_sympy) std::printf("  SymPy not available (python3 with sympy): phynjo times only, no ratio\n");
    for (int n : {5, 10, 20, 40}) {
        const int reps = n <= 10 ? 20 : n <= 20 ? 5 : 3;
        const Result r = run_phynjo(n, reps);
        std::printf("N = %d\n", n);
        std::printf("    phynjo: %.6f s (best of %d)  nodes: L %zu, results %zu (DAG), %zu (as trees)\n", r.seconds,
                    reps, r.lagrangian_dag, r.result_dag, r.result_tree);
        if (!have_sympy) continue;
        if (n > sympy_max_n) {
            std::printf("    sympy: skipped (N > --sympy-max-n %d; it takes minutes)\n", sympy_max_n);
            continue;
        }
        double check = std::numeric_limits<double>::quiet_NaN();
        const double s = run_sympy(script, n, n <= 5 ? 3 : n <= 10 ? 2 : 1, check);
        if (s < 0) {
            std::printf("    sympy: failed to run\n");
            continue;
        }
        const bool agree = std::fabs(check - r.check) <= 1e-9 * (1 + std::fabs(r.check));
        std::printf("    same results: sum of all outputs at a common point: phynjo %.15g, sympy %.15g: %s\n",
                    r.check, check, agree ? "agree" : "DISAGREE");
        if (!agree) {
            std::printf("    no ratio: the results differ\n");
            continue;
        }
        std::printf("ratio cas_diff_%d = %.1f\n", n, s / r.seconds);
    }
    return 0;
}
