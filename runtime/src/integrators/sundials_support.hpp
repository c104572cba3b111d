#pragma once
// What the SUNDIALS integrators (cvode.cpp, ida.cpp) share: a flag's name, the setup check,
// the check that a world is where the solver left it (continue its history) or was changed
// (restart), the end of an advance, and the solver as a workflow. Internal to the runtime.
#include "phynjo/runtime/system/constraint_projection.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace phynjo::runtime::sundials {

/// A solver's name of a return flag (SUNDIALS' XGetReturnFlagName allocates it: freed here).
inline std::string flag_name(char* (*name_of)(long), long flag) {
    char* p = name_of(flag);
    std::string name = p ? p : "unknown flag";
    std::free(p);
    return name;
}

/// Throws std::runtime_error for a failed setup call (a negative flag).
inline void check_setup(int flag, const char* solver, const char* what, char* (*name_of)(long)) {
    if (flag < 0)
        throw std::runtime_error(std::string(solver) + " setup failed in " + what + ": " + flag_name(name_of, flag));
}

/// A solver's step() towards t_end: std::invalid_argument naming `who` unless t_end is after
/// the world's time.
inline void require_after(const World& w, double t_end, const char* who) {
    if (!(t_end > w.time))
        throw std::invalid_argument(std::string(who) + ": t_end " + std::to_string(t_end) +
                                    " is not after the world's time " + std::to_string(w.time));
}

/// The internal step of a solver's step(): `take()` (one CV_ONE_STEP / IDA_ONE_STEP call,
/// returning its flag) unless the solver's time `now()` is already past the world's time
/// `t_world` (its last output was interpolated back); a solver hands back a step it took
/// but did not return before it takes another, so it is called until its time passes
/// t_world or it fails. Returns the last flag (0 when no call was needed), `tn` its time.
template <class Now, class Take>
int step_past(double t_world, double& tn, Now&& now, Take&& take) {
    int flag = 0;
    tn = now();
    while (flag >= 0 && !(tn > t_world)) {
        flag = take();
        tn = now();
    }
    return flag;
}

/// Where a solver left a world: its time and (q, q'), to tell a continuation from a restart.
struct LastState {
    bool valid = false;
    double time = 0;
    std::vector<double> y; ///< (q, q')

    /// True when `w` is where the solver left it (the history may continue): the same state,
    /// bit for bit, at the same time to a few ulps (a Stepper sets its time to t₀ + k·dt,
    /// where the solver's rule reached t + dt).
    [[nodiscard]] bool matches(const World& w, std::size_t n) const {
        bool same = valid && std::fabs(w.time - time) <= 4 * std::numeric_limits<double>::epsilon() *
                                                              std::max(1.0, std::fabs(time));
        for (std::size_t i = 0; i < n && same; ++i)
            same = w.at(kGQ, static_cast<Index>(i)) == y[i] && w.at(kGV, static_cast<Index>(i)) == y[n + i];
        return same;
    }
    void remember(const World& w, std::size_t n) {
        valid = true;
        time = w.time;
        y.resize(2 * n);
        for (std::size_t i = 0; i < n; ++i) {
            y[i] = w.at(kGQ, static_cast<Index>(i));
            y[n + i] = w.at(kGV, static_cast<Index>(i));
        }
    }
};

/// The end of a solver's advance to t_end: (q, q') into the world at t_end (at the time
/// reached when the solver failed), the output projected onto a constrained model's
/// constraints (the solver's own state is left as it is), the state remembered; then the
/// model's exception rethrown, or the solver's failure (a negative flag) thrown as a
/// ConvergenceError naming the flag, the time reached and the solver's message.
inline void finish_advance(World& w, const double* q, const double* v, int flag, double t_reached, double t_end,
                           const LagrangianSystem& sys, const ProjectionOptions& projection, LastState& last,
                           const std::exception_ptr& error, const char* solver, char* (*name_of)(long),
                           const std::string& message) {
    const std::size_t n = sys.dof;
    for (std::size_t i = 0; i < n; ++i) {
        w.at(kGQ, static_cast<Index>(i)) = q[i];
        w.at(kGV, static_cast<Index>(i)) = v[i];
    }
    w.time = flag < 0 ? t_reached : t_end;
    if (sys.n_constraints > 0 && flag >= 0 && !error)
        project_onto_constraints(sys, w.time, w.field(kGQ), w.field(kGV), projection);
    last.remember(w, n);
    if (error) std::rethrow_exception(error);
    if (flag < 0)
        throw ConvergenceError(std::string(solver) + " stopped at t = " + std::to_string(t_reached) + ": " +
                               flag_name(name_of, flag) + (message.empty() ? "" : " (" + message + ")"));
}

} // namespace phynjo::runtime::sundials

namespace phynjo::runtime::sundials {

/// A SUNDIALS solver as a workflow: one rule (`name`, writing q and q') advancing the world
/// by dt per step with one shared solver (lagrangian_cvode, lagrangian_ida).
template <class Solver>
NumericWorkflow solver_workflow(const char* name, std::shared_ptr<Solver> solver, std::size_t dof,
                                const std::shared_ptr<const Layout>& layout) {
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(dof));
    NumericRule r{name, Domain(kGQ, all) | Domain(kGV, all), {}, nullptr, layout};
    r.step = [solver](double dt, World& w) {
        const double t0 = w.time;
        solver->advance(w, t0 + dt);
        w.time = t0; // the interpreter advances the time
    };
    return NumericWorkflow::run(r);
}

} // namespace phynjo::runtime::sundials
