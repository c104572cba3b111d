// Block elimination of q' = v in CVODE's Newton systems (the Schur complement on the
// velocities). See second_order_linear_solver.hpp.
#include "second_order_linear_solver.hpp"

#include "velocity_schur.hpp"

#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <memory>
#include <new>

namespace phynjo::runtime::sundials {

/// The solver's content: γ as last formed, the block elimination and the LU of S.
struct SecondOrderNewton::Factor {
    explicit Factor(std::size_t n) : schur(n) {}
    integrators::VelocitySchur schur;
    double gamma = 0;
    long last_flag = 0;
};

namespace {

using Factor = SecondOrderNewton::Factor;

Factor& factor(SUNLinearSolver s) { return *static_cast<Factor*>(s->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver) { return SUNLS_SUCCESS; }

int setup(SUNLinearSolver s, SUNMatrix) {
    auto& f = factor(s);
    // a zero pivot k: the positive flag k + 1, recoverable (CVODE retries with a smaller step)
    return static_cast<int>(f.last_flag = static_cast<long>(f.schur.factor(f.gamma)));
}

int solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, double) {
    auto& f = factor(s);
    f.schur.solve(N_VGetArrayPointer(b), N_VGetArrayPointer(x));
    return static_cast<int>(f.last_flag = SUNLS_SUCCESS);
}

sunindextype last_flag(SUNLinearSolver s) { return factor(s).last_flag; }

int free_solver(SUNLinearSolver s) {
    if (!s) return SUNLS_SUCCESS;
    delete static_cast<Factor*>(s->content);
    s->content = nullptr;
    SUNLinSolFreeEmpty(s);
    return SUNLS_SUCCESS;
}

} // namespace

SecondOrderNewton::SecondOrderNewton(std::size_t n, SUNContext ctx) {
    auto content = std::make_unique<Factor>(n);
    const auto N = static_cast<sunindextype>(n);
    matrix_ = SUNDenseMatrix(N, N, ctx);
    solver_ = SUNLinSolNewEmpty(ctx);
    if (!matrix_ || !solver_) {
        if (solver_) SUNLinSolFreeEmpty(solver_);
        if (matrix_) SUNMatDestroy(matrix_);
        throw std::bad_alloc();
    }
    solver_->ops->gettype = get_type;
    solver_->ops->getid = get_id;
    solver_->ops->initialize = initialize;
    solver_->ops->setup = setup;
    solver_->ops->solve = solve;
    solver_->ops->lastflag = last_flag;
    solver_->ops->free = free_solver;
    solver_->content = content.release();
}

SecondOrderNewton::~SecondOrderNewton() {
    if (solver_) SUNLinSolFree(solver_);
    if (matrix_) SUNMatDestroy(matrix_);
}

void SecondOrderNewton::form(const double* J, double gamma) {
    auto& f = factor(solver_);
    f.schur.set_jacobian(J);
    f.gamma = gamma;
}

} // namespace phynjo::runtime::sundials
