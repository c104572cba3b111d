#pragma once
/// \file
/// phynjo's own BDF for generated models: variable order 1–5, variable step, the numerical
/// differentiation formulas (NDF, Klopfenstein's κ as Shampine & Reichelt choose them) at
/// orders 1–4 and BDF5, in the quasi-constant step-size form (backward differences D of the
/// solution, rescaled when the step changes), Newton iterations with the model's exact
/// rhs_jacobian and a banded LU of the velocity Schur complement (I − cJ reduced by q' = v).
/// Order ≤ 5, A(α)-stable (L-stable at order 1), for stiff systems; not symplectic.
/// Every vector pass over the state is one loop; a steady step allocates nothing.
/// (source: integrators/bdf.cpp)
/// References: L. F. Shampine and M. W. Reichelt, The MATLAB ODE Suite, SIAM J. Sci. Comput.
/// 18, 1 (1997) (NDF, the quasi-constant step size); G. D. Byrne and A. C. Hindmarsh, A
/// polyalgorithm for the numerical solution of ODEs, ACM TOMS 1, 71 (1975) (the error
/// estimates); the step, order and Newton controls follow SciPy's solve_ivp(method='BDF').
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <limits>
#include <memory>
#include <span>

namespace phynjo::runtime {

/// BDF on y = (q, q'), y' = (q', q'') for models without constraints (constrained models:
/// Cvode with its projection, or Ida).
class Bdf {
public:
    struct Options {
        /// The local error of each step, weighted: RMS over y of err_i / (atol + rtol |y_i|) ≤ 1.
        double rtol = 1e-8, atol = 1e-10;
        long max_steps = 1'000'000;                                ///< internal steps per call to advance
        double max_step = std::numeric_limits<double>::infinity(); ///< s
        double first_step = 0; ///< s; 0: chosen from the right side (Hairer, Nørsett & Wanner's rule)
    };
    /// Counters since construction.
    struct Stats {
        long steps = 0, rhs_evaluations = 0, jacobian_evaluations = 0, factorizations = 0, newton_iterations = 0,
             newton_failures = 0, error_test_failures = 0;
        int order = 0;                                    ///< of the last step
        std::size_t lower_bandwidth = 0, upper_bandwidth = 0; ///< of the last Schur complement factored
    };
    /// Throws std::invalid_argument for a system without rhs_jacobian, with constraints, or
    /// for tolerances or steps that are not positive.
    Bdf(LagrangianSystem system, Options options);
    ~Bdf();
    Bdf(const Bdf&) = delete;
    Bdf& operator=(const Bdf&) = delete;

    /// Advances `w` to time `t_end` ≥ w.time: internal steps until one ends at or past t_end,
    /// the state at t_end from the interpolating polynomial of the differences. Continues
    /// the history when `w` is where the last call left it, restarts otherwise (a state
    /// changed between calls). Errors: ConvergenceError (the step size fell below 10 ulp of
    /// t, or max_steps) naming the time reached, or the model's own (SingularMassMatrix, …);
    /// `w` is then the last accepted step, at its time.
    void advance(World& w, double t_end);
    /// One internal step towards `t_end` > w.time, for a caller that watches each step (the
    /// event monitor): one step unless the last one already ends past w.time, and `w` set to
    /// min(its end, t_end) — at t_end the same interpolant, bit for bit, as `advance` gives.
    /// Continues or restarts as `advance` does; the same errors.
    void step(World& w, double t_end);
    /// The interpolating polynomial of the last internal step: (q, q') at t in that step, s.
    /// Between step() calls it covers the world's last advance.
    void dense(double t, std::span<double> q, std::span<double> qdot) const;
    [[nodiscard]] Stats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Bdf as a workflow: one rule (`bdf`, writing q and q') advancing the world by dt per step
/// with one Bdf (its history carries over from step to step; a world changed between steps
/// restarts it). The rule is stateful: copies of the workflow share the solver.
NumericWorkflow lagrangian_bdf(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                               const Bdf::Options& options = {});

} // namespace phynjo::runtime
