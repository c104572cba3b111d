// Numeric rules and workflows: domains computed at build time, overlap errors that name the
// shared components, par bit-identical to seq, checked mode, tick semantics.
#include "property.hpp"

#include "phynjo/runtime/runtime.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace phynjo::runtime;
using phynjo::test::check_property;

namespace {

struct Fixture {
    Registry reg;
    std::shared_ptr<const Layout> layout;
    World world;
    explicit Fixture(int n) : world(make(n, reg, layout)) {}
    static World make(int n, Registry& reg, std::shared_ptr<const Layout>& layout) {
        for (int i = 0; i < n; ++i) reg.add("body" + std::to_string(i));
        World w = make_nstate(reg);
        layout = w.layout_ptr();
        for (Index i = 0; i < w.size(); ++i) {
            w.at(kQ, i) = 0.1 * i + 1;
            w.at(kP, i) = std::sin(i + 0.5);
        }
        return w;
    }
    /// q_i ← f(q_i, Σ p) for i in `set`: nonlinear, reads every p.
    NumericRule rule(const std::string& name, const ComponentSet& set, double salt) const {
        NumericRule r{name, Domain(kQ, set), Domain(kP, ComponentSet::range(0, static_cast<Index>(reg.size()))), nullptr,
                      layout};
        r.step = [set, salt](double dt, World& w) {
            double s = 0;
            for (Index i = 0; i < w.size(); ++i) s += w.at(kP, i);
            for (Index i : set.indices()) w.at(kQ, i) = std::sin(w.at(kQ, i) * salt + s) + dt * w.at(kQ, i);
        };
        return r;
    }
};

} // namespace

TEST_CASE("par over overlapping domains is rejected at build time, naming what is shared", "[runtime][workflow]") {
    Fixture f(4);
    using W = NumericWorkflow;
    const auto a = W::run(f.rule("left", ComponentSet{0, 1, 2}, 1.0));
    const auto b = W::run(f.rule("right", ComponentSet{2, 3}, 2.0));
    try {
        (void)W::par(a, b);
        FAIL("no exception");
    } catch (const DomainOverlapError& e) {
        CHECK(e.shared() == std::vector<std::string>{"q:body2"});
        CHECK(std::string(e.what()) == "par: branches [left] and [right] both write q:body2");
    }
    // nested: the overlap is found through seq
    const auto c = W::run(f.rule("c", ComponentSet{3}, 3.0));
    const auto d = W::run(f.rule("d", ComponentSet{1}, 4.0));
    CHECK_THROWS_AS(W::par(W::seq(c, d), a), DomainOverlapError);
    // a branch that writes what another reads is rejected too (the results would differ)
    NumericRule pw{"writes_p", Domain(kP, ComponentSet{0}), Domain(), [](double, World& w) { w.at(kP, 0) = 1; }, f.layout};
    try {
        (void)W::par(W::run(pw), c);
        FAIL("no exception");
    } catch (const DomainOverlapError& e) {
        CHECK(std::string(e.what()) == "par: branch [writes_p] writes p:body0, which branch [c] reads");
    }
    // disjoint: fine, and the workflow's domain is the union
    const auto ok = W::par(c, d);
    CHECK(ok.domain().components(kQ) == ComponentSet{1, 3});
    CHECK_THROWS_AS(NumericWorkflow::run(NumericRule{"empty", {}, {}, nullptr, f.layout}), Error);
}

