#include "phynjo/runtime/core/event.hpp"

#include <array>

namespace phynjo::runtime {

FlagWorld::FlagWorld(const Registry& r)
    : layout(std::make_shared<Layout>(r, std::vector<std::string>{"flag"})), flags(r.size()) {}

Action<FlagWorld> rule_to_action(const EventRule& rule, std::shared_ptr<const Layout> layout) {
    if (!rule.step) throw Error("event rule '" + rule.name + "' has no step function");
    Action<FlagWorld> a;
    a.name = rule.name;
    a.writes = Domain(0, rule.domain);
    a.reads = Domain(0, rule.reads);
    a.layout = std::move(layout);
    a.run = [rule](FlagWorld& w, const StepContext& ctx) {
        const auto idx = rule.domain.indices();
        std::array<std::uint8_t, 256> small{};
        std::vector<std::uint8_t> big;
        std::span<std::uint8_t> slice(small.data(), idx.size());
        if (idx.size() > small.size()) {
            big.resize(idx.size());
            slice = big;
        }
        for (std::size_t k = 0; k < idx.size(); ++k) slice[k] = w.flags.lookup(idx[k]) ? 1 : 0; // split
        if (rule.events && ctx.events) rule.events(ctx.tick, slice, *ctx.events);
        rule.step(w.flags, slice);                                                           // step
        for (std::size_t k = 0; k < idx.size(); ++k) w.flags.set(idx[k], slice[k] != 0);      // paste
    };
    return a;
}

Action<FlagWorld> WorkflowTraits<FlagWorld>::lower(const EventRule& rule, const FlagWorld& shape) {
    return rule_to_action(rule, shape.layout);
}

std::optional<std::string> first_change_outside(const FlagWorld& before, const FlagWorld& after, const Domain& writes) {
    const std::size_t n = std::max(before.flags.size(), after.flags.size());
    for (Index i = 0; i < n; ++i)
        if (before.flags.lookup(i) != after.flags.lookup(i) && !writes.contains(0, i))
            return before.layout->describe(0, i);
    return std::nullopt;
}

} // namespace phynjo::runtime
