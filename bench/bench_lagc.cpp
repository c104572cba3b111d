// phynjo-lagc against SymPy on the n-link pendulum on a cart, N = 5, 10, 20, 40:
//  * compile speed: `phynjo-lagc nlink_N.lag -o out.cpp` end to end (a process, reading the
//    file, writing C++) against SymPy's n_link_pendulum_on_cart(N) + mass_matrix_full /
//    forcing_full + cse + C printing (bench/sympy_nlink_compile.py), in the same run;
//  * generated code size: the operation count of the CSE'd M and f, both counted by SymPy's
//    count_ops (phynjo's expressions are handed to SymPy as text).
// Prints `ratio lagc_compile_N = SymPy time / phynjo time` and `ratio lagc_ops_N = SymPy
// operations / phynjo operations` (above 1: phynjo emits fewer); and, SymPy computing also
// forcing_full.jacobian(q, u) and CSE'ing it with M and f (phynjo-lagc always emits its
// Jacobians), `ratio lagc_jacobian_N = that SymPy time / phynjo time`.
//   usage: bench_lagc [--sympy-max-n N] [--sympy-jacobian-max-n N]   (defaults 20 and 10)
#include "bench_util.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>


namespace {

std::string models(int n) {
    return n == 5 ? std::string(PHYNJO_SOURCE_DIR "/examples/models/nlink_cart_5.lag")
                  : std::string(PHYNJO_SOURCE_DIR "/bench/nlink_cart_") + std::to_string(n) + ".lag";
}

using phynjo::bench::run_seconds;

/// Runs a command and returns the number after `key` in its output, or −1.
double read_value(const std::string& cmd, const std::string& key) {
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return -1;
    char line[512];
    double v = -1;
    while (std::fgets(line, sizeof line, p))
        if (std::string(line).rfind(key + " ", 0) == 0) v = std::atof(line + key.size() + 1);
    pclose(p);
    return v;
}

} // namespace

int main(int argc, char** argv) {
    int sympy_max_n = 20, sympy_jacobian_max_n = 10;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (std::string(argv[i]) == "--sympy-max-n") sympy_max_n = std::atoi(argv[i + 1]);
        if (std::string(argv[i]) == "--sympy-jacobian-max-n") sympy_jacobian_max_n = std::atoi(argv[i + 1]);
    }
    const bool have_sympy = std::system("python3 -c 'import sympy' >/dev/null 2>&1") == 0;
    const std::string tmp = "/tmp/phynjo_bench_lagc_" + std::to_string(::getpid());
    std::printf("bench_lagc: nlink_cart(N) from the .lag file to C++, and the size of the generated M and f\n");
    if (!have_sympy) std::printf("  SymPy not available (python3 with sympy): phynjo figures only, no ratio\n");
    for (int n : {5, 10, 20, 40}) {
        const std::string model = models(n);
        double best = 1e300;
        for (int rep = 0; rep < (n <= 20 ? 7 : 3); ++rep)
            best = std::min(best, run_seconds({PHYNJO_LAGC, model, "-o", tmp + ".cpp"}));
        std::printf("N = %d\n    phynjo-lagc: %.4f s (best of %d runs, process end to end)\n", n, best, n <= 20 ? 7 : 3);
        const std::string ops_file = tmp + "_ops.txt";
        std::system((std::string(PHYNJO_NLINK_OPS) + " '" + model + "' " + ops_file).c_str());
        const double ops = have_sympy ? read_value("python3 " PHYNJO_SOURCE_DIR "/bench/sympy_nlink_compile.py --count " + ops_file, "ops") : -1;
        if (!have_sympy) continue;
        std::printf("    phynjo operations in M and f after CSE: %.0f\n", ops);
        if (n > sympy_max_n) {
            std::printf("    sympy: skipped (N > --sympy-max-n %d; it takes minutes)\n", sympy_max_n);
            continue;
        }
        const std::string cmd = "python3 " PHYNJO_SOURCE_DIR "/bench/sympy_nlink_compile.py " + std::to_string(n);
        FILE* p = popen(cmd.c_str(), "r");
        double s_time = -1, s_ops = -1;
        char line[256];
        while (p && std::fgets(line, sizeof line, p)) {
            if (std::string(line).rfind("seconds ", 0) == 0) s_time = std::atof(line + 8);
            if (std::string(line).rfind("ops ", 0) == 0) s_ops = std::atof(line + 4);
        }
        if (p) pclose(p);
        if (s_time < 0) {
            std::printf("    sympy: failed to run\n");
            continue;
        }
        std::printf("    sympy: %.3f s, %.0f operations after cse\n", s_time, s_ops);
        std::printf("ratio lagc_compile_%d = %.1f\n", n, s_time / best);
        std::printf("ratio lagc_ops_%d = %.2f\n", n, s_ops / ops);
        if (n > sympy_jacobian_max_n) continue;
        // the same with the Jacobian of f, which phynjo-lagc always emits (rhs_jacobian)
        double j_time = -1;
        if (FILE* pj = popen(("python3 " PHYNJO_SOURCE_DIR "/bench/sympy_nlink_compile.py --jacobian " + std::to_string(n)).c_str(), "r")) {
            while (std::fgets(line, sizeof line, pj))
                if (std::string(line).rfind("seconds ", 0) == 0) j_time = std::atof(line + 8);
            pclose(pj);
        }
        if (j_time < 0) {
            std::printf("    sympy with forcing_full.jacobian: failed to run\n");
            continue;
        }
        std::printf("    sympy with forcing_full.jacobian(q, u): %.3f s\n", j_time);
        std::printf("ratio lagc_jacobian_%d = %.1f\n", n, j_time / best);
    }
    std::remove((tmp + ".cpp").c_str());
    std::remove((tmp + ".hpp").c_str());
    std::remove((tmp + "_ops.txt").c_str());
    return 0;
}
