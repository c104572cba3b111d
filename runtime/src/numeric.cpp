#include "phynjo/runtime/numeric.hpp"

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

World make_nstate(const Registry& components, const std::vector<double>& masses,
                  const std::vector<std::string>& extra_fields) {
    std::vector<std::string> fields{"q", "p", "m"};
    fields.insert(fields.end(), extra_fields.begin(), extra_fields.end());
    auto layout = std::make_shared<Layout>(components, std::move(fields));
    World w(layout);
    for (Index i = 0; i < w.size(); ++i) w.at(kM, i) = masses.empty() ? 1.0 : masses.at(i);
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
