// N-body gravity: a Kepler orbit over 1,000 orbits, momentum conservation, adaptive steps,
// and a determinism hash that does not depend on the thread count.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include "scenes.hpp"

#include <cmath>
#include <random>

using namespace phynjo::runtime;

namespace {

/// Two bodies (M = 1, m = 1e-3) on a Kepler orbit of semi-major axis 1 and eccentricity e,
/// starting at apocentre, centre of mass at rest at the origin. G = 1.
World kepler(double e, double& period) {
    Registry r;
    r.add("sun");
    r.add("planet");
    World w = make_particles(r);
    const double M = 1, m = 1e-3, a = 1, mu = M + m;
    const double ra = a * (1 + e), va = std::sqrt(mu * (1 - e) / ra);
    w.at(kMass, 0) = M;
    w.at(kMass, 1) = m;
    w.at(kX, 0) = -m / mu * ra;
    w.at(kX, 1) = M / mu * ra;
    w.at(kVY, 0) = -m / mu * va;
    w.at(kVY, 1) = M / mu * va;
    period = 2 * M_PI * std::sqrt(a * a * a / mu);
    return w;
}

World cluster(int n, std::uint32_t seed, int partitions) { return phynjo::test::random_cluster(n, seed, partitions); }

} // namespace

TEST_CASE("Kepler orbit, e = 0.5: leapfrog keeps the energy bounded over 1,000 orbits", "[runtime][nbody]") {
    double period;
    World w = kepler(0.5, period);
    const NBodyGravity g{1.0, 1e-3};
    Stepper s(nbody_leapfrog(g, w.layout_ptr()));
    const int per_orbit = 1000;
    const double dt = period / per_orbit;
    const double e0 = nbody_energy(w, g);
    double first = 0, last = 0, r_max = 0, r_min = 1e300; // separations over the last orbit
    for (int orbit = 0; orbit < 1000; ++orbit) {
        for (int k = 0; k < per_orbit; ++k) {
            s.step(w, dt);
            if (orbit == 999) {
                const double r = std::hypot(w.at(kX, 1) - w.at(kX, 0), w.at(kY, 1) - w.at(kY, 0));
                r_max = std::max(r_max, r);
                r_min = std::min(r_min, r);
            }
            if (k % 50 == 0) {
                const double err = std::fabs((nbody_energy(w, g) - e0) / e0);
                if (orbit < 100) first = std::max(first, err);
                if (orbit >= 900) last = std::max(last, err);
            }
        }
    }
    INFO("max relative energy error: orbits 0-99 " << first << ", orbits 900-999 " << last);
    CHECK(first < 1e-4);
    CHECK(last < 1.2 * first); // bounded: no secular drift
    // The orbit is still the same ellipse after 1,000 orbits: apocentre a(1 + e) = 1.5 and
    // pericentre a(1 − e) = 0.5 within 1e-3 (catches a drift of a or e, e.g. an asymmetric
    // kick, that a bounded energy error alone would not show).
    INFO("last orbit: apocentre " << r_max << ", pericentre " << r_min);
    CHECK(std::abs(r_max - 1.5) < 1e-3);
    CHECK(std::abs(r_min - 0.5) < 1e-3);
}

TEST_CASE("isolated N-body system: total momentum conserved to round-off", "[runtime][nbody]") {
    World w = cluster(100, 42, 1);
    const NBodyGravity g{1.0, 1e-2};
    const Vec3 p0 = nbody_momentum(w);
    double scale = 0;
    for (Index i = 0; i < w.size(); ++i) scale += w.at(kMass, i) * std::hypot(w.at(kVX, i), w.at(kVY, i), w.at(kVZ, i));
    Stepper(nbody_leapfrog(g, w.layout_ptr())).run(w, 1e-3, 2000);
    const Vec3 p1 = nbody_momentum(w);
    for (int k = 0; k < 3; ++k) CHECK(std::fabs(p1[static_cast<std::size_t>(k)] - p0[static_cast<std::size_t>(k)]) < 1e-13 * scale);
}

