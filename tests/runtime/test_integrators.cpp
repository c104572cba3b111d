// Integrators: measured convergence orders, energy errors O(dt²) per step over random
// worlds, bounded energy of the symplectic schemes over long runs.
#include "property.hpp"

#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numeric>

using namespace phynjo::runtime;
using phynjo::test::check_property;

namespace {

/// Harmonic oscillator m = 1, k = 1: q(t) = cos t, p(t) = −sin t.
struct Oscillator {
    Registry reg;
    World w;
    Force1D force;
    ComponentSet bodies{0};
    Oscillator() : w(init(reg)), force(Force1D::anchor(0, 0.0, 1.0)) {}
    static World init(Registry& r) {
        r.add("mass");
        World w = make_nstate(r, {1.0}, rk4_fields());
        w.at(kQ, 0) = 1;
        return w;
    }
};

enum class Scheme { Euler, LeapfrogDKD, LeapfrogKDK, ForestRuth, RK4 };

NumericWorkflow build(Scheme s, const Force1D& f, const ComponentSet& bodies, const std::shared_ptr<const Layout>& layout) {
    const Splitting sp = nstate_splitting(f, bodies, layout);
    switch (s) {
    case Scheme::Euler: return symplectic_euler(sp);
    case Scheme::LeapfrogDKD: return leapfrog_dkd(sp);
    case Scheme::LeapfrogKDK: return leapfrog_kdk(sp);
    case Scheme::ForestRuth: return forest_ruth(sp);
    case Scheme::RK4: return rk4(f, bodies, layout);
    }
    return symplectic_euler(sp);
}

/// Least-squares slope of log(error) against log(dt).
double slope(const std::vector<double>& dts, const std::vector<double>& errs) {
    const std::size_t n = dts.size();
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double x = std::log(dts[i]), y = std::log(errs[i]);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace

TEST_CASE("measured convergence orders: 1, 2, 2, 4, 4", "[runtime][integrators]") {
    const double T = 3.0;
    const std::pair<Scheme, double> cases[] = {{Scheme::Euler, 1}, {Scheme::LeapfrogDKD, 2}, {Scheme::LeapfrogKDK, 2},
                                               {Scheme::ForestRuth, 4}, {Scheme::RK4, 4}};
    for (const auto& [scheme, order] : cases) {
        std::vector<double> dts, errs;
        for (int steps : {30, 60, 120, 240}) {
            Oscillator o;
            Stepper s(build(scheme, o.force, o.bodies, o.w.layout_ptr()));
            const double dt = T / steps;
            s.run(o.w, dt, static_cast<std::size_t>(steps));
            dts.push_back(dt);
            errs.push_back(std::hypot(o.w.at(kQ, 0) - std::cos(T), o.w.at(kP, 0) + std::sin(T)));
        }
        INFO("scheme " << static_cast<int>(scheme) << " errors " << errs[0] << " … " << errs[3]);
        CHECK(std::fabs(slope(dts, errs) - order) < 0.2);
    }
}

TEST_CASE("energy after one step is E + O(dt²) over random worlds", "[runtime][integrators]") {
    // The law totalEnergy (step dt w) = totalEnergy w + O(dt²): |ΔE(h)|/h² must stay
    // bounded as h shrinks (an O(dt) error would double it at every halving).
    check_property("|ΔE(h)|/h² bounded", [] {
        const int n = *rc::gen::inRange(1, 6);
        Registry reg;
        for (int i = 0; i < n; ++i) reg.add("b" + std::to_string(i));
        std::vector<double> masses;
        for (int i = 0; i < n; ++i) masses.push_back(*rc::gen::inRange(1, 50) / 10.0);
        World w0 = make_nstate(reg, masses, rk4_fields());
        Force1D f = Force1D::anchor(0, 0.0, *rc::gen::inRange(1, 100) / 10.0);
        for (Index i = 0; i + 1 < static_cast<Index>(n); ++i)
            f = f + Force1D::spring(i, i + 1, *rc::gen::inRange(1, 100) / 10.0, *rc::gen::inRange(0, 20) / 10.0);
        f = f + Force1D::gravity(9.81, ComponentSet::range(0, static_cast<Index>(n)));
        for (Index i = 0; i < static_cast<Index>(n); ++i) {
            w0.at(kQ, i) = i * 1.5 + *rc::gen::inRange(-50, 50) / 100.0;
            w0.at(kP, i) = *rc::gen::inRange(-100, 100) / 50.0;
        }
        const auto scheme = *rc::gen::element(Scheme::Euler, Scheme::LeapfrogDKD, Scheme::ForestRuth, Scheme::RK4);
        const double e0 = total_energy(w0, f);
        // |ΔE(h)|/h² at h = 0.02 … 0.00125; the error curve of a scheme can cross zero at some
        // h, so the finest ratio is compared with the largest coarser one. Round-off (1e-13 of
        // the energy) counts as zero.
        const double hs[] = {2e-2, 1e-2, 5e-3, 2.5e-3, 1.25e-3};
        double coarse = 0, finest = 0;
        for (double h : hs) {
            World w = w0;
            Stepper s(build(scheme, f, ComponentSet::range(0, static_cast<Index>(n)), w.layout_ptr()));
            s.step(w, h);
            const double de = std::max(0.0, std::fabs(total_energy(w, f) - e0) - 1e-13 * (std::fabs(e0) + 1));
            if (h == hs[4]) finest = de / (h * h);
            else coarse = std::max(coarse, de / (h * h));
        }
        RC_ASSERT(finest <= 1.5 * coarse);
    }, {.cases = 300});
}

TEST_CASE("symplectic schemes keep the energy bounded while RK4 drifts", "[runtime][integrators]") {
    const double dt = 0.1;
    const std::size_t steps = 200000; // ~3,200 periods
    auto run = [&](Scheme scheme) {
        Oscillator o;
        Stepper s(build(scheme, o.force, o.bodies, o.w.layout_ptr()));
        const double e0 = total_energy(o.w, o.force);
        double early = 0, late = 0;
        for (std::size_t i = 0; i < steps; ++i) {
            s.step(o.w, dt);
            const double err = std::fabs(total_energy(o.w, o.force) - e0) / e0;
            if (i < steps / 10) early = std::max(early, err);
            if (i >= steps - steps / 10) late = std::max(late, err);
        }
        return std::pair{early, late};
    };
    for (Scheme s : {Scheme::Euler, Scheme::LeapfrogDKD, Scheme::ForestRuth}) {
        const auto [early, late] = run(s);
        INFO("scheme " << static_cast<int>(s) << ": max error in the first tenth " << early << ", in the last " << late);
        CHECK(late < 1.05 * early + 1e-15); // no drift
        CHECK(late < (s == Scheme::Euler ? 0.06 : 3e-3));
    }
    const auto [early, late] = run(Scheme::RK4);
    CHECK(late > 5 * early); // RK4 is not symplectic: its error grows
}
