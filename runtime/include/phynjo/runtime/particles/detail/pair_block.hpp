#pragma once
/// \file
/// The pair sum of direct N-body gravity (internal: nbody.cpp, and bench/bench_nbody.cpp's
/// hand-driven baseline, which calls the same kernel without the workflow around it):
/// structure of arrays, each pair once (Newton's third law), a j-loop GCC vectorizes (the
/// i-accumulators are `omp simd` reductions: no -ffast-math, a summation order fixed by the
/// binary, not by the thread count).
#include <cmath>
#include <cstddef>

namespace phynjo::runtime::detail {

/// Adds to (ax, ay, az) the accelerations (without the factor G) of every pair (i, j) with
/// i in [begin, end) and j > i.
inline void pair_block(const double* __restrict x, const double* __restrict y, const double* __restrict z,
                const double* __restrict m, double* __restrict ax, double* __restrict ay, double* __restrict az,
                std::size_t begin, std::size_t end, std::size_t n, double eps2) {
    for (std::size_t i = begin; i < end; ++i) {
        const double xi = x[i], yi = y[i], zi = z[i], mi = m[i];
        double axi = 0, ayi = 0, azi = 0;
#pragma omp simd reduction(+ : axi, ayi, azi)
        for (std::size_t j = i + 1; j < n; ++j) {
            const double dx = x[j] - xi, dy = y[j] - yi, dz = z[j] - zi;
            const double r2 = dx * dx + dy * dy + dz * dz + eps2;
            const double inv = 1.0 / (r2 * std::sqrt(r2));
            const double sj = m[j] * inv, si = mi * inv;
            axi += sj * dx;
            ayi += sj * dy;
            azi += sj * dz;
            ax[j] -= si * dx;
            ay[j] -= si * dy;
            az[j] -= si * dz;
        }
        ax[i] += axi;
        ay[i] += ayi;
        az[i] += azi;
    }
}

} // namespace phynjo::runtime::detail
