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
#include "phynjo/runtime/system/constraint_projection.hpp"

#include <memory>
#include <span>
#include <vector>

namespace phynjo::runtime {

/// The stabilized index-2 equations above, on their own: residuals, their Jacobian, and
/// consistent initial values — what Ida hands to IDA, open to tests and to other DAE solvers.
/// Allocates only when constructed.
class GglEquations {
public:
    /// Where q, q', p, λ, μ start in Y (and the residual rows: q̇ rows, p rows, ṗ rows, ψ, φ_h).
    struct Offsets {
        std::size_t q = 0, v = 0, p = 0, lambda = 0, mu = 0;
    };
    explicit GglEquations(LagrangianSystem system);
    /// N = 3·dof + m + m_h, the number of unknowns and of residuals.
    [[nodiscard]] std::size_t size() const noexcept { return N_; }
    [[nodiscard]] Offsets offsets() const noexcept { return off_; }
    [[nodiscard]] const LagrangianSystem& system() const noexcept { return sys_; }
    /// R(t, Y, Ẏ) (size N each).
    void residual(double t, std::span<const double> Y, std::span<const double> Yd, std::span<double> R);
    /// ∂R/∂Y + cj·∂R/∂Ẏ at (t, Y), column-major N×N (SUNDIALS' dense layout). Needs the
    /// system's canonical_jacobian; the constraints' curvature by central differences.
    void jacobian(double t, double cj, std::span<const double> Y, std::span<double> J);
    /// Y and Ẏ consistent with (q, q') at t: (q, q') projected onto the constraints, p =
    /// ∂L/∂q', q̈ and λ from the saddle-point system, ṗ = F + Gᵀλ, μ = 0: R(t, Y, Ẏ) = 0 up to
    /// round-off. Throws what the projection and the solve throw (SingularMassMatrix, …).
    void consistent_values(double t, std::span<const double> q, std::span<const double> qdot,
                           const ProjectionOptions& projection, std::span<double> Y, std::span<double> Yd);

private:
    LagrangianSystem sys_;
    std::size_t n_ = 0, m_ = 0, mh_ = 0, N_ = 0;
    Offsets off_;
    std::vector<std::size_t> holonomic_; ///< the holonomic rows of G, in file order
    // scratch, sized once
    std::vector<double> p_, F_, G_, psi_, phi_, dp_, dF_, qt_, Gp_, Gm_, psip_, psim_, q_, v_, acc_, lambda_;
};

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
    /// One internal step towards `t_end` > w.time, for a caller that watches each step (the
    /// event monitor): IDA takes one step (IDA_ONE_STEP) unless its last one already ends
    /// past w.time, and `w` is set to min(its end, t_end) — at t_end the same interpolant,
    /// bit for bit, as `advance` gives. Continues or restarts as `advance` does; the same errors.
    void step(World& w, double t_end);
    /// IDA's interpolating polynomial of its last internal step (IDAGetDky): (q, q') at t in
    /// that step, s (not projected onto the constraints). Between step() calls it covers the
    /// world's last advance.
    void dense(double t, std::span<double> q, std::span<double> qdot) const;
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
