// The forces DSL against analytic solutions and conservation laws.
#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace phynjo::runtime;

TEST_CASE("uniform gravity: leapfrog is exact for a constant force", "[runtime][forces]") {
    Registry r;
    r.add("apple");
    World w = make_nstate(r, {0.2});
    w.at(kQ, 0) = 10;
    w.at(kP, 0) = 0.2 * 3; // 3 m/s up
    const Force1D f = Force1D::gravity(9.81, ComponentSet{0});
    Stepper(leapfrog_kdk(nstate_splitting(f, ComponentSet{0}, w.layout_ptr()))).run(w, 0.01, 100);
    CHECK(w.at(kQ, 0) == Approx(10 + 3 * 1.0 - 0.5 * 9.81 * 1.0).epsilon(1e-12));
    CHECK(w.at(kP, 0) / 0.2 == Approx(3 - 9.81).epsilon(1e-12));
}

TEST_CASE("linear drag: velocity decays as exp(−γt/m)", "[runtime][forces]") {
    Registry r;
    r.add("bead");
    World w = make_nstate(r, {2.0}, rk4_fields());
    w.at(kP, 0) = 2.0 * 5; // 5 m/s
    const Force1D f = Force1D::drag(0.5, ComponentSet{0});
    Stepper(rk4(f, ComponentSet{0}, w.layout_ptr())).run(w, 0.01, 400); // 4 s
    CHECK(w.at(kP, 0) / 2.0 == Approx(5 * std::exp(-0.5 * 4 / 2.0)).epsilon(1e-9));
    // the distance travelled: (m v0/γ)(1 − e^{−γt/m})
    CHECK(w.at(kQ, 0) == Approx(2.0 * 5 / 0.5 * (1 - std::exp(-1.0))).epsilon(1e-9));
}

TEST_CASE("springs: momentum and energy of an isolated chain", "[runtime][forces]") {
    Registry r;
    r.add("a");
    r.add("b");
    r.add("c");
    World w = make_nstate(r, {1.0, 3.0, 2.0});
    w.at(kQ, 1) = 1.3;
    w.at(kQ, 2) = 3.0;
    w.at(kP, 0) = 0.5;
    const ComponentSet all = ComponentSet::range(0, 3);
    const Force1D f = Force1D::spring(0, 1, 4.0, 1.0) + 0.5 * Force1D::spring(1, 2, 2.0, 1.5);
    const double e0 = total_energy(w, f), p0 = total_momentum(w);
    Stepper s(forest_ruth(nstate_splitting(f, all, w.layout_ptr())));
    double worst = 0;
    for (int k = 0; k < 20000; ++k) {
        s.step(w, 1e-3);
        worst = std::max(worst, std::fabs(total_energy(w, f) - e0));
    }
    CHECK(std::fabs(total_momentum(w) - p0) < 1e-13); // internal forces only
    CHECK(worst < 1e-10 * std::fabs(e0));
    // the scaled spring really is half as stiff
    World probe = make_nstate(r);
    probe.at(kQ, 2) = 2.5; // b at 0: stretched by 1 m
    std::vector<double> F(3, 0.0);
    (0.5 * Force1D::spring(1, 2, 2.0, 1.5)).accumulate(probe, F);
    CHECK(F[2] == Approx(-1.0));
    CHECK(F[1] == Approx(1.0));
}

TEST_CASE("1-D Newtonian gravity: escape follows v² = v∞² + 2G(m1+m2)/d", "[runtime][forces]") {
    Registry r;
    r.add("m1");
    r.add("m2");
    const double G = 0.5, m1 = 2, m2 = 1, d0 = 1, v0 = 2; // v0² = 4 > 2G(m1+m2)/d0 = 3: escapes
    World w = make_nstate(r, {m1, m2});
    w.at(kQ, 1) = d0;
    w.at(kP, 0) = -m1 * v0 * m2 / (m1 + m2); // centre of mass at rest, relative speed v0
    w.at(kP, 1) = m2 * v0 * m1 / (m1 + m2);
    const Force1D f = Force1D::newtonian(G, ComponentSet{0, 1});
    Stepper(forest_ruth(nstate_splitting(f, ComponentSet{0, 1}, w.layout_ptr()))).run(w, 1e-3, 20000);
    const double d = w.at(kQ, 1) - w.at(kQ, 0), v = w.at(kP, 1) / m2 - w.at(kP, 0) / m1;
    CHECK(d > 5);
    CHECK(v * v == Approx(v0 * v0 - 2 * G * (m1 + m2) / d0 + 2 * G * (m1 + m2) / d).epsilon(1e-10));
    CHECK(std::fabs(total_momentum(w)) < 1e-14);
}

TEST_CASE("custom forces and the kick's domain", "[runtime][forces]") {
    Registry r;
    r.add("a");
    r.add("b");
    World w = make_nstate(r);
    const Force1D f = Force1D::custom("push", ComponentSet{1}, ComponentSet{0},
                                      [](const World& s, std::span<double> F) { F[1] += 2 * s.at(kQ, 0); });
    w.at(kQ, 0) = 3;
    const NumericRule k = kick(f, 1.0, w.layout_ptr());
    CHECK(k.domain.components(kP) == ComponentSet{1});
    CHECK(k.reads.components(kQ) == ComponentSet{0});
    Stepper(NumericWorkflow::run(k)).step(w, 0.5);
    CHECK(w.at(kP, 1) == Approx(3.0));
    CHECK(w.at(kP, 0) == 0.0);
}

TEST_CASE("Force3D: springs are equal and opposite, forces add and scale", "[runtime][forces]") {
    Registry r;
    r.add("p");
    r.add("q");
    World w = make_particles(r);
    w.at(kX, 1) = 3;
    w.at(kY, 1) = 4; // |r| = 5
    w.at(kMass, 0) = w.at(kMass, 1) = 2;
    const Force3D spring = Force3D::spring(0, 1, 10.0, 4.0); // stretched by 1: |F| = 10
    const State3D s = state3d(w);
    const auto [f0, t0] = spring(s, 0);
    const auto [f1, t1] = spring(s, 1);
    CHECK(f0[0] == Approx(6.0));
    CHECK(f0[1] == Approx(8.0));
    for (int k = 0; k < 3; ++k) CHECK(f0[static_cast<std::size_t>(k)] == Approx(-f1[static_cast<std::size_t>(k)]));
    const Force3D both = spring + 2.0 * Force3D::gravity(9.81);
    CHECK(both(s, 0).first[1] == Approx(8.0 - 2 * 2 * 9.81));
    // lowered to a rule on a particle world: v += dt F/m
    Stepper(NumericWorkflow::run(kick3d(both, 1.0, w.layout_ptr()))).step(w, 0.1);
    CHECK(w.at(kVY, 0) == Approx(0.1 * (8.0 - 4 * 9.81) / 2));
    CHECK(w.at(kVX, 1) == Approx(-0.1 * 6.0 / 2));
}
