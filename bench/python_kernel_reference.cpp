// The reference of `ratio py_batch_accelerations` (bench/python_bench.py): C++ calling a loaded
// kernel's accelerations on N states, one call a state, as the Python package's batched call
// does inside. Prints `cxx seconds S` (the best of 7).
//   usage: python_kernel_reference KERNEL.so N
#include "phynjo/runtime/system/kernel.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: python_kernel_reference KERNEL.so N\n");
        return 2;
    }
    using namespace phynjo::runtime;
    const auto kernel = ModelKernel::load(argv[1]);
    const KernelParameters P(kernel);
    const phynjo_kernel& t = kernel->table();
    const std::size_t n = t.dof, N = std::strtoul(argv[2], nullptr, 10);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-3, 3);
    std::vector<double> q(N * n), v(N * n), a(N * n);
    for (double& x : q) x = u(rng);
    for (double& x : v) x = u(rng);
    double best = 1e300, sum = 0;
    for (int rep = 0; rep < 7; ++rep) {
        const auto t0 = std::chrono::steady_clock::now();
        int status = 0;
        for (std::size_t i = 0; i < N && status == 0; ++i)
            status = t.accelerations(P.data(), 0.0, q.data() + i * n, v.data() + i * n, a.data() + i * n);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        kernel->check(status);
        sum += a[0];
    }
    std::printf("cxx seconds %.6g (checksum %.17g)\n", best, sum);
    return 0;
}
