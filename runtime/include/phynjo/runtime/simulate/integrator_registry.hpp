#pragma once
/// \file
/// The integrators of generated models, one entry each: what the command-line simulator
/// (`--integrator NAME`, its --help), the sweeps, generated code's `workflow(P, world, NAME)`
/// and docs/generated-code.md's table know of them. A new integrator is one file under
/// integrators/ and one entry in runtime/src/simulate/integrator_registry.cpp.
#include "phynjo/runtime/core/archive.hpp"
#include "phynjo/runtime/core/workflow.hpp"
#include "phynjo/runtime/core/world.hpp"
#include "phynjo/runtime/simulate/events.hpp"
#include "phynjo/runtime/system/constraint_projection.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace phynjo::runtime {

/// How a run sets up its integrator: the projection onto the constraints after each step, and
/// the local error tolerances of the adaptive ones (unset: each integrator's defaults).
struct IntegratorSettings {
    /// The run's step, s: Dormand–Prince's first trial step and the scale of its end test.
    double dt = 0;
    ProjectionOptions projection{};
    std::optional<double> rtol, atol;
};

/// One run's integrator as the drivers step it (model_main, run_one): one step towards a
/// target time at a time, watched by the EventMonitor when the model has events.
class RunIntegrator {
public:
    virtual ~RunIntegrator() = default;
    /// One step of the integrator towards `target` s (`h`: the run step's length, s), leaving
    /// `w.time` where it ended. Unwatched (a model without events), it reaches `target`.
    virtual void step_to(World& w, double target, double h) = 0;
    /// The integrator's own continuous extension of its last step, where it has one (the
    /// monitor locates crossings on it); null: the monitor's cubic Hermite.
    [[nodiscard]] virtual const EventMonitor::Extension* dense() const { return nullptr; }
    /// What it did, one line for stderr (its step and Newton counts), or empty.
    [[nodiscard]] virtual std::string statistics() const { return {}; }

    /// For an archive's snapshot (core/archive.hpp, docs/archive.md): what the integrator
    /// carries from one run step to the next beyond the world (Dormand–Prince: its step
    /// size). A new integrator of the same entry and settings that restores it continues
    /// bit for bit as this one would have.
    virtual void save(ArchiveBytes& out) const { (void)out; }
    virtual void restore(ArchiveReader& in) { (void)in; }
    /// The restart rule of integrators whose history is not saved (CVODE's, IDA's and Bdf's
    /// multistep history: SUNDIALS' memory): the driver calls this after each snapshot, and the
    /// integrator starts afresh from the world as a resumed one does. True when it restarts
    /// (a run with snapshots is then the run that restarts at each of them).
    virtual bool restart_at_snapshot() { return false; }
};

/// One integrator of generated models.
struct IntegratorEntry {
    std::string_view name;
    std::string_view order;     ///< its order of accuracy ("4", "5(4)", "1-5": variable)
    bool symplectic;            ///< symplectic without constraints
    bool constraints;           ///< takes models with constraints (and keeps them)
    bool adaptive;              ///< chooses its own steps between the rows
    bool tolerances;            ///< takes --rtol and --atol
    bool stiff;                 ///< made for stiff models (implicit, with the exact Jacobian)
    bool sweeps;                ///< the sweeps run it
    bool fused_kernels;         ///< a sweep's run steps on generated code's fused kernels (rk4_step_values, lanes)
    /// Its history is not archived: it restarts at every snapshot (RunIntegrator::
    /// restart_at_snapshot, docs/archive.md), so its snapshots are spaced by steps, never by
    /// wall time (where they fall changes its run).
    bool restarts;
    std::string_view reference; ///< the paper or software it follows
    std::string_view help;      ///< one line for --help and the docs' table
    /// The step as a workflow (generated code's `workflow(P, world, name)`), or null where the
    /// integrator only runs under the drivers (its steps are not a fixed dt).
    NumericWorkflow (*workflow)(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                                const IntegratorSettings& settings);
    /// One run's integrator over `w`; `watched`: the model has events (steps are taken one at
    /// a time and watched, rather than all the way to each target).
    std::unique_ptr<RunIntegrator> (*make)(const LagrangianSystem& system, World& w, const IntegratorSettings& settings,
                                           bool watched);
};

/// Every integrator, in the order --help lists them; the first is the default.
[[nodiscard]] std::span<const IntegratorEntry> integrator_registry();
/// The entry named `name`, or null.
[[nodiscard]] const IntegratorEntry* find_integrator(std::string_view name);
/// The names of the entries `keep` accepts, for messages: "a, b or c".
[[nodiscard]] std::string integrator_names(bool (*keep)(const IntegratorEntry&) = nullptr);
/// The workflow of integrator `name` over `world`'s layout, with the default settings.
/// std::invalid_argument "WHO: unknown integrator 'NAME' (the names that have a workflow)".
[[nodiscard]] NumericWorkflow integrator_workflow(const LagrangianSystem& system, const World& world,
                                                  std::string_view name, std::string_view who);

} // namespace phynjo::runtime