TEST_CASE("the pair sum split into partitions agrees with the single sum", "[runtime][nbody]") {
    const NBodyGravity g{1.0, 1e-2};
    World one = cluster(77, 7, 1), three = cluster(77, 7, 3);
    Stepper(nbody_accelerations(g, one.layout_ptr(), 1)).step(one, 0);
    Stepper(nbody_accelerations(g, three.layout_ptr(), 3)).step(three, 0);
    for (Index i = 0; i < one.size(); ++i)
        for (FieldId f : {kAX, kAY, kAZ}) CHECK(three.at(f, i) == Approx(one.at(f, i)).epsilon(1e-12));
    // and against a brute-force oracle without the third law
    for (Index i = 0; i < one.size(); ++i) {
        double a[3] = {0, 0, 0};
        for (Index j = 0; j < one.size(); ++j) {
            if (j == i) continue;
            const double d[3] = {one.at(kX, j) - one.at(kX, i), one.at(kY, j) - one.at(kY, i), one.at(kZ, j) - one.at(kZ, i)};
            const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 1e-4;
            for (int k = 0; k < 3; ++k) a[k] += one.at(kMass, j) * d[k] / (r2 * std::sqrt(r2));
        }
        CHECK(one.at(kAX, i) == Approx(a[0]).epsilon(1e-11));
        CHECK(one.at(kAZ, i) == Approx(a[2]).epsilon(1e-11));
    }
}

TEST_CASE("determinism: a 10,000-step N-body run hashes the same on 1, 2 and 4 threads", "[runtime][nbody][determinism]") {
    const NBodyGravity g{1.0, 1e-2};
    std::vector<std::uint64_t> hashes;
    for (unsigned threads : {0u, 1u, 2u, 4u}) {
        World w = cluster(64, 2026, 4);
        Executor ex(threads);
        Stepper s(nbody_leapfrog(g, w.layout_ptr(), 4), threads ? &ex : nullptr);
        s.run(w, 1e-3, 10000);
        hashes.push_back(w.hash());
    }
    CHECK(hashes[1] == hashes[0]);
    CHECK(hashes[2] == hashes[0]);
    CHECK(hashes[3] == hashes[0]);
    // and the same inputs give the same hash again
    World w = cluster(64, 2026, 4);
    Stepper(nbody_leapfrog(g, w.layout_ptr(), 4)).run(w, 1e-3, 10000);
    CHECK(w.hash() == hashes[0]);
}

TEST_CASE("adaptive velocity Verlet: small steps at pericentre, better energy per force evaluation", "[runtime][nbody]") {
    double period;
    const NBodyGravity g{1.0, 1e-3};
    World w = kepler(0.9, period);
    AdaptiveVerlet av(g, w.layout_ptr(), {.eta = 0.005, .dt_min = 1e-7, .dt_max = period / 50});
    av.prepare(w);
    const double e0 = nbody_energy(w, g);
    int steps = 0;
    double dt_min = 1e9, dt_max = 0, adaptive_err = 0;
    while (w.time < 10 * period) {
        const double dt = av.step(w);
        dt_min = std::min(dt_min, dt);
        dt_max = std::max(dt_max, dt);
        ++steps;
        adaptive_err = std::max(adaptive_err, std::fabs((nbody_energy(w, g) - e0) / e0));
    }
    CHECK(dt_max > 10 * dt_min); // the controller does adapt (pericentre is 19× closer)
    // A fixed step with the same number of force evaluations: its error peaks at every
    // pericentre passage. Compare the largest error along the run.
    World f = kepler(0.9, period);
    Stepper fixed(nbody_leapfrog(g, f.layout_ptr()));
    double fixed_err = 0;
    for (int k = 0; k < steps; ++k) {
        fixed.step(f, 10 * period / steps);
        fixed_err = std::max(fixed_err, std::fabs((nbody_energy(f, g) - e0) / e0));
    }
    INFO("steps " << steps << ", largest energy error: adaptive " << adaptive_err << ", fixed " << fixed_err);
    CHECK(adaptive_err < 0.2 * fixed_err);
    CHECK(adaptive_err < 1e-3);
}
