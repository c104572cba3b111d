#pragma once
/// \file
/// Workflows: run | seq | par over the rules of one world kind, lowered into the generic
/// Process and validated when built (one Workflow<W> for both layers: NumericWorkflow over
/// NumericRule on a World, EventWorkflow over EventRule on a FlagWorld, in event.hpp). The
/// continuous half of the DSL: NumericRule {domain, step}, and the Stepper that runs it.
#include "phynjo/runtime/core/process.hpp"

#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// A pure update of a World: `step(dt, world)` rewrites the entries of `domain` (and only
/// those) from the entries of `domain` and `reads`. Implemented in place.
struct NumericRule {
    std::string name;
    Domain domain;          ///< the entries it may write
    Domain reads;           ///< the other entries it reads
    std::function<void(double dt, World& world)> step;
    std::shared_ptr<const Layout> layout; ///< names in error messages
};

/// The lowering of a rule: one action of the Process interpreter.
Action<World> to_action(const NumericRule& rule);

/// How the rules of world kind W become actions of the Process interpreter: specialised
/// once per world kind (`Rule`, `lower(rule, …)`), here for World and in event.hpp for FlagWorld.
template <typename W>
struct WorkflowTraits;

/// A composition of rules of one world kind: run | seq | par. Its domain is computed when it
/// is built; `par` over overlapping domains throws DomainOverlapError naming the shared
/// entries, right there (never mid-run).
template <typename W>
class Workflow {
public:
    using Rule = typename WorkflowTraits<W>::Rule;

    /// One rule (for the event layer: `run(rule, world_shape)`).
    template <typename... Shape>
    static Workflow run(const Rule& rule, const Shape&... shape) {
        return Workflow(Process<W>::act(WorkflowTraits<W>::lower(rule, shape...)));
    }
    static Workflow seq(std::vector<Workflow> parts) { return Workflow(Process<W>::seq(processes(parts))); }
    static Workflow par(std::vector<Workflow> parts) { return Workflow(Process<W>::par(processes(parts))); }
    template <typename... More>
    static Workflow seq(const Workflow& a, const More&... rest) {
        return seq(std::vector<Workflow>{a, rest...});
    }
    template <typename... More>
    static Workflow par(const Workflow& a, const More&... rest) {
        return par(std::vector<Workflow>{a, rest...});
    }

    [[nodiscard]] const Domain& domain() const noexcept { return process_.writes(); }
    [[nodiscard]] const Domain& reads() const noexcept { return process_.reads(); }
    [[nodiscard]] const Process<W>& process() const noexcept { return process_; }

private:
    explicit Workflow(Process<W> p) : process_(std::move(p)) {}
    static std::vector<Process<W>> processes(const std::vector<Workflow>& parts) {
        std::vector<Process<W>> ps;
        ps.reserve(parts.size());
        for (const Workflow& p : parts) ps.push_back(p.process_);
        return ps;
    }
    Process<W> process_;
};

template <>
struct WorkflowTraits<World> {
    using Rule = NumericRule;
    /// Throws Error for a rule without a step function.
    static Action<World> lower(const NumericRule& rule);
};

/// A composition of numeric rules.
using NumericWorkflow = Workflow<World>;

/// Why a guarded run stopped (the runtime never aborts a simulation: it says why it ended).
struct RunReport {
    bool completed = true;      ///< all requested steps were taken
    std::size_t steps = 0;      ///< steps completed
    std::uint64_t tick = 0;     ///< world.tick when it stopped
    double time = 0;            ///< world.time when it stopped, s
    std::string reason;         ///< empty when completed
    std::string where;          ///< `field:component` of the first non-finite entry, if that was the reason
};

/// Steps a world with a workflow: the built form of `step :: Δt -> world -> world`.
class Stepper {
public:
    explicit Stepper(const NumericWorkflow& workflow, Executor* executor = nullptr)
        : interpreter_(workflow.process(), executor), writes_(workflow.domain()) {}
    /// world ← workflow(dt, world); allocates nothing. The time is not a running sum: steps
    /// of one dt that continue each other (the world's time is the one the last step left)
    /// end at t₀ + k·dt exactly, t₀ where that sequence began — a loop of 3,000 steps of
    /// 1 ms ends at 3 s, not 3 s − 2.2e-13, so a controller's `t < 1.5` switches on time.
    void step(World& world, double dt) {
        if (!(world.time == last_time_ && dt == last_dt_ && count_ < kMaxCount)) {
            origin_ = world.time;
            last_dt_ = dt;
            count_ = 0;
        }
        interpreter_.step(world, dt);
        ++count_;
        world.time = origin_ + static_cast<double>(count_) * dt;
        last_time_ = world.time;
    }
    /// `steps` steps of size dt (through step(): one path for tests and users alike).
    void run(World& world, double dt, std::size_t steps) {
        for (std::size_t i = 0; i < steps; ++i) step(world, dt);
    }
    void set_checked(bool on) noexcept { interpreter_.set_checked(on); }

    /// What step() keeps to make times exact: t₀, dt, the steps k since t₀, the time the last
    /// step ended (NaN before the first). Saved with a world (simulate/archived_run.hpp), it
    /// lets a continued run's times be t₀ + k·dt like the uninterrupted run's.
    struct Clock {
        double origin = 0, dt = 0, last_time = std::numeric_limits<double>::quiet_NaN();
        std::uint64_t count = 0;
    };
    [[nodiscard]] Clock clock() const noexcept { return {origin_, last_dt_, last_time_, count_}; }
    void set_clock(const Clock& c) noexcept {
        origin_ = c.origin;
        last_dt_ = c.dt;
        last_time_ = c.last_time;
        count_ = c.count;
    }

    /// Like run(), but never throws and never lets NaN or infinity through unnoticed: after
    /// every step the entries the workflow writes are checked; the run stops at the first
    /// non-finite entry, or at the first exception a rule throws, and the report says which
    /// entry, at which tick, or what the rule said. On a stop the world holds the state the
    /// failing step produced (for inspection).
    RunReport run_guarded(World& world, double dt, std::size_t steps);

private:
    static constexpr std::uint64_t kMaxCount = std::uint64_t{1} << 52; ///< k·dt exact in a double
    Interpreter<World> interpreter_;
    Domain writes_;
    double origin_ = 0, last_dt_ = 0, last_time_ = std::numeric_limits<double>::quiet_NaN(); ///< t₀, dt, the last end
    std::uint64_t count_ = 0; ///< k: steps since t₀
};

} // namespace phynjo::runtime
