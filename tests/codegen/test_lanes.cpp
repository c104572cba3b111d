// Runs in the lanes of SIMD registers: generated rk4_step_values_lanes, runtime/system/detail/lanes.hpp,
// and run_many, which steps a sweep's runs kWidth at a time.
// Bugs caught: a lane kernel that reads or writes another lane's component (a stride, a
// store, a load out of place), or computes something else than rk4_step_values; a vector
// sine whose lane depends on its neighbour (a run's bits would then depend on the run it was
// paired with, and a sweep's rows on the thread count); `as` losing −0; run_many giving a
// run another run's summary or trajectory, leaking one run's state into the next run of its
// slot, dropping a healthy run's step when its neighbour fails, or depending on the order or the
// grouping of the runs; run_many drifting from run_one beyond rounding; a lane reading another
// run's parameters (rk4_step_values_lanes_each, run_many's runs of their own systems), or runs
// of different models sharing the lanes of one kernel.
#include "bouncing_ball.hpp"
#include "coupled_balls.hpp"
#include "driven.hpp"
#include "flip_pendulum.hpp"
#include "incline.hpp"
#include "pendulum.hpp"
#include "physical_pendulum.hpp"
#include "two_balls.hpp"

#include "phynjo/runtime/simulate/ensemble.hpp"
#include "same_bits.hpp"
#include "phynjo/runtime/system/detail/lanes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace phynjo::runtime;
using phynjo::test::same_bits;
using phynjo::test::same_summary;
namespace L = phynjo::runtime::lanes;
constexpr std::size_t W = L::kWidth;

