// Direct-summation N-body gravity (Plummer softening, G = 1), leapfrog DKD, N = 256, 1024,
// 4096: phynjo's workflow interpreter (drift · accelerations · kick · drift as rules, the
// pair sum as one rule or as par over two partitions) against the same pair kernel driven by
// hand, in the same run: a plain loop of drift, kick and drift on a structure of arrays, and
// for two threads persistent workers with per-thread accumulators and a barrier — what the
// workflow, its rules and its interpreter cost beyond the arithmetic.
//
// Prints ms per step, pairs per second, allocations per phynjo step, the largest difference
// between the two final states, and `ratio nbody_N_Tt = hand-written time / phynjo time`.
#include "phynjo/runtime/runtime.hpp"
#include "phynjo/runtime/particles/detail/pair_block.hpp"

#include <algorithm>
#include <atomic>
#include <barrier>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <new>
#include <random>
#include <thread>
#include <vector>

#include "../tests/support/counting_allocator.hpp"

using phynjo::test::allocations;

using namespace phynjo::runtime;

namespace {

constexpr double kEps = 1e-3, kDt = 1e-4;

// ---- the hand-written reference -------------------------------------------------------------

struct Soa {
    std::size_t n;
    std::vector<double> x, y, z, vx, vy, vz, m, ax, ay, az;
    explicit Soa(std::size_t n_) : n(n_), x(n), y(n), z(n), vx(n), vy(n), vz(n), m(n), ax(n), ay(n), az(n) {}
};

/// The pair sum: the runtime's own kernel, called by hand (so the ratio measures what the
/// workflow adds around it, not two spellings of the same loop).
void pairs(const double* x, const double* y, const double* z, const double* m, double* ax, double* ay, double* az,
           std::size_t begin, std::size_t end, std::size_t n) {
    phynjo::runtime::detail::pair_block(x, y, z, m, ax, ay, az, begin, end, n, kEps * kEps);
}

void drift(Soa& s, double h) {
    for (std::size_t i = 0; i < s.n; ++i) {
        s.x[i] += h * s.vx[i];
        s.y[i] += h * s.vy[i];
        s.z[i] += h * s.vz[i];
    }
}

void hand_step_1(Soa& s) {
    drift(s, 0.5 * kDt);
    std::fill(s.ax.begin(), s.ax.end(), 0.0);
    std::fill(s.ay.begin(), s.ay.end(), 0.0);
    std::fill(s.az.begin(), s.az.end(), 0.0);
    pairs(s.x.data(), s.y.data(), s.z.data(), s.m.data(), s.ax.data(), s.ay.data(), s.az.data(), 0, s.n, s.n);
    for (std::size_t i = 0; i < s.n; ++i) {
        s.vx[i] += kDt * s.ax[i];
        s.vy[i] += kDt * s.ay[i];
        s.vz[i] += kDt * s.az[i];
    }
    drift(s, 0.5 * kDt);
}

/// Two threads: the pair triangle split into two blocks of equal pair counts, one buffer set
/// per thread, a barrier, then the sum.
class HandTwoThreads {
public:
    explicit HandTwoThreads(Soa& s) : s_(s), b_(s.n), sync_(2) {
        double acc = 0;
        const double half = 0.25 * static_cast<double>(s.n) * static_cast<double>(s.n - 1);
        while (split_ < s.n && acc + static_cast<double>(s.n - 1 - split_) <= half) acc += static_cast<double>(s.n - 1 - split_++);
        worker_ = std::thread([this] {
            for (;;) {
                sync_.arrive_and_wait(); // start
                if (stop_) return;
                std::fill(b_.ax.begin(), b_.ax.end(), 0.0);
                std::fill(b_.ay.begin(), b_.ay.end(), 0.0);
                std::fill(b_.az.begin(), b_.az.end(), 0.0);
                pairs(s_.x.data(), s_.y.data(), s_.z.data(), s_.m.data(), b_.ax.data(), b_.ay.data(), b_.az.data(), split_,
                      s_.n, s_.n);
                sync_.arrive_and_wait(); // done
            }
        });
    }
    ~HandTwoThreads() {
        stop_ = true;
        sync_.arrive_and_wait();
        worker_.join();
    }
    void step() {
        drift(s_, 0.5 * kDt);
        sync_.arrive_and_wait();
        std::fill(s_.ax.begin(), s_.ax.end(), 0.0);
        std::fill(s_.ay.begin(), s_.ay.end(), 0.0);
        std::fill(s_.az.begin(), s_.az.end(), 0.0);
        pairs(s_.x.data(), s_.y.data(), s_.z.data(), s_.m.data(), s_.ax.data(), s_.ay.data(), s_.az.data(), 0, split_, s_.n);
        sync_.arrive_and_wait();
        for (std::size_t i = 0; i < s_.n; ++i) {
            s_.vx[i] += kDt * (s_.ax[i] + b_.ax[i]);
            s_.vy[i] += kDt * (s_.ay[i] + b_.ay[i]);
            s_.vz[i] += kDt * (s_.az[i] + b_.az[i]);
        }
        drift(s_, 0.5 * kDt);
    }

private:
    Soa& s_;
    Soa b_;
    std::size_t split_ = 0;
    std::barrier<> sync_;
    std::atomic<bool> stop_{false};
    std::thread worker_;
};

// ---- scene and timing -------------------------------------------------------------------------

Soa scene(std::size_t n) {
    Soa s(n);
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> u(-1, 1);
    for (std::size_t i = 0; i < n; ++i) {
        s.x[i] = u(rng);
        s.y[i] = u(rng);
        s.z[i] = u(rng);
        s.vx[i] = 0.1 * u(rng);
        s.vy[i] = 0.1 * u(rng);
        s.vz[i] = 0.1 * u(rng);
        s.m[i] = 1.0 / static_cast<double>(n);
    }
    return s;
}

World to_world(const Soa& s, int partitions) {
    Registry r;
    for (std::size_t i = 0; i < s.n; ++i) r.add("b" + std::to_string(i));
    World w = make_particles(r, partitions);
    for (Index i = 0; i < s.n; ++i) {
        w.at(kX, i) = s.x[i];
        w.at(kY, i) = s.y[i];
        w.at(kZ, i) = s.z[i];
        w.at(kVX, i) = s.vx[i];
        w.at(kVY, i) = s.vy[i];
        w.at(kVZ, i) = s.vz[i];
        w.at(kMass, i) = s.m[i];
    }
    return w;
}

/// Best seconds per step over `reps` runs of `steps` steps.
double time_per_step(const std::function<void()>& step, int steps, int reps) {
    double best = 1e300;
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < steps; ++k) step();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / steps);
    }
    return best;
}

} // namespace

