#include "phynjo/runtime/core/workflow.hpp"

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

Action<World> WorkflowTraits<World>::lower(const NumericRule& rule) {
    if (!rule.step) throw Error("numeric rule '" + rule.name + "' has no step function");
    return to_action(rule);
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
            step(world, dt);
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

} // namespace phynjo::runtime
