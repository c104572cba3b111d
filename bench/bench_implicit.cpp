// The implicit midpoint rule on the double pendulum: the time of one step against one RK4
// step (both through the runtime's workflow, same model, same dt), and the Newton iteration
// with the exact Jacobian against the fixed-point iteration it replaced.
// Prints µs per step and
//   `ratio midpoint_vs_rk4_double_pendulum = RK4 step time / midpoint step time`
//   `ratio midpoint_newton_vs_fixed_point  = fixed-point step time / Newton step time`.
#include "bench_double_pendulum.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace {

using namespace phynjo::runtime;

/// Best-of-5 µs per step over `steps` steps from the model's initial state.
double us_per_step(const LagrangianSystem& s, const char* integrator, int steps) {
    double best = 1e300;
    for (int round = 0; round < 5; ++round) {
        World w = make_lagrangian_world(s);
        Stepper st(std::string(integrator) == "rk4" ? lagrangian_rk4(s, w.layout_ptr()) : lagrangian_midpoint(s, w.layout_ptr()));
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < steps; ++k) st.step(w, 1e-3);
        const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / steps;
        best = std::min(best, us);
    }
    return best;
}

} // namespace

int main() {
    const double_pendulum::Parameters P;
    const LagrangianSystem newton = double_pendulum::system(P);
    LagrangianSystem fixed = newton;
    fixed.canonical_jacobian = nullptr;
    const int steps = 100000;
    const double rk4 = us_per_step(newton, "rk4", steps), mid = us_per_step(newton, "midpoint", steps),
                 old = us_per_step(fixed, "midpoint", steps);
    std::printf("bench_implicit: double pendulum from th1 = th2 = pi/2, dt = 1 ms, %d steps, best of 5\n", steps);
    std::printf("    RK4:                                  %.3f us/step\n", rk4);
    std::printf("    implicit midpoint, Newton (exact J):  %.3f us/step\n", mid);
    std::printf("    implicit midpoint, fixed point:       %.3f us/step\n", old);
    std::printf("ratio midpoint_vs_rk4_double_pendulum = %.3f\n", rk4 / mid);
    std::printf("ratio midpoint_newton_vs_fixed_point = %.3f\n", old / mid);
}
