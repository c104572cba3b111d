#pragma once
/// \file
/// SUNDIALS CVODE for generated models: variable-order (1–5), variable-step BDF with Newton
/// iterations on a direct solver, the model's exact rhs_jacobian as the Jacobian — for
/// stiff systems, where an explicit method's step is bounded by the fastest mode. Not
/// symplectic. (source: integrators/cvode.cpp)
/// Reference: A. C. Hindmarsh et al., SUNDIALS: Suite of nonlinear and differential/algebraic
/// equation solvers, ACM TOMS 31, 363 (2005); CVODE user guide v6.4.
#include "phynjo/runtime/system/constraint_projection.hpp"

#include <memory>
#include <span>

namespace phynjo::runtime {

/// CVODE on y = (q, q'), y' = (q', q''). Constrained models: the index-1 equations (the
/// accelerations of the saddle-point system) with CVODE's projection after every step onto
/// the position and velocity constraints (CVodeSetProjFn; ProjectionOptions), so the
/// constraints hold to the projection tolerance without restarting the multistep history.
class Cvode {
public:
    struct Options {
        double rtol = 1e-8, atol = 1e-10;
        /// The model's exact rhs_jacobian (true), or CVODE's internal difference quotients.
        bool exact_jacobian = true;
        /// The Newton systems (I − γJ)x = b. `second_order` (with the exact Jacobian): block
        /// elimination of q' = v, an LU of the n×n Schur complement I − γ∂a/∂v − γ²∂a/∂q
        /// (1/8 of the flops of the 2n×2n LU). `dense`: SUNDIALS' dense LU of the 2n×2n
        /// matrix (always used with difference quotients, whose identity block is inexact).
        enum class LinearSolver { second_order, dense } linear_solver = LinearSolver::second_order;
        long max_steps = 1'000'000; ///< internal steps per call to advance
        ProjectionOptions projection{};
    };
    /// Counters since construction (CVODE's own).
    struct Stats {
        long steps = 0, rhs_evaluations = 0, jacobian_evaluations = 0, difference_quotient_rhs = 0,
             newton_iterations = 0, newton_failures = 0, error_test_failures = 0, linear_setups = 0;
    };
    /// Throws std::invalid_argument for a system without rhs_jacobian when exact_jacobian is set.
    Cvode(LagrangianSystem system, Options options);
    ~Cvode();
    Cvode(const Cvode&) = delete;
    Cvode& operator=(const Cvode&) = delete;

    /// Advances `w` to time `t_end` (CVODE chooses its internal steps; the state at t_end is
    /// its interpolant there). Continues the multistep history when `w` is where the last
    /// call left it, restarts otherwise (a state changed between calls). Errors become the
    /// runtime's: ConvergenceError (CVODE's flag and message, and the time reached), or the
    /// model's own (SingularMassMatrix, NonFiniteResult, …); `w` is then at the time reached.
    void advance(World& w, double t_end);
    /// One internal step towards `t_end` > w.time, for a caller that watches each step (the
    /// event monitor): CVODE takes one step (CV_ONE_STEP) unless its last one already ends
    /// past w.time, and `w` is set to min(its end, t_end) — at t_end the same interpolant,
    /// bit for bit, as `advance` gives. Continues or restarts as `advance` does; the same errors.
    void step(World& w, double t_end);
    /// CVODE's interpolating polynomial of its last internal step (CVodeGetDky): (q, q') at t
    /// in that step, s. Between step() calls it covers the world's last advance.
    void dense(double t, std::span<double> q, std::span<double> qdot) const;
    [[nodiscard]] Stats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// CVODE as a workflow: one rule (`cvode`, writing q and q') that advances the world by dt
/// per step with one Cvode (its multistep history carries over from step to step; a world
/// changed between steps restarts it). The rule is stateful: copies of the workflow share
/// the solver, so step one world per workflow.
NumericWorkflow lagrangian_cvode(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                                 const Cvode::Options& options = {});

} // namespace phynjo::runtime
