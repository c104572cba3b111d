#include "phynjo/runtime/numeric.hpp"

#include <cmath>
#include <stdexcept>

namespace phynjo::runtime {

Action<World> to_action(const NumericRule& rule) {
    Action<World> a;
    a.name = rule.name;
    a.writes = rule.domain;
    a.reads = rule.reads;
    a.layout = rule.layout;
    a.run = [step = rule.step](World& w, const StepContext& ctx) { step(ctx.dt, w); };
    return a;
}

NumericWorkflow NumericWorkflow::run(const NumericRule& rule) {
    if (!rule.step) throw Error("numeric rule '" + rule.name + "' has no step function");
    return NumericWorkflow(Process<World>::act(to_action(rule)));
}

NumericWorkflow NumericWorkflow::seq(std::vector<NumericWorkflow> parts) {
    std::vector<Process<World>> ps;
    for (auto& p : parts) ps.push_back(p.process_);
    return NumericWorkflow(Process<World>::seq(std::move(ps)));
}

NumericWorkflow NumericWorkflow::par(std::vector<NumericWorkflow> parts) {
    std::vector<Process<World>> ps;
    for (auto& p : parts) ps.push_back(p.process_);
    return NumericWorkflow(Process<World>::par(std::move(ps)));
}

RunReport Stepper::run_guarded(World& world, double dt, std::size_t steps) {
    RunReport r;
    auto stop = [&](std::string reason) {
        r.completed = false;
        r.reason = std::move(reason);
        r.tick = world.tick;
        r.time = world.time;
    };
    if (!std::isfinite(dt)) {
        stop("the step dt is not finite");
        return r;
    }
    for (std::size_t k = 0; k < steps; ++k) {
        try {
            interpreter_.step(world, dt);
        } catch (const std::exception& e) {
            stop(std::string("a rule failed: ") + e.what());
            return r;
        }
        for (const auto& [f, set] : writes_.parts())
            for (Index i : set.indices())
                if (!std::isfinite(world.at(f, i))) {
                    r.where = world.layout().describe(f, i);
                    stop(r.where + " became " + (std::isnan(world.at(f, i)) ? "NaN" : "infinite") + " at tick " +
                         std::to_string(world.tick) + " (t = " + std::to_string(world.time) + " s)");
                    return r;
                }
        r.steps = k + 1;
    }
    r.tick = world.tick;
    r.time = world.time;
    return r;
}

World make_nstate(const Registry& components, const std::vector<double>& masses,
                  const std::vector<std::string>& extra_fields) {
    std::vector<std::string> fields{"q", "p", "m"};
    fields.insert(fields.end(), extra_fields.begin(), extra_fields.end());
    auto layout = std::make_shared<Layout>(components, std::move(fields));
    World w(layout);
    if (!masses.empty() && masses.size() != w.size())
        throw std::invalid_argument("make_nstate: " + std::to_string(masses.size()) + " masses for " +
                                    std::to_string(w.size()) + " components");
    for (Index i = 0; i < w.size(); ++i) {
        const double m = masses.empty() ? 1.0 : masses[i];
        if (!(m > 0) || !std::isfinite(m))
            throw InvalidBody("mass of '" + components.label(i) + "' must be positive and finite, got " + std::to_string(m));
        w.at(kM, i) = m;
    }
    return w;
}

double kinetic_energy(const World& w) {
    double e = 0;
    for (Index i = 0; i < w.size(); ++i) e += w.at(kP, i) * w.at(kP, i) / (2 * w.at(kM, i));
    return e;
}

double total_momentum(const World& w) {
    double p = 0;
    for (Index i = 0; i < w.size(); ++i) p += w.at(kP, i);
    return p;
}

} // namespace phynjo::runtime
