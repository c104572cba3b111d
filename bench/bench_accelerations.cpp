// Evaluation speed of generated code: `accelerations` of the double pendulum against the
// best closed form we can write by hand (sin and cos of each angle once, the 2×2 system
// solved in closed form), and the time per call at N = 20 (nlink_cart_20, 21 coordinates).
// Both sides are compiled with the same flags (-O3 -march=native -fno-math-errno).
// Prints ns per call and `ratio accelerations_double_pendulum = hand time / phynjo time`.
#include "bench_double_pendulum.hpp"
#include "nlink_cart_20.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

struct Params {
    double m1 = 1, m2 = 1, l1 = 1, l2 = 1, g = 9.81;
};

/// The double pendulum by hand (absolute angles from the downward vertical):
///   [(m1+m2) l1²        m2 l1 l2 cosΔ] [θ1'']   [−m2 l1 l2 θ2'² sinΔ − (m1+m2) g l1 sin θ1]
///   [m2 l1 l2 cosΔ      m2 l2²       ] [θ2''] = [ m2 l1 l2 θ1'² sinΔ − m2 g l2 sin θ2     ]
/// with Δ = θ1 − θ2.
__attribute__((noinline)) void hand_accelerations(const Params& p, const double* q, const double* v, double* a) {
    const double s1 = std::sin(q[0]), c1 = std::cos(q[0]), s2 = std::sin(q[1]), c2 = std::cos(q[1]);
    const double sd = s1 * c2 - c1 * s2, cd = c1 * c2 + s1 * s2;
    const double M = p.m1 + p.m2, k = p.m2 * p.l1 * p.l2;
    const double a11 = M * p.l1 * p.l1, a12 = k * cd, a22 = p.m2 * p.l2 * p.l2;
    const double f1 = -k * v[1] * v[1] * sd - M * p.g * p.l1 * s1;
    const double f2 = k * v[0] * v[0] * sd - p.m2 * p.g * p.l2 * s2;
    const double inv = 1.0 / (a11 * a22 - a12 * a12);
    a[0] = (a22 * f1 - a12 * f2) * inv;
    a[1] = (a11 * f2 - a12 * f1) * inv;
}

template <typename F>
double ns_per_call(std::size_t n_states, std::size_t dof, const std::vector<double>& q, const std::vector<double>& v,
                   std::vector<double>& out, F&& f, int rounds) {
    double best = 1e300;
    for (int r = 0; r < rounds; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < n_states; ++i) f(&q[i * dof], &v[i * dof], &out[i * dof]);
        best = std::min(best, std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() /
                                  static_cast<double>(n_states));
    }
    return best;
}

} // namespace

int main() {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-2, 2);
    const std::size_t states = 4096;
    {
        std::vector<double> q(2 * states), v(2 * states), a_hand(2 * states), a_gen(2 * states);
        for (auto& x : q) x = u(rng);
        for (auto& x : v) x = u(rng);
        const Params hp;
        const double_pendulum::Parameters gp;
        double t_hand = 1e300, t_gen = 1e300;
        for (int round = 0; round < 5; ++round) { // interleaved
            t_hand = std::min(t_hand, ns_per_call(states, 2, q, v, a_hand,
                                                  [&](const double* x, const double* y, double* z) { hand_accelerations(hp, x, y, z); }, 20));
            t_gen = std::min(t_gen, ns_per_call(states, 2, q, v, a_gen,
                                                [&](const double* x, const double* y, double* z) {
                                                    double_pendulum::accelerations(gp, 0.0, {x, 2}, {y, 2}, {z, 2});
                                                }, 20));
        }
        double diff = 0;
        for (std::size_t i = 0; i < a_hand.size(); ++i) diff = std::max(diff, std::fabs(a_hand[i] - a_gen[i]) / (1 + std::fabs(a_hand[i])));
        std::printf("bench_accelerations: double pendulum, %zu random states\n", states);
        std::printf("    hand-written closed form: %.1f ns per call\n", t_hand);
        std::printf("    phynjo generated:         %.1f ns per call\n", t_gen);
        std::printf("    largest relative difference of the results: %.2g\n", diff);
        std::printf("ratio accelerations_double_pendulum = %.2f\n", t_hand / t_gen);
    }
    {
        constexpr std::size_t n = nlink_cart_20::dof;
        const std::size_t m = 1024;
        std::vector<double> q(n * m), v(n * m), a(n * m);
        for (auto& x : q) x = 0.5 * u(rng);
        for (auto& x : v) x = 0.5 * u(rng);
        const nlink_cart_20::Parameters P;
        const double t = ns_per_call(m, n, q, v, a, [&](const double* x, const double* y, double* z) {
            nlink_cart_20::accelerations(P, 0.0, {x, n}, {y, n}, {z, n});
        }, 10);
        std::printf("nlink_cart_20 (%zu coordinates): %.2f us per accelerations call (target: under 5 us)\n", n, t / 1000);
    }
    return 0;
}
