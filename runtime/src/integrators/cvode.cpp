// SUNDIALS CVODE (BDF, Newton, direct solver: block elimination of q' = v, or dense) for
// generated models, with the model's exact Jacobian. See integrators/cvode.hpp.
#include "phynjo/runtime/integrators/cvode.hpp"

#include "second_order_linear_solver.hpp"
#include "serial_vector_ops.hpp"
#include "sundials_support.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_proj.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace phynjo::runtime {

struct Cvode::Impl {
    LagrangianSystem sys;
    Options opt;
    std::size_t n = 0, N = 0;
    SUNContext ctx = nullptr;
    N_Vector y = nullptr, dense_y = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver LS = nullptr;
    std::unique_ptr<sundials::SecondOrderNewton> newton; ///< the reduced Newton systems, or A and LS
    void* mem = nullptr;
    bool initialized = false;
    sundials::LastState last;
    std::vector<double> J, q, v;
    std::exception_ptr error;  ///< thrown by the model inside a callback: rethrown after CVode returns
    std::string message;       ///< CVODE's last error message

    /// y' = (q', q'').
    static int rhs(sunrealtype t, N_Vector yv, N_Vector ydot, void* data) {
        auto& k = *static_cast<Impl*>(data);
        const double* y = N_VGetArrayPointer(yv);
        double* d = N_VGetArrayPointer(ydot);
        try {
            for (std::size_t i = 0; i < k.n; ++i) d[i] = y[k.n + i];
            k.sys.accelerations(t, std::span<const double>(y, k.n), std::span<const double>(y + k.n, k.n),
                                std::span<double>(d + k.n, k.n));
        } catch (...) {
            k.error = std::current_exception();
            return -1; // unrecoverable: CVode returns, the exception is rethrown
        }
        return 0;
    }

    /// The exact ∂y'/∂y at (t, y) into J (row-major); false when the model threw (kept in `error`).
    bool evaluate_jacobian(double t, N_Vector yv) {
        const double* at = N_VGetArrayPointer(yv);
        try {
            sys.rhs_jacobian(t, std::span<const double>(at, n), std::span<const double>(at + n, n), J);
        } catch (...) {
            error = std::current_exception();
            return false;
        }
        return true;
    }

    /// The exact ∂y'/∂y into CVODE's dense (column-major) matrix.
    static int jacobian(sunrealtype t, N_Vector yv, N_Vector, SUNMatrix Jm, void* data, N_Vector, N_Vector, N_Vector) {
        auto& k = *static_cast<Impl*>(data);
        if (!k.evaluate_jacobian(t, yv)) return -1;
        for (std::size_t i = 0; i < k.N; ++i)
            for (std::size_t j = 0; j < k.N; ++j)
                SM_ELEMENT_D(Jm, static_cast<sunindextype>(i), static_cast<sunindextype>(j)) = k.J[i * k.N + j];
        return 0;
    }

    /// The reduced Newton matrix I − γJ_v − γ²J_q from the exact Jacobian, re-evaluated
    /// unless CVODE says the last one will do (jok).
    static int linear_system(sunrealtype t, N_Vector yv, N_Vector, SUNMatrix, sunbooleantype jok, sunbooleantype* jcur,
                             sunrealtype gamma, void* data, N_Vector, N_Vector, N_Vector) {
        auto& k = *static_cast<Impl*>(data);
        *jcur = SUNFALSE;
        if (!jok) {
            if (!k.evaluate_jacobian(t, yv)) return -1;
            *jcur = SUNTRUE;
        }
        k.newton->form(k.J.data(), gamma);
        return 0;
    }

    /// Constrained models: the correction onto the constraints after each step.
    static int project(sunrealtype t, N_Vector yv, N_Vector corr, sunrealtype, N_Vector, void* data) {
        auto& k = *static_cast<Impl*>(data);
        const double* y = N_VGetArrayPointer(yv);
        double* c = N_VGetArrayPointer(corr);
        try {
            for (std::size_t i = 0; i < k.n; ++i) {
                k.q[i] = y[i];
                k.v[i] = y[k.n + i];
            }
            project_onto_constraints(k.sys, t, k.q, k.v, k.opt.projection);
            for (std::size_t i = 0; i < k.n; ++i) {
                c[i] = k.q[i] - y[i];
                c[k.n + i] = k.v[i] - y[k.n + i];
            }
        } catch (...) {
            k.error = std::current_exception();
            return -1;
        }
        return 0;
    }