namespace {

/// |a − b| within `rel` of max(1, |a|) (rounding: libmvec's functions against libm's).
bool close(double a, double b, double rel) {
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
    return std::abs(a - b) <= rel * std::max(1.0, std::abs(a));
}

/// One lane of rk4_step_values_lanes' arrays.
struct LaneState {
    double t, h, t1;
    std::vector<double> q, v, a, g;
    double E = 0;
};

/// rk4_step_values_lanes on `lanes` (kWidth states); returns its result, the states updated.
template <class Fn>
bool call_lanes(Fn&& kernel, std::vector<LaneState>& lanes, std::size_t n, std::size_t ne) {
    std::vector<double> t(W), h(W), t1(W), q(n * W), v(n * W), a(n * W), e(W), g(ne * W);
    for (std::size_t l = 0; l < W; ++l) {
        t[l] = lanes[l].t;
        h[l] = lanes[l].h;
        t1[l] = lanes[l].t1;
        for (std::size_t i = 0; i < n; ++i) {
            q[i * W + l] = lanes[l].q[i];
            v[i * W + l] = lanes[l].v[i];
            a[i * W + l] = lanes[l].a[i];
        }
    }
    const bool ok = kernel(t.data(), h.data(), t1.data(), q.data(), v.data(), a.data(), e.data(), g.data());
    for (std::size_t l = 0; l < W; ++l) {
        for (std::size_t i = 0; i < n; ++i) {
            lanes[l].q[i] = q[i * W + l];
            lanes[l].v[i] = v[i * W + l];
            lanes[l].a[i] = a[i * W + l];
        }
        lanes[l].E = e[l];
        lanes[l].g.resize(ne);
        for (std::size_t k = 0; k < ne; ++k) lanes[l].g[k] = g[k * W + l];
    }
    return ok;
}

/// At random states of model NS, lane l with the parameters `vary(P, l)` makes from the defaults
/// (a no-op: every lane the defaults): each lane of one rk4_step_values_lanes_each call is its
/// state with its parameters alone (rk4_step_values_lanes, that state and those parameters in
/// every lane), bit for bit, and rk4_step_values with them within rounding (bit for bit
/// without libmvec). Every other trial puts one state in every lane, so that the lanes differ
/// by their parameters alone.
#define PHYNJO_LANES_AGREE(NS, vary)                                                                                   \
    do {                                                                                                               \
        namespace M = NS;                                                                                              \
        INFO(#NS);                                                                                                     \
        constexpr std::size_t n = M::dof, ne = M::n_events;                                                            \
        std::vector<M::Parameters> P(W);                                                                               \
        std::vector<const void*> each(W);                                                                              \
        for (std::size_t l = 0; l < W; ++l) {                                                                          \
            vary(P[l], l);                                                                                             \
            each[l] = &P[l];                                                                                           \
        }                                                                                                              \
        auto kernel = [&](auto... x) { return M::rk4_step_values_lanes_each(each.data(), x...); };                     \
        std::mt19937_64 rng(20261202);                                                                                 \
        std::uniform_real_distribution<double> d(-2.0, 2.0);                                                          \
        for (int trial = 0; trial < 50; ++trial) {                                                                     \
            std::vector<LaneState> lanes(W);                                                                           \
            for (std::size_t l = 0; l < W; ++l) {                                                                      \
                LaneState& s = lanes[l];                                                                               \
                s.q.resize(n);                                                                                         \
                s.v.resize(n);                                                                                         \
                s.a.resize(n);                                                                                         \
                for (auto& x : s.q) x = d(rng);                                                                        \
                for (auto& x : s.v) x = d(rng);                                                                        \
                s.t = 1 + d(rng);                                                                                      \
                s.h = 0.01 * (2.5 + d(rng));                                                                           \
                s.t1 = s.t + s.h;                                                                                      \
                if (trial % 2 == 1 && l > 0) {                                                                         \
                    s = lanes[0];                                                                                      \
                }                                                                                                      \
                M::accelerations(P[l], s.t, s.q, s.v, s.a);                                                            \
            }                                                                                                          \
            const std::vector<LaneState> start = lanes;                                                                \
            CHECK(call_lanes(kernel, lanes, n, ne));                                                                   \
            for (std::size_t l = 0; l < W; ++l) {                                                                      \
                INFO("lane " << l);                                                                                    \
                std::vector<LaneState> alone(W, start[l]);                                                             \
                CHECK(call_lanes([&](auto... x) { return M::rk4_step_values_lanes(P[l], x...); }, alone, n, ne));     \
                CHECK(same_bits(alone[0].q, lanes[l].q));                                                              \
                CHECK(same_bits(alone[0].v, lanes[l].v));                                                              \
                CHECK(same_bits(alone[0].a, lanes[l].a));                                                              \
                CHECK(same_bits(alone[0].g, lanes[l].g));                                                              \
                CHECK(same_bits(alone[0].E, lanes[l].E));                                                              \
                /* the scalar kernel */                                                                                \
                std::vector<double> q = start[l].q, v = start[l].v, a = start[l].a, g(ne);                             \
                double E = 0;                                                                                          \
                CHECK(M::rk4_step_values(P[l], start[l].t, start[l].h, start[l].t1, q, v, a, E, g));                   \
                for (std::size_t i = 0; i < n; ++i) {                                                                  \
                    CHECK(close(q[i], lanes[l].q[i], 1e-14));                                                          \
                    CHECK(close(v[i], lanes[l].v[i], 1e-14));                                                          \
                    CHECK(close(a[i], lanes[l].a[i], 1e-13));                                                          \
                }                                                                                                      \
                CHECK(close(E, lanes[l].E, 1e-14));                                                                    \
                for (std::size_t k = 0; k < ne; ++k) CHECK(close(g[k], lanes[l].g[k], 1e-14));                         \
                if (!L::kVectorMath) {                                                                                 \
                    CHECK(same_bits(q, lanes[l].q));                                                                   \
                    CHECK(same_bits(a, lanes[l].a));                                                                   \
                    CHECK(same_bits(E, lanes[l].E));                                                                   \
                }                                                                                                      \
            }                                                                                                          \
        }                                                                                                              \
    } while (0)

/// The defaults in every lane.
constexpr auto same = [](auto&, std::size_t) {};

/// A batch of runs of `sys`: run_many in order, reversed, and one at a time give every run the
/// same summary and trajectory, bit for bit; run_one agrees to `rel` (status, reason, the
/// events that fired; bit for bit without libmvec). Returns run_many's summaries.
/// With `systems`, run k is of its own system (RunStart::system; null: `sys`).
std::vector<RunSummary> check_batch(const LagrangianSystem& sys,
                                    const std::vector<std::vector<std::pair<std::size_t, double>>>& q0,
                                    const std::vector<std::vector<std::pair<std::size_t, double>>>& v0,
                                    const RunSettings& settings, double rel,
                                    const std::vector<const LagrangianSystem*>& systems = {}) {
    REQUIRE(sys.rk4_step_values_lanes_each);
    REQUIRE((systems.empty() || systems.size() == q0.size()));
    auto system_of = [&](std::size_t k) -> const LagrangianSystem& { return systems.empty() || !systems[k] ? sys : *systems[k]; };
    CHECK(sys.lane_width == W); // the model's width, as compiled (the same flags here)
    REQUIRE(settings.lanes);
    const std::size_t count = q0.size();
    auto many = [&](const std::vector<std::size_t>& order, std::vector<std::string>& rows) {
        std::vector<RunStart> starts;
        rows.assign(count, "");
        for (std::size_t k : order) starts.push_back({q0[k], v0[k], &rows[k], systems.empty() ? nullptr : systems[k]});
        std::vector<RunSummary> out(order.size()), by_run(count);
        std::vector<int> calls(order.size(), 0);
        run_many(sys, starts, settings, out, [&](std::size_t j) { ++calls[j]; });
        for (int c : calls) CHECK(c == 1); // `finished` once per run
        for (std::size_t j = 0; j < order.size(); ++j) by_run[order[j]] = out[j];
        return by_run;
    };
    std::vector<std::size_t> forward(count);
    for (std::size_t k = 0; k < count; ++k) forward[k] = k;
    std::vector<std::size_t> backward(forward.rbegin(), forward.rend());
    std::vector<std::string> rows_f, rows_b, rows_1;
    const std::vector<RunSummary> f = many(forward, rows_f), b = many(backward, rows_b);
    for (std::size_t k = 0; k < count; ++k) {
        INFO("run " << k);
        same_summary(f[k], b[k]);
        CHECK(rows_f[k] == rows_b[k]);
        std::vector<std::string> rows_k;
        const std::vector<RunSummary> one = many({k}, rows_k); // alone (its slot's neighbour repeats it)
        same_summary(f[k], one[k]);
        CHECK(rows_f[k] == rows_k[k]);
        const RunSummary r = run_one(system_of(k), q0[k], v0[k], settings);
        { // without lanes, run_many is run_one
            RunSettings plain = settings;
            plain.lanes = false;
            std::vector<RunSummary> p(1);
            const RunStart start{q0[k], v0[k], nullptr, systems.empty() ? nullptr : systems[k]};
            run_many(sys, std::span<const RunStart>(&start, 1), plain, p);
            same_summary(p[0], r);
        }
        CHECK(f[k].status == r.status);
        CHECK(f[k].reason == r.reason);
        if (r.status != RunSummary::Status::failed) {
            CHECK(close(f[k].t, r.t, rel));
            for (std::size_t i = 0; i < r.q.size(); ++i) {
                CHECK(close(f[k].q[i], r.q[i], rel));
                CHECK(close(f[k].qdot[i], r.qdot[i], rel));
            }
            for (std::size_t e = 0; e < r.first_event.size(); ++e) CHECK(close(f[k].first_event[e], r.first_event[e], rel));
        }
        if (!L::kVectorMath) same_summary(f[k], r);
    }
    return f;
}

/// `s` whose evaluations fail where q_0 > limit — accelerations throws there, the kernels
/// return false — in the scalar functions and the lane kernel alike: a run that fails in the
/// middle of a sweep, its neighbours healthy.
LagrangianSystem failing_above(LagrangianSystem s, double limit) {
    auto acc = s.accelerations;
    s.accelerations = [acc, limit](double t, std::span<const double> q, std::span<const double> v, std::span<double> a) {
        if (q[0] > limit) throw NonFiniteResult("synthetic: q0 above the limit");
        acc(t, q, v, a);
    };
    auto aeg = s.accelerations_energy_guards;
    s.accelerations_energy_guards = [aeg, limit](double t, std::span<const double> q, std::span<const double> v,
                                                 std::span<double> a, double& E, std::span<double> g) {
        return aeg(t, q, v, a, E, g) && !(q[0] > limit);
    };
    auto rsv = s.rk4_step_values;
    s.rk4_step_values = [rsv, limit](double t, double h, double t1, std::span<double> q, std::span<double> v,
                                     std::span<double> a, double& E, std::span<double> g) {
        return rsv(t, h, t1, q, v, a, E, g) && !(q[0] > limit);
    };
    auto lanes = s.rk4_step_values_lanes_each;
    s.rk4_step_values_lanes_each = [lanes, limit, width = s.lane_width](const void* const* P, const double* t, const double* h,
                                                                        const double* t1, double* q, double* v, double* a,
                                                                        double* E, double* g) {
        bool ok = lanes(P, t, h, t1, q, v, a, E, g);
        for (std::size_t l = 0; l < width; ++l) ok = ok && !(q[l] > limit); // q_0 of lane l
        return ok;
    };
    return s;
}

} // namespace

TEST_CASE("lanes.hpp: each lane is its own function value, wherever it sits and whatever its neighbour holds",
          "[lanes]") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> d(-40.0, 40.0);
    const double odd[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), 1e300,
                          -0.0, 1e-310};
    int checked = 0;
    for (int k = 0; k < 20000; ++k) {
        const double x = d(rng), y = k % 7 == 0 ? odd[k / 7 % 5] : d(rng);
        L::Lanes a{}, b{}, c{};
        for (std::size_t l = 0; l < W; ++l) {
            a[l] = l == 0 ? x : y;
            b[l] = l == 1 ? x : y;
            c[l] = x;
        }
        for (auto f : {+[](L::Lanes v) { return L::sin(v); }, +[](L::Lanes v) { return L::cos(v); },
                       +[](L::Lanes v) { return L::exp(v * 0.1); }, +[](L::Lanes v) { return L::log(L::fabs(v)); },
                       +[](L::Lanes v) { return L::pow(L::fabs(v), 1.3); }}) {
            const L::Lanes fa = f(a), fb = f(b), fc = f(c);
            CHECK(same_bits(fa[0], fb[1])); // the other lane
            CHECK(same_bits(fa[0], fc[0])); // another neighbour
            ++checked;
        }
    }
    CHECK(checked == 100000);
    // within 4 ulp of the exact value (long double), as libmvec promises; odd sine, even cosine
    for (int k = 0; k < 20000; ++k) {
        const double x = d(rng);
        L::Lanes arg{};
        for (std::size_t l = 0; l < W; ++l) arg[l] = l % 2 ? -x : x;
        const L::Lanes s = L::sin(arg), c = L::cos(arg);
        const long double es = std::sin(static_cast<long double>(x)), ec = std::cos(static_cast<long double>(x));
        auto ulp = [](long double e) { return std::nextafter(std::fabs(static_cast<double>(e)), 1e300) - std::fabs(static_cast<double>(e)); };
        CHECK(std::fabs(static_cast<double>(s[0] - es)) <= 4 * ulp(es));
        CHECK(std::fabs(static_cast<double>(c[0] - ec)) <= 4 * ulp(ec));
        CHECK(same_bits(s[1], -s[0]));
        CHECK(same_bits(c[1], c[0]));
    }
    // as<T> keeps −0 (an addition of +0 would not)
    CHECK(std::signbit(L::as<L::Lanes>(-0.0)[1]));
    CHECK(std::signbit(L::as<double>(-0.0)));
}

