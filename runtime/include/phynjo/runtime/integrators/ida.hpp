#pragma once
/// \file
/// SUNDIALS IDA for generated models, constrained ones above all: variable-order (1–5),
/// variable-step BDF on the differential-algebraic equations themselves, in the stabilized
/// index-2 form of Gear, Gupta and Leimkuhler, so the position and velocity constraints hold
/// at every step to the Newton tolerance — no projection, no drift. Not symplectic.
/// (source: integrators/ida.cpp)
/// References: C. W. Gear, B. Leimkuhler, G. K. Gupta, Automatic integration of Euler–Lagrange
/// equations with constraints, J. Comput. Appl. Math. 12–13, 77 (1985); A. C. Hindmarsh et
/// al., SUNDIALS, ACM TOMS 31, 363 (2005); IDA user guide v6.4.
///
/// The unknowns are Y = (q, q', p, λ, μ), with p the momenta, λ the multipliers of all m
/// constraints and μ those of the m_h holonomic ones; the residuals (all zero on a solution):
///
///     q̇ − q' − G_hᵀ μ            (μ = 0 on the exact solution: it absorbs the drift of φ)
///     p − ∂L/∂q'(t, q, q')
///     ṗ − F(t, q, q') − Gᵀ λ      (F = ∂L/∂q + Q − ∂R/∂q': the Euler–Lagrange equations)
///     ψ(t, q, q')                 (velocity level: G q' + ∂φ/∂t, and the nonholonomic rows)
///     φ_h(t, q)                   (position level: the holonomic rows)
///
/// The momentum form makes the equations semi-explicit (q' and λ, μ are algebraic; q and p
/// carry the error test, λ and μ are left out of it, IDASetSuppressAlg) and serves models
/// whose M depends on q' too. Unconstrained models are the first three rows.
#include "phynjo/runtime/models/constraint_projection.hpp"

#include <memory>

namespace phynjo::runtime {

class Ida {
public:
    struct Options {
        double rtol = 1e-8, atol = 1e-10;
        /// The Jacobian of the residuals from the model's canonical_jacobian (∂p, ∂F exact),
        /// with the constraints' curvature terms ∂(Gᵀλ)/∂q, ∂(G_hᵀμ)/∂q and ∂ψ/∂q by central
        /// differences of G and ψ (the generated code has no second derivatives of φ) —
        /// exact for models without constraints. False: IDA's own difference quotients.
        bool exact_jacobian = true;
        long max_steps = 1'000'000; ///< internal steps per call to advance
        /// The initial state is projected onto the constraints with these options (IDA needs
        /// consistent initial values), and so is the output interpolated between IDA's steps.
        ProjectionOptions projection{};
    };
    /// Counters since construction (IDA's own).
    struct Stats {
        long steps = 0, residual_evaluations = 0, jacobian_evaluations = 0, difference_quotient_residuals = 0,
             newton_iterations = 0, newton_failures = 0, error_test_failures = 0;
    };
    /// Throws std::invalid_argument for a system without canonical_jacobian when
    /// exact_jacobian is set, or non-positive tolerances.
    Ida(LagrangianSystem system, Options options);
    ~Ida();
    Ida(const Ida&) = delete;
    Ida& operator=(const Ida&) = delete;

    /// Advances `w` to time `t_end` (IDA's interpolant there, projected onto the constraints).
    /// Continues IDA's history when `w` is where the last call left it, restarts otherwise
    /// (from `w` projected onto the constraints, with consistent q̈, ṗ, λ). Errors become the
    /// runtime's: ConvergenceError (IDA's flag and message, and the time reached), or the
    /// model's own (SingularMassMatrix, SingularConstraints, …); `w` is then at the time reached.
    void advance(World& w, double t_end);
    [[nodiscard]] Stats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// IDA as a workflow: one rule (`ida`, writing q and q') that advances the world by dt per
/// step with one Ida (its history carries over; a world changed between steps restarts it).
/// The rule is stateful: copies of the workflow share the solver, so step one world per
/// workflow.
NumericWorkflow lagrangian_ida(const LagrangianSystem& system, const std::shared_ptr<const Layout>& layout,
                               const Ida::Options& options = {});

} // namespace phynjo::runtime
