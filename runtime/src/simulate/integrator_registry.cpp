// The integrators of generated models, one entry each (integrator_registry.hpp).
#include "phynjo/runtime/simulate/integrator_registry.hpp"

#include "phynjo/runtime/core/process.hpp"
#include "phynjo/runtime/integrators/bdf.hpp"
#include "phynjo/runtime/integrators/cvode.hpp"
#include "phynjo/runtime/integrators/dormand_prince.hpp"
#include "phynjo/runtime/integrators/ida.hpp"
#include "phynjo/runtime/integrators/lagrangian_midpoint.hpp"
#include "phynjo/runtime/integrators/lagrangian_rattle.hpp"
#include "phynjo/runtime/integrators/lagrangian_rk4.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <stdexcept>

namespace phynjo::runtime {

namespace {

/// A fixed-step scheme: its workflow, one step of h per call, the time set (not accumulated).
class FixedStep final : public RunIntegrator {
public:
    explicit FixedStep(NumericWorkflow workflow) : stepper_(std::move(workflow)) {}
    void step_to(World& w, double target, double h) override {
        stepper_.step(w, h);
        w.time = target;
    }

private:
    Stepper stepper_;
};

template <NumericWorkflow (*Scheme)(const LagrangianSystem&, const std::shared_ptr<const Layout>&, const ProjectionOptions&)>
NumericWorkflow fixed_workflow(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                               const IntegratorSettings& settings) {
    return Scheme(system, layout, settings.projection);
}

template <NumericWorkflow (*Scheme)(const LagrangianSystem&, const std::shared_ptr<const Layout>&, const ProjectionOptions&)>
std::unique_ptr<RunIntegrator> make_fixed(const LagrangianSystem& system, World& w, const IntegratorSettings& settings, bool) {
    return std::make_unique<FixedStep>(Scheme(system, w.layout_ptr(), settings.projection));
}

/// Dormand–Prince: its accepted steps (watched: one at a time), its dense output for events.
class DormandPrinceRun final : public RunIntegrator {
public:
    DormandPrinceRun(const LagrangianSystem& system, const IntegratorSettings& settings, bool watched)
        : dp_(system, options(settings)), watched_(watched), dt_(settings.dt), h_(settings.dt),
          dense_([this](double t, std::span<double> q, std::span<double> v) { dp_.dense(t, q, v); }) {}
    void step_to(World& w, double target, double) override {
        do h_ = dp_.step(w, std::min(dp_.next_dt() > 0 ? dp_.next_dt() : h_, target - w.time), target);
        while (!watched_ && w.time < target - 1e-12 * dt_);
    }
    [[nodiscard]] const EventMonitor::Extension* dense() const override { return &dense_; }
    void save(ArchiveBytes& out) const override { out.f64(h_).f64(dp_.next_dt()); }
    void restore(ArchiveReader& in) override {
        h_ = in.f64();
        dp_.set_next_dt(in.f64());
    }

private:
    static DormandPrince45::Options options(const IntegratorSettings& settings) {
        DormandPrince45::Options o;
        o.projection = settings.projection;
        if (settings.rtol) o.rtol = *settings.rtol;
        if (settings.atol) o.atol = *settings.atol;
        return o;
    }
    DormandPrince45 dp_;
    bool watched_;
    double dt_, h_;
    EventMonitor::Extension dense_;
};

template <typename Solver>
typename Solver::Options solver_options(const IntegratorSettings& settings) {
    typename Solver::Options o;
    if constexpr (requires { o.projection; }) o.projection = settings.projection;
    if (settings.rtol) o.rtol = *settings.rtol;
    if (settings.atol) o.atol = *settings.atol;
    return o;
}

/// A variable-step BDF (CVODE, IDA, Bdf): unwatched, its own steps up to each target (the
/// solver's interpolant there); watched, one internal step at a time, crossings located on
/// its interpolating polynomial.
template <typename Solver>
class MultistepRun final : public RunIntegrator {
public:
    MultistepRun(const char* name, const LagrangianSystem& system, const IntegratorSettings& settings, bool watched)
        : name_(name), system_(system), options_(solver_options<Solver>(settings)), watched_(watched),
          dense_([this](double t, std::span<double> q, std::span<double> v) { solver_->dense(t, q, v); }) {
        solver_.emplace(system_, options_);
    }
    void step_to(World& w, double target, double) override {
        if (watched_) {
            solver_->step(w, target);
        } else {
            solver_->advance(w, target);
            w.time = target;
        }
    }
    bool restart_at_snapshot() override {
        add(before_, solver_->stats());
        solver_.emplace(system_, options_);
        return true;
    }
    [[nodiscard]] const EventMonitor::Extension* dense() const override { return &dense_; }
    [[nodiscard]] std::string statistics() const override {
        auto st = before_;
        add(st, solver_->stats());
        char line[256];
        std::snprintf(line, sizeof line,
                      "%s: %ld steps, %ld Jacobians, %ld Newton iterations, %ld Newton failures, %ld error-test failures",
                      name_, st.steps, st.jacobian_evaluations, st.newton_iterations, st.newton_failures,
                      st.error_test_failures);
        return line;
    }

private:
    static void add(typename Solver::Stats& to, const typename Solver::Stats& s) {
        to.steps += s.steps;
        to.jacobian_evaluations += s.jacobian_evaluations;
        to.newton_iterations += s.newton_iterations;
        to.newton_failures += s.newton_failures;
        to.error_test_failures += s.error_test_failures;
    }
    const char* name_;
    LagrangianSystem system_;
    typename Solver::Options options_;
    std::optional<Solver> solver_;
    typename Solver::Stats before_{}; ///< the counts of the solvers before a restart
    bool watched_;
    EventMonitor::Extension dense_;
};

template <typename Solver, NumericWorkflow (*Workflow)(const LagrangianSystem&, const std::shared_ptr<const Layout>&,
                                                       const typename Solver::Options&)>
NumericWorkflow multistep_workflow(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                                   const IntegratorSettings& settings) {
    return Workflow(system, layout, solver_options<Solver>(settings));
}

template <typename Solver, const char* Name>
std::unique_ptr<RunIntegrator> make_multistep(const LagrangianSystem& system, World&, const IntegratorSettings& settings,
                                              bool watched) {
    return std::make_unique<MultistepRun<Solver>>(Name, system, settings, watched);
}

std::unique_ptr<RunIntegrator> make_dopri(const LagrangianSystem& system, World&, const IntegratorSettings& settings,
                                          bool watched) {
    return std::make_unique<DormandPrinceRun>(system, settings, watched);
}

constexpr char kCvode[] = "cvode", kIda[] = "ida", kBdf[] = "bdf";

// name, order, symplectic, constraints, adaptive, tolerances, stiff, sweeps, fused_kernels,
// restarts, reference, help, workflow, make
const std::array<IntegratorEntry, 7> kRegistry{{
    {"rk4", "4", false, true, false, false, false, true, true, false, "Kutta (1901)",
     "classical Runge-Kutta on (q, q'); constraints: projected after each step",
     &fixed_workflow<lagrangian_rk4>, &make_fixed<lagrangian_rk4>},
    {"dopri", "5(4)", false, true, true, true, false, true, false, false, "Dormand & Prince, J. Comput. Appl. Math. 6, 19 (1980)",
     "Dormand-Prince 5(4), adaptive between the rows (defaults rtol 1e-9, atol 1e-12)", nullptr, &make_dopri},
    {"midpoint", "2", true, true, false, false, false, true, false, false,
     "Hairer, Lubich & Wanner, Geometric Numerical Integration, VI.3",
     "implicit midpoint in (q, p): symplectic without constraints, symmetric with them (bounded energy error)",
     &fixed_workflow<lagrangian_midpoint>, &make_fixed<lagrangian_midpoint>},
    {"rattle", "2", true, true, false, false, false, true, false, false, "Andersen, J. Comput. Phys. 52, 24 (1983)",
     "RATTLE: symplectic with holonomic constraints too", &fixed_workflow<lagrangian_rattle>,
     &make_fixed<lagrangian_rattle>},
    {"cvode", "1-5", false, true, true, true, true, false, false, true, "Hindmarsh et al., ACM TOMS 31, 363 (2005)",
     "SUNDIALS CVODE: variable-order BDF with the exact Jacobian, for stiff models (defaults rtol 1e-8, atol 1e-10); its step counts on stderr",
     &multistep_workflow<Cvode, lagrangian_cvode>, &make_multistep<Cvode, kCvode>},
    {"ida", "1-5", false, true, true, true, true, false, false, true, "Gear, Gupta & Leimkuhler, J. Comput. Appl. Math. 12, 77 (1985)",
     "SUNDIALS IDA: BDF on the equations with their constraints (stabilized index 2), held at every step; "
     "about 3x cvode's steps (defaults rtol 1e-8, atol 1e-10); its step counts on stderr",
     &multistep_workflow<Ida, lagrangian_ida>, &make_multistep<Ida, kIda>},
    {"bdf", "1-5", false, false, true, true, true, false, false, true, "Shampine & Reichelt, SIAM J. Sci. Comput. 18, 1 (1997)",
     "phynjo's own variable-order BDF/NDF with the exact Jacobian, for stiff models without constraints "
     "(defaults rtol 1e-8, atol 1e-10); its step counts on stderr",
     &multistep_workflow<Bdf, lagrangian_bdf>, &make_multistep<Bdf, kBdf>},
}};

} // namespace

std::span<const IntegratorEntry> integrator_registry() { return kRegistry; }

const IntegratorEntry* find_integrator(std::string_view name) {
    for (const IntegratorEntry& e : kRegistry)
        if (e.name == name) return &e;
    return nullptr;
}

std::string integrator_names(bool (*keep)(const IntegratorEntry&)) {
    std::vector<std::string_view> names;
    for (const IntegratorEntry& e : kRegistry)
        if (!keep || keep(e)) names.push_back(e.name);
    std::string s;
    for (std::size_t k = 0; k < names.size(); ++k)
        s += std::string(k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + std::string(names[k]);
    return s;
}

NumericWorkflow integrator_workflow(const LagrangianSystem& system, const World& world, std::string_view name,
                                    std::string_view who) {
    const IntegratorEntry* e = find_integrator(name);
    if (!e || !e->workflow)
        throw std::invalid_argument(std::string(who) + ": unknown integrator '" + std::string(name) + "' (" +
                                    integrator_names([](const IntegratorEntry& x) { return x.workflow != nullptr; }) + ")");
    return e->workflow(system, world.layout_ptr(), IntegratorSettings{});
}

} // namespace phynjo::runtime
