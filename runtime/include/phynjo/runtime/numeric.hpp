#pragma once
/// \file
/// The continuous half of the DSL: NumericRule {domain, step} and NumericWorkflow
/// (run | seq | par), lowered into the generic Process; the 1-D NState of the seed.
#include "phynjo/runtime/process.hpp"

#include <initializer_list>
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

/// A composition of numeric rules. Its domain is computed when it is built; `par` over
/// overlapping domains throws DomainOverlapError naming the shared entries, right there.
class NumericWorkflow {
public:
    static NumericWorkflow run(const NumericRule& rule);
    static NumericWorkflow seq(std::vector<NumericWorkflow> parts);
    static NumericWorkflow par(std::vector<NumericWorkflow> parts);
    template <typename... W>
    static NumericWorkflow seq(const NumericWorkflow& a, const W&... rest) {
        return seq(std::vector<NumericWorkflow>{a, rest...});
    }
    template <typename... W>
    static NumericWorkflow par(const NumericWorkflow& a, const W&... rest) {
        return par(std::vector<NumericWorkflow>{a, rest...});
    }

    [[nodiscard]] const Domain& domain() const noexcept { return process_.writes(); }
    [[nodiscard]] const Domain& reads() const noexcept { return process_.reads(); }
    [[nodiscard]] const Process<World>& process() const noexcept { return process_; }

private:
    explicit NumericWorkflow(Process<World> p) : process_(std::move(p)) {}
    Process<World> process_;
};

/// Why a guarded run stopped (the runtime never aborts a simulation: it says why it ended).
struct RunReport {
    bool completed = true;      ///< all requested steps were taken
    std::size_t steps = 0;      ///< steps completed
    std::uint64_t tick = 0;     ///< world.tick when it stopped
    double time = 0;            ///< world.time when it stopped, s
    std::string reason;         ///< empty when completed
    std::string where;          ///< `field:component` of the first non-finite entry, if that was the reason
};

/// Steps a world with a workflow: the built form of the seed's `step :: Δt -> world -> world`.
class Stepper {
public:
    explicit Stepper(const NumericWorkflow& workflow, Executor* executor = nullptr)
        : interpreter_(workflow.process(), executor), writes_(workflow.domain()) {}
    /// world ← workflow(dt, world); allocates nothing.
    void step(World& world, double dt) { interpreter_.step(world, dt); }
    /// `steps` steps of size dt (through step(): one path for tests and users alike).
    void run(World& world, double dt, std::size_t steps) {
        for (std::size_t i = 0; i < steps; ++i) step(world, dt);
    }
    void set_checked(bool on) noexcept { interpreter_.set_checked(on); }

    /// Like run(), but never throws and never lets NaN or infinity through unnoticed: after
    /// every step the entries the workflow writes are checked; the run stops at the first
    /// non-finite entry, or at the first exception a rule throws, and the report says which
    /// entry, at which tick, or what the rule said. On a stop the world holds the state the
    /// failing step produced (for inspection).
    RunReport run_guarded(World& world, double dt, std::size_t steps);

private:
    Interpreter<World> interpreter_;
    Domain writes_;
};

// ---- NState: 1-D point masses (positions q, momenta p, masses m) ----------------------------

/// Field ids of an NState world.
inline constexpr FieldId kQ = 0, kP = 1, kM = 2;

/// A 1-D world of point masses: fields q (m), p (kg·m/s) and m (kg) for every component of
/// `components`, with the given masses (all 1 kg when `masses` is empty), then the
/// `extra_fields` (for example the stage storage of rk4: rk4_fields()). Throws InvalidBody
/// for a mass that is not positive and finite, std::invalid_argument for a count mismatch.
World make_nstate(const Registry& components, const std::vector<double>& masses = {},
                  const std::vector<std::string>& extra_fields = {});

/// Lookups and updates in the seed's vocabulary.
inline double lookup_pos(Index c, const World& w) { return w.at(kQ, c); }
inline double lookup_mom(Index c, const World& w) { return w.at(kP, c); }
inline void insert_pos(Index c, double q, World& w) { w.at(kQ, c) = q; }
inline void insert_mom(Index c, double p, World& w) { w.at(kP, c) = p; }

/// Kinetic energy Σ p²/(2m), J.
double kinetic_energy(const World& nstate);
/// Total momentum Σ p, kg·m/s.
double total_momentum(const World& nstate);

} // namespace phynjo::runtime