TEST_CASE("par of disjoint rules is bit-identical to seq, on any number of threads", "[runtime][workflow]") {
    Executor two(2), four(4);
    check_property("par == seq", [&] {
        const int n = *rc::gen::inRange(2, 40);
        const int k = *rc::gen::inRange(2, 6);
        Fixture f(n);
        // a random partition of the components among k rules
        std::vector<std::vector<Index>> parts(static_cast<std::size_t>(k));
        for (Index i = 0; i < static_cast<Index>(n); ++i)
            parts[static_cast<std::size_t>(*rc::gen::inRange(0, k))].push_back(i);
        std::vector<NumericWorkflow> rules;
        for (int r = 0; r < k; ++r)
            rules.push_back(NumericWorkflow::run(f.rule("r" + std::to_string(r), ComponentSet(parts[static_cast<std::size_t>(r)]),
                                                        1.0 + r)));
        const auto par = NumericWorkflow::par(rules);
        const auto seq = NumericWorkflow::seq(rules);
        World w_seq = f.world, w_par1 = f.world, w_par2 = f.world, w_par4 = f.world;
        Stepper s_seq(seq), s_par1(par), s_par2(par, &two), s_par4(par, &four);
        for (int step = 0; step < 5; ++step) {
            s_seq.step(w_seq, 0.01);
            s_par1.step(w_par1, 0.01);
            s_par2.step(w_par2, 0.01);
            s_par4.step(w_par4, 0.01);
        }
        // fields bitwise equal (ticks differ: seq takes k ticks a step, par one)
        w_par1.tick = w_par2.tick = w_par4.tick = w_seq.tick;
        RC_ASSERT(w_par1 == w_seq);
        RC_ASSERT(w_par2 == w_seq);
        RC_ASSERT(w_par4 == w_seq);
    }, {.cases = 300});
}

TEST_CASE("ticks: seq adds, par takes the longest branch", "[runtime][workflow]") {
    Fixture f(3);
    using W = NumericWorkflow;
    const auto a = W::run(f.rule("a", ComponentSet{0}, 1)), b = W::run(f.rule("b", ComponentSet{1}, 2)),
               c = W::run(f.rule("c", ComponentSet{2}, 3));
    World w = f.world;
    Stepper(W::seq(a, b, c)).step(w, 0.1);
    CHECK(w.tick == 3);
    Stepper(W::par(W::seq(a, b), c)).step(w, 0.1);
    CHECK(w.tick == 5);
    CHECK(w.time == Approx(0.2));
}

TEST_CASE("checked mode catches a rule that writes outside its domain", "[runtime][workflow]") {
    Fixture f(3);
    NumericRule liar{"liar", Domain(kQ, ComponentSet{0}), Domain(), [](double, World& w) { w.at(kQ, 2) += 1; }, f.layout};
    Stepper s(NumericWorkflow::run(liar));
    World w = f.world;
    s.step(w, 0.1); // unchecked: nothing notices
    s.set_checked(true);
    try {
        s.step(w, 0.1);
        FAIL("no exception");
    } catch (const DomainViolation& e) {
        CHECK(std::string(e.what()) == "rule 'liar' changed q:body2, outside its declared domain");
    }
}

// Catches: a Stepper whose time is a running sum (3,000 steps of 1 ms end at 3 − 2.2e-13, so a
// controller's `t < 1.5` holds one step too long); a sequence that does not restart from a time
// set between steps, or from a new dt. The oracle: t = t0 + k·dt, rounded once.
TEST_CASE("Stepper: the time after k steps is t0 + k*dt, not a running sum", "[runtime][workflow]") {
    Fixture f(1);
    int before = 0; // steps that began with t < 1.5
    NumericRule controller{"controller", Domain(kQ, ComponentSet{0}), Domain(), [&before](double, World& w) {
                               if (w.time < 1.5) ++before;
                               w.at(kQ, 0) = w.time;
                           }, f.layout};
    Stepper s(NumericWorkflow::run(controller));
    World w = f.world;
    w.time = 0;
    for (int k = 0; k < 3000; ++k) s.step(w, 1e-3);
    CHECK(w.time == 3.0);
    CHECK(before == 1500);
    double sum = 0;
    for (int k = 0; k < 3000; ++k) sum += 1e-3;
    CHECK(sum != 3.0); // what a running sum gives
    // run() and run_guarded() are step() too; a time set between steps starts a new sequence
    w.time = 0.5;
    s.run(w, 1e-3, 1000);
    CHECK(w.time == 0.5 + 1000 * 1e-3);
    CHECK(s.run_guarded(w, 0.1, 7).completed);
    CHECK(w.time == (0.5 + 1000 * 1e-3) + 7 * 0.1);
}