TEST_CASE("rk4_step_values_lanes: each lane is its run alone, bit for bit, and rk4_step_values to rounding",
          "[lanes][kernels]") {
    PHYNJO_LANES_AGREE(flip_pendulum, same);
    PHYNJO_LANES_AGREE(pendulum, same);
    PHYNJO_LANES_AGREE(driven, same);
    PHYNJO_LANES_AGREE(two_balls, same);
}

TEST_CASE("rk4_step_values_lanes_each: each lane with its own parameters is its run alone, bit for bit",
          "[lanes][kernels]") {
    PHYNJO_LANES_AGREE(flip_pendulum, [](flip_pendulum::Parameters& p, std::size_t lane) {
        p.g = 9.81 + 0.7 * static_cast<double>(lane);
        p.l2 = 1.0 / (1.0 + static_cast<double>(lane));
        p.m1 = 1.0 + 0.25 * static_cast<double>(lane * lane);
    });
    // I = Mp R²/2 follows Mp and R lane by lane, or is set in one lane
    PHYNJO_LANES_AGREE(physical_pendulum, [](physical_pendulum::Parameters& p, std::size_t lane) {
        p.Mp = 2.0 + static_cast<double>(lane);
        p.R = 0.5 - 0.1 * static_cast<double>(lane % 2);
        if (lane == 1) p.I = 0.77;
    });
    // sin(alpha) and the derived s0 = sin(alpha)/2 + 1/10: functions of the parameters alone
    PHYNJO_LANES_AGREE(incline, [](incline::Parameters& p, std::size_t lane) {
        p.alpha = 0.4 + 0.3 * static_cast<double>(lane);
        p.k = 3.0 + static_cast<double>(lane);
    });
    PHYNJO_LANES_AGREE(driven, [](driven::Parameters& p, std::size_t lane) {
        p.u = 0.3 - 0.2 * static_cast<double>(lane);
        p.w = 1.2 + 0.5 * static_cast<double>(lane);
    });
}

