// Block elimination of q' = v in CVODE's Newton systems (the Schur complement on the
// velocities). See second_order_linear_solver.hpp.
#include "second_order_linear_solver.hpp"

#include <Eigen/Dense>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <memory>
#include <new>

namespace phynjo::runtime::sundials {

/// The solver's content: γ and J as last formed, the LU of S, a work vector.
struct SecondOrderNewton::Factor {
    explicit Factor(Eigen::Index n_) : n(n_), lu(n_), r(n_) {}
    Eigen::Index n;
    double gamma = 0;
    const double* J = nullptr;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;
    Eigen::VectorXd r;
    long last_flag = 0;

    /// J_q: rows n…2n−1, columns 0…n−1 of the row-major (2n)×(2n) J.
    [[nodiscard]] auto Jq() const {
        using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        return Eigen::Map<const Rows, 0, Eigen::OuterStride<>>(J + 2 * n * n, n, n, Eigen::OuterStride<>(2 * n));
    }
};

namespace {

using Factor = SecondOrderNewton::Factor;

Factor& factor(SUNLinearSolver s) { return *static_cast<Factor*>(s->content); }

SUNLinearSolver_Type get_type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
SUNLinearSolver_ID get_id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
int initialize(SUNLinearSolver) { return SUNLS_SUCCESS; }

int setup(SUNLinearSolver s, SUNMatrix A) {
    auto& f = factor(s);
    f.lu.compute(Eigen::Map<const Eigen::MatrixXd>(SM_DATA_D(A), f.n, f.n)); // column-major, as SUNDIALS stores it
    // a zero pivot: recoverable (CVODE retries with a smaller step)
    for (Eigen::Index i = 0; i < f.n; ++i)
        if (f.lu.matrixLU()(i, i) == 0.0) return static_cast<int>(f.last_flag = i + 1);
    return static_cast<int>(f.last_flag = SUNLS_SUCCESS);
}

int solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, double) {
    auto& f = factor(s);
    const Eigen::Index n = f.n;
    const Eigen::Map<const Eigen::VectorXd> b1(N_VGetArrayPointer(b), n), b2(N_VGetArrayPointer(b) + n, n);
    Eigen::Map<Eigen::VectorXd> x1(N_VGetArrayPointer(x), n), x2(N_VGetArrayPointer(x) + n, n);
    f.r.noalias() = f.gamma * (f.Jq() * b1);
    f.r += b2; // before x is written: x and b may be one vector
    x1 = b1;
    x2 = f.lu.solve(f.r);
    x1 += f.gamma * x2;
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
    auto content = std::make_unique<Factor>(static_cast<Eigen::Index>(n));
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
    const Eigen::Index n = f.n;
    f.J = J;
    f.gamma = gamma;
    Eigen::Map<Eigen::MatrixXd> S(SM_DATA_D(matrix_), n, n);
    for (Eigen::Index j = 0; j < n; ++j)
        for (Eigen::Index i = 0; i < n; ++i) {
            const double* row = J + (n + i) * 2 * n;
            S(i, j) = (i == j ? 1.0 : 0.0) - gamma * row[n + j] - gamma * gamma * row[j];
        }
}

} // namespace phynjo::runtime::sundials
