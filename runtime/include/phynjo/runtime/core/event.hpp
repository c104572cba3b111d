#pragma once
/// \file
/// The Boolean layer: flags, one-tick steps and emitted events, lowered into the same
/// Process interpreter as numeric rules.
#include "phynjo/runtime/core/literal.hpp"
#include "phynjo/runtime/core/workflow.hpp"

#include <span>

namespace phynjo::runtime {

/// The world of the event layer: one flag per component and the tick.
struct FlagWorld {
    std::shared_ptr<const Layout> layout; ///< components = the flags; one field, "flag"
    FlagLit flags;
    std::uint64_t tick = 0;

    explicit FlagWorld(const Registry& flags_registry);
    friend bool operator==(const FlagWorld& a, const FlagWorld& b) { return a.flags == b.flags && a.tick == b.tick; }
};

/// A small chip: looks at flags, decides the flags of its domain for the next tick, and may
/// announce that something happened.
struct EventRule {
    std::string name;
    ComponentSet domain; ///< the flags it may change
    ComponentSet reads;  ///< other flags it looks at
    /// `in`: every flag (read only those of domain and reads); `out`: the next values of the
    /// domain's flags, in the order of domain.indices(), preset to their current values.
    std::function<void(const FlagLit& in, std::span<std::uint8_t> out)> step;
    /// Events at `tick`, from the domain slice before the step (may be empty).
    std::function<void(std::uint64_t tick, std::span<const std::uint8_t> slice, Phenomenon& out)> events;
};

/// An event rule as an action (ruleToAction): split the flags into the domain slice and the rest, step the
/// slice, paste it back; the interpreter advances the tick. Domains above 256 flags use a
/// heap buffer per step.
Action<FlagWorld> rule_to_action(const EventRule& rule, std::shared_ptr<const Layout> layout);

template <>
struct WorkflowTraits<FlagWorld> {
    using Rule = EventRule;
    /// `shape`: a world of the flags the rule's components index.
    static Action<FlagWorld> lower(const EventRule& rule, const FlagWorld& shape);
};

/// run | seq | par over event rules, with the same domain checks as NumericWorkflow:
/// `EventWorkflow::run(rule, world_shape)`.
using EventWorkflow = Workflow<FlagWorld>;

/// One event of `component` at `tick` (`epsilon component tick`).
inline Event epsilon(Index component, std::uint64_t tick, std::string what) { return Event{tick, component, std::move(what)}; }

/// For the checked interpreter: the first flag outside `writes` that differs, described.
std::optional<std::string> first_change_outside(const FlagWorld& before, const FlagWorld& after, const Domain& writes);

} // namespace phynjo::runtime