    static void on_error(int, const char* module, const char* function, char* msg, void* data) {
        static_cast<Impl*>(data)->message = std::string(module) + "::" + function + ": " + msg;
    }

    static void check(int flag, const char* what) { sundials::check_setup(flag, "CVODE", what, CVodeGetReturnFlagName); }

    /// Continues from w when it is where the last call left the state, else (re)starts there.
    void prepare(const World& w);

    ~Impl() {
        if (mem) CVodeFree(&mem);
        newton.reset();
        if (LS) SUNLinSolFree(LS);
        if (A) SUNMatDestroy(A);
        if (dense_y) N_VDestroy(dense_y);
        if (y) N_VDestroy(y);
        if (ctx) SUNContext_Free(&ctx);
    }
};

Cvode::Cvode(LagrangianSystem system, Options options) : impl_(std::make_unique<Impl>()) {
    auto& k = *impl_;
    if (options.exact_jacobian && !system.rhs_jacobian)
        throw std::invalid_argument("Cvode: the system has no rhs_jacobian (set Options.exact_jacobian = false)");
    if (!(options.rtol > 0) || !(options.atol > 0))
        throw std::invalid_argument("Cvode: rtol and atol must be positive");
    k.sys = std::move(system);
    k.opt = options;
    k.n = k.sys.dof;
    k.N = 2 * k.n;
    k.J.assign(k.N * k.N, 0.0);
    k.q.assign(k.n, 0.0);
    k.v.assign(k.n, 0.0);
    k.check(SUNContext_Create(nullptr, &k.ctx), "SUNContext_Create");
    const auto N = static_cast<sunindextype>(k.N);
    k.y = N_VNew_Serial(N, k.ctx);
    k.dense_y = N_VNew_Serial(N, k.ctx);
    if (options.exact_jacobian && options.linear_solver == Options::LinearSolver::second_order) {
        k.newton = std::make_unique<sundials::SecondOrderNewton>(k.n, k.ctx);
    } else {
        k.A = SUNDenseMatrix(N, N, k.ctx);
        k.LS = SUNLinSol_Dense(k.y, k.A, k.ctx);
    }
    k.mem = CVodeCreate(CV_BDF, k.ctx);
    if (!k.y || !k.dense_y || (!k.newton && (!k.A || !k.LS)) || !k.mem) throw std::runtime_error("Cvode: out of memory");
    sundials::use_fast_serial_ops(k.y); // CVODE's vectors are clones of y
}

Cvode::~Cvode() = default;

void Cvode::Impl::prepare(const World& w) {
    auto& k = *this;
    double* values = N_VGetArrayPointer(k.y);
    // continue only from where the last call left the state
    if (!k.last.matches(w, k.n)) {
        for (std::size_t i = 0; i < k.n; ++i) {
            values[i] = w.at(kGQ, static_cast<Index>(i));
            values[k.n + i] = w.at(kGV, static_cast<Index>(i));
        }
        if (!k.initialized) {
            k.check(CVodeInit(k.mem, Impl::rhs, w.time, k.y), "CVodeInit");
            k.check(CVodeSetUserData(k.mem, &k), "CVodeSetUserData");
            k.check(CVodeSetErrHandlerFn(k.mem, Impl::on_error, &k), "CVodeSetErrHandlerFn");
            k.check(CVodeSStolerances(k.mem, k.opt.rtol, k.opt.atol), "CVodeSStolerances");
            if (k.newton) {
                k.check(CVodeSetLinearSolver(k.mem, k.newton->solver(), k.newton->matrix()), "CVodeSetLinearSolver");
                k.check(CVodeSetLinSysFn(k.mem, Impl::linear_system), "CVodeSetLinSysFn");
            } else {
                k.check(CVodeSetLinearSolver(k.mem, k.LS, k.A), "CVodeSetLinearSolver");
                if (k.opt.exact_jacobian) k.check(CVodeSetJacFn(k.mem, Impl::jacobian), "CVodeSetJacFn");
            }
            k.check(CVodeSetMaxNumSteps(k.mem, k.opt.max_steps), "CVodeSetMaxNumSteps");
            if (k.sys.n_constraints > 0) k.check(CVodeSetProjFn(k.mem, Impl::project), "CVodeSetProjFn");
            k.initialized = true;
        } else {
            k.check(CVodeReInit(k.mem, w.time, k.y), "CVodeReInit");
        }
    }
}