TEST_CASE("run_many: a run's summary and trajectory do not depend on its company, and are run_one's to rounding",
          "[lanes][ensemble]") {
    RunSettings settings;
    settings.every = 5;
    settings.lanes = true;
    SECTION("the flip map: flips, runs to the end, a singular and a non-finite start among them") {
        settings.t_end = 2;
        std::vector<std::vector<std::pair<std::size_t, double>>> q0, v0;
        for (double th1 = -3; th1 <= 3; th1 += 1.5)
            for (double th2 = -3; th2 <= 3; th2 += 2) {
                q0.push_back({{0, th1}, {1, th2}});
                v0.push_back({});
            }
        q0.push_back({{0, 0.3}});
        v0.push_back({{0, 1e160}}); // non-finite along the way
        const std::vector<RunSummary> r = check_batch(flip_pendulum::system({}), q0, v0, settings, 1e-9);
        int stopped = 0, finished = 0, failed = 0;
        for (const RunSummary& s : r) {
            stopped += s.status == RunSummary::Status::stopped;
            finished += s.status == RunSummary::Status::finished;
            failed += s.status == RunSummary::Status::failed;
        }
        CHECK(stopped > 3);
        CHECK(finished > 3);
        CHECK(failed == 1);
        flip_pendulum::Parameters massless;
        massless.m2 = 0;
        const std::vector<RunSummary> s = check_batch(flip_pendulum::system(massless), {{}, {{0, 1.0}}, {}}, {{}, {}, {}}, settings, 1e-9);
        for (const RunSummary& x : s) CHECK_THAT(x.reason, Catch::Contains("singular"));
        // runs whose values fail in the middle, beside healthy ones: each decides only its own steps
        std::vector<std::vector<std::pair<std::size_t, double>>> q1, v1;
        // (the healthy ones with large angles, where libmvec's sines and libm's differ in the
        // last bits: a neighbour's q'' re-evaluated by the scalar functions would show)
        const double start[][3] = {{-1.0, 2.8, 0.2}, {1.9, 0.3, 1.5}, {-0.5, -2.7, 0.2},
                                   {1.95, 0.3, 1.0}, {-1.2, 2.5, 0.2}, {0.3, -2.9, 0.2}};
        for (const auto& [th1, th2, w1] : start) {
            q1.push_back({{0, th1}, {1, th2}});
            v1.push_back({{0, w1}});
        }
        const std::vector<RunSummary> u = check_batch(failing_above(flip_pendulum::system({}), 1.99), q1, v1, settings, 1e-9);
        int synthetic = 0;
        for (const RunSummary& x : u) synthetic += x.reason.find("synthetic") != std::string::npos;
        CHECK(synthetic >= 1);
        CHECK(synthetic <= 4);
    }
    SECTION("events with resets: bounces to rest, a reset writing the other ball's velocity, a hold") {
        settings.t_end = 3;
        settings.events.rest_speed = 0.05;
        check_batch(bouncing_ball::system({}), {{}, {{0, 2.0}}, {{0, 0.5}}}, {{}, {}, {{0, 1.0}}}, settings, 1e-9);
        settings.events.rest_speed = 0;
        settings.t_end = 2.5;
        check_batch(two_balls::system({}), {{}, {}, {{0, 1.2}}}, {{{1, 1.5}}, {}, {{1, -0.5}}}, settings, 1e-9);
        settings.t_end = 6;
        settings.events.rest_speed = 0.3;
        check_batch(coupled_balls::system({}), {{}, {{1, 0.8}}}, {{}, {}}, settings, 1e-9);
    }
    SECTION("no events, a last step shorter than dt, time-dependent forces") {
        settings.t_end = 2.355;
        settings.dt = 0.01;
        check_batch(pendulum::system({}), {{{0, 2.5}}, {{0, -1.0}}, {{0, 3.0}}}, {{}, {}, {}}, settings, 1e-11);
        check_batch(driven::system({}), {{}, {{0, 0.2}}}, {{{0, 0.3}}, {}}, settings, 1e-11);
    }
}

