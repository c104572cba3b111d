#pragma once
// CVODE's Newton systems for second-order ODEs, reduced to the velocities. Internal to the
// runtime (cvode.cpp); see second_order_linear_solver.cpp.
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <cstddef>
#include <memory>

namespace phynjo::runtime::sundials {

/// The Newton systems (I − γJ)x = b of y = (q, v) ∈ ℝ²ⁿ, y' = (v, a(q, v)), whose Jacobian is
/// J = [[0, I], [J_q, J_v]]. Block elimination with the identity as pivot leaves the n×n
/// Schur complement on the velocities,
///     S = I − γJ_v − γ²J_q,   x₂ = S⁻¹(b₂ + γJ_q b₁),   x₁ = b₁ + γx₂,
/// factorized by LU with partial pivoting within its band (velocity_schur.hpp, shared with
/// Bdf): at most 1/8 of the flops of the 2n×2n LU, 1/4 of its solves, and no 2n×2n matrix to
/// copy and scale at every setup.
/// Used through CVODE's linear-system function (CVodeSetLinSysFn): form() remembers γ and J;
/// CVODE then calls the solver's setup (S formed and factored; a zero pivot is a recoverable
/// failure) and solve. matrix() is the dense matrix CVODE asks for, unused. No allocation
/// in a steady run.
class SecondOrderNewton {
public:
    /// Throws std::bad_alloc when SUNDIALS cannot allocate.
    SecondOrderNewton(std::size_t n, SUNContext ctx);
    ~SecondOrderNewton();
    SecondOrderNewton(const SecondOrderNewton&) = delete;
    SecondOrderNewton& operator=(const SecondOrderNewton&) = delete;

    [[nodiscard]] SUNLinearSolver solver() const { return solver_; }
    [[nodiscard]] SUNMatrix matrix() const { return matrix_; }
    /// γ and J ((2n)×(2n), row-major) of the next setup; J is read again by the setup and
    /// the solves, so it must stay unchanged until the next form().
    void form(const double* J, double gamma);

    struct Factor;

private:
    SUNMatrix matrix_ = nullptr;
    SUNLinearSolver solver_ = nullptr;
};

} // namespace phynjo::runtime::sundials