int main() {
    std::printf("bench_nbody: direct N-body, leapfrog DKD, dt = %g, Plummer eps = %g\n", kDt, kEps);
    const NBodyGravity g{1.0, kEps};
    for (std::size_t n : {256u, 1024u, 4096u}) {
        const double npairs = 0.5 * static_cast<double>(n) * static_cast<double>(n - 1);
        const int steps = n <= 256 ? 2000 : n <= 1024 ? 200 : 16;
        for (int threads : {1, 2}) {
            Soa hand = scene(n);
            World w = to_world(hand, threads);
            Executor ex(static_cast<unsigned>(threads));
            Stepper phynjo(nbody_leapfrog(g, w.layout_ptr(), threads), threads > 1 ? &ex : nullptr);
            std::unique_ptr<HandTwoThreads> two;
            if (threads == 2) two = std::make_unique<HandTwoThreads>(hand);
            auto hand_step = [&] { threads == 1 ? hand_step_1(hand) : two->step(); };
            auto phynjo_step = [&] { phynjo.step(w, kDt); };
            // interleave the two measurements so that machine noise hits both alike
            double t_hand = 1e300, t_phynjo = 1e300;
            long allocs = 0;
            for (int round = 0; round < 3; ++round) {
                t_hand = std::min(t_hand, time_per_step(hand_step, steps, 1));
                const long a0 = allocations.load();
                t_phynjo = std::min(t_phynjo, time_per_step(phynjo_step, steps, 1));
                allocs += allocations.load() - a0;
            }
            double diff = 0;
            for (Index i = 0; i < n; ++i)
                diff = std::max({diff, std::fabs(w.at(kX, i) - hand.x[i]), std::fabs(w.at(kVZ, i) - hand.vz[i])});
            std::printf("N = %zu, %d thread%s\n", n, threads, threads > 1 ? "s" : "");
            std::printf("    hand-written: %.4f ms/step (%.0f M pairs/s)\n", t_hand * 1e3, npairs / t_hand / 1e6);
            std::printf("    phynjo:       %.4f ms/step (%.0f M pairs/s), %ld allocations in %d steps\n", t_phynjo * 1e3,
                        npairs / t_phynjo / 1e6, allocs, 3 * steps);
            std::printf("    same trajectory: largest |difference| of x and vz after %d steps: %.3g\n", 3 * steps, diff);
            std::printf("ratio nbody_%zu_%dt = %.2f\n", n, threads, t_hand / t_phynjo);
        }
    }
    return 0;
}