TEST_CASE("run_many: runs of their own systems (a parameter sweep) share the lanes, each its own run",
          "[lanes][ensemble]") {
    RunSettings settings;
    settings.every = 5;
    settings.lanes = true;
    SECTION("the flip map over g, l2 and m1: flips, finishes, a singular system among them") {
        settings.t_end = 2;
        std::vector<LagrangianSystem> owned;
        std::vector<std::vector<std::pair<std::size_t, double>>> q0, v0;
        for (int k = 0; k < 9; ++k) {
            flip_pendulum::Parameters p;
            p.g = 4.0 + 1.5 * k;
            p.l2 = 0.5 + 0.1 * (k % 4);
            p.m1 = k == 6 ? 0.0 : 1.0 + 0.2 * (k % 3); // k = 6: m1 = 0 …
            if (k == 6) p.m2 = 0.0;                      // … and m2 = 0: M is singular
            owned.push_back(flip_pendulum::system(p));
            q0.push_back({{0, k % 2 ? 2.9 : 0.5}, {1, k % 2 ? -2.8 : 0.3 * k}}); // odd k near the top: flips
            v0.push_back({});
        }
        std::vector<const LagrangianSystem*> systems;
        for (const auto& s : owned) systems.push_back(&s);
        const std::vector<RunSummary> r = check_batch(flip_pendulum::system({}), q0, v0, settings, 1e-9, systems);
        int stopped = 0, finished = 0, failed = 0;
        for (const RunSummary& s : r) {
            stopped += s.status == RunSummary::Status::stopped;
            finished += s.status == RunSummary::Status::finished;
            failed += s.status == RunSummary::Status::failed;
        }
        CHECK(stopped >= 2);
        CHECK(finished >= 2);
        CHECK(failed == 1);
        // a system of the default parameters, or none (run_many's own): the same bits
        const LagrangianSystem defaults = flip_pendulum::system({});
        const std::pair<std::size_t, double> q[] = {{0, 1.5}, {1, -0.5}};
        std::vector<RunStart> starts{{q, {}, nullptr, &owned[0]}, {q, {}, nullptr, &defaults}, {q, {}, nullptr, nullptr}};
        std::vector<RunSummary> out(3);
        run_many(flip_pendulum::system({}), starts, settings, out);
        same_summary(out[1], out[2]);
        CHECK(!same_bits(out[0].q, out[1].q)); // other parameters, another run
    }
    SECTION("derived parameters following their definitions lane by lane, or set; functions of parameters alone") {
        settings.t_end = 3;
        std::vector<LagrangianSystem> owned;
        std::vector<std::vector<std::pair<std::size_t, double>>> q0, v0;
        for (int k = 0; k < 5; ++k) {
            physical_pendulum::Parameters p;
            p.Mp = 1.0 + k;
            if (k == 3) p.I = 0.05;
            owned.push_back(physical_pendulum::system(p));
            q0.push_back({{0, 0.5 + 0.4 * k}});
            v0.push_back({});
        }
        std::vector<const LagrangianSystem*> systems;
        for (const auto& s : owned) systems.push_back(&s);
        check_batch(physical_pendulum::system({}), q0, v0, settings, 1e-11, systems);
        std::vector<LagrangianSystem> inclines;
        for (int k = 0; k < 6; ++k) {
            incline::Parameters p;
            p.alpha = -1.2 + 0.5 * k;
            inclines.push_back(incline::system(p));
        }
        std::vector<const LagrangianSystem*> incline_systems;
        for (const auto& s : inclines) incline_systems.push_back(&s);
        check_batch(incline::system({}), std::vector<std::vector<std::pair<std::size_t, double>>>(6),
                    std::vector<std::vector<std::pair<std::size_t, double>>>(6), settings, 1e-11, incline_systems);
    }
    SECTION("runs of different models never share a kernel: each is run_one's, bit for bit") {
        settings.t_end = 1;
        const LagrangianSystem flip = flip_pendulum::system({}), pend = pendulum::system({});
        const std::pair<std::size_t, double> q[] = {{0, 1.0}};
        std::vector<RunStart> starts{{q, {}, nullptr, &flip}, {q, {}, nullptr, &pend}, {q, {}, nullptr, &flip}};
        std::vector<RunSummary> out(3);
        run_many(flip, starts, settings, out);
        same_summary(out[0], run_one(flip, q, {}, settings));
        same_summary(out[1], run_one(pend, q, {}, settings));
        same_summary(out[2], out[0]);
    }
}