void Cvode::advance(World& w, double t_end) {
    auto& k = *impl_;
    double* y = N_VGetArrayPointer(k.y);
    k.prepare(w);
    if (t_end == w.time) return;
    // no stop time: CVODE steps past t_end where its error control allows and interpolates
    // back (CV_NORMAL); the next call continues from its internal state
    double t_reached = w.time;
    k.error = nullptr;
    k.message.clear();
    const int flag = CVode(k.mem, t_end, k.y, &t_reached, CV_NORMAL);
    // CVODE projects its steps, not the interpolant between them: the output is projected too
    sundials::finish_advance(w, y, y + k.n, flag, t_reached, t_end, k.sys, k.opt.projection, k.last, k.error, "CVODE",
                             CVodeGetReturnFlagName, k.message);
}

void Cvode::step(World& w, double t_end) {
    auto& k = *impl_;
    sundials::require_after(w, t_end, "Cvode::step");
    double* y = N_VGetArrayPointer(k.y);
    k.prepare(w);
    k.error = nullptr;
    k.message.clear();
    double tn = w.time, t_reached = w.time;
    const int flag = sundials::step_past(
        w.time, tn,
        [&] {
            double now = tn;
            CVodeGetCurrentTime(k.mem, &now);
            return now;
        },
        [&] { return CVode(k.mem, t_end, k.y, &t_reached, CV_ONE_STEP); });
    const double t_out = std::min(tn, t_end);
    // the same interpolant CV_NORMAL gives at its output times
    if (flag >= 0) k.check(CVodeGetDky(k.mem, t_out, 0, k.y), "CVodeGetDky");
    sundials::finish_advance(w, y, y + k.n, flag, t_reached, t_out, k.sys, k.opt.projection, k.last, k.error, "CVODE",
                             CVodeGetReturnFlagName, k.message);
}

void Cvode::dense(double t, std::span<double> q, std::span<double> qdot) const {
    auto& k = *impl_;
    if (q.size() != k.n || qdot.size() != k.n)
        throw std::invalid_argument("Cvode::dense: q and qdot must have length " + std::to_string(k.n));
    if (!k.initialized) throw std::logic_error("Cvode::dense: no step taken yet");
    k.check(CVodeGetDky(k.mem, t, 0, k.dense_y), "CVodeGetDky");
    const double* y = N_VGetArrayPointer(k.dense_y);
    for (std::size_t i = 0; i < k.n; ++i) {
        q[i] = y[i];
        qdot[i] = y[k.n + i];
    }
}

Cvode::Stats Cvode::stats() const {
    Stats s;
    const auto& k = *impl_;
    if (!k.initialized) return s;
    CVodeGetNumSteps(k.mem, &s.steps);
    CVodeGetNumRhsEvals(k.mem, &s.rhs_evaluations);
    CVodeGetNumJacEvals(k.mem, &s.jacobian_evaluations);
    CVodeGetNumLinRhsEvals(k.mem, &s.difference_quotient_rhs);
    CVodeGetNumNonlinSolvIters(k.mem, &s.newton_iterations);
    CVodeGetNumNonlinSolvConvFails(k.mem, &s.newton_failures);
    CVodeGetNumErrTestFails(k.mem, &s.error_test_failures);
    CVodeGetNumLinSolvSetups(k.mem, &s.linear_setups);
    return s;
}

NumericWorkflow lagrangian_cvode(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                               const Cvode::Options& options) {
    return sundials::solver_workflow("cvode", std::make_shared<Cvode>(s, options), s.dof, layout);
}

} // namespace phynjo::runtime
