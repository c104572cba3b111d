// SUNDIALS IDA (BDF on the stabilized index-2 equations of motion, Newton, dense direct
// solver) for generated models. See integrators/ida.hpp for the equations.
#include "phynjo/runtime/integrators/ida.hpp"

#include "sundials_support.hpp"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace phynjo::runtime {

namespace {

std::string flag_name(long flag) { return sundials::flag_name(IDAGetReturnFlagName, flag); }

} // namespace

struct Ida::Impl {
    LagrangianSystem sys;
    Options opt;
    std::size_t n = 0, m = 0, mh = 0, N = 0;
    /// Offsets of the unknowns in Y = (q, q', p, λ, μ) …
    std::size_t oQ = 0, oV = 0, oP = 0, oL = 0, oM = 0;
    /// … and of the residual rows (q̇ rows, p rows, ṗ rows, ψ rows, φ_h rows).
    std::size_t rQ = 0, rV = 0, rP = 0, rPsi = 0, rPhi = 0;
    std::vector<std::size_t> holonomic; ///< the holonomic rows of G, in file order
    SUNContext ctx = nullptr;
    N_Vector yy = nullptr, yp = nullptr, id = nullptr, atol = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver LS = nullptr;
    void* mem = nullptr;
    bool initialized = false;
    sundials::LastState last;
    // scratch, sized once: no allocation in a step
    std::vector<double> p, F, G, psi, phi, dp, dF, qt, Gp, Gm, psip, psim, q, v, acc, lambda;
    std::exception_ptr error; ///< thrown by the model inside a callback: rethrown after IDASolve returns
    std::string message;      ///< IDA's last error message

    static std::span<const double> span(const double* x, std::size_t k) { return {x, k}; }

    int residual(double t, const double* y, const double* yd, double* r) {
        const double *q_ = y + oQ, *v_ = y + oV, *p_ = y + oP, *lam = y + oL, *mu = y + oM;
        sys.momenta(t, span(q_, n), span(v_, n), p);
        sys.generalized_forces(t, span(q_, n), span(v_, n), F);
        if (m > 0) {
            sys.constraint_matrix(t, span(q_, n), G);
            sys.constraint_velocity_residuals(t, span(q_, n), span(v_, n), psi);
            sys.constraint_residuals(t, span(q_, n), span(v_, n), phi);
        }
        for (std::size_t i = 0; i < n; ++i) {
            double gmu = 0, glam = 0;
            for (std::size_t k = 0; k < mh; ++k) gmu += G[holonomic[k] * n + i] * mu[k];
            for (std::size_t c = 0; c < m; ++c) glam += G[c * n + i] * lam[c];
            r[rQ + i] = yd[oQ + i] - v_[i] - gmu;
            r[rV + i] = p_[i] - p[i];
            r[rP + i] = yd[oP + i] - F[i] - glam;
        }
        for (std::size_t c = 0; c < m; ++c) r[rPsi + c] = psi[c];
        for (std::size_t k = 0; k < mh; ++k) r[rPhi + k] = phi[holonomic[k]];
        return 0;
    }

    /// ∂R/∂Y + c_j ∂R/∂Ẏ: ∂p and ∂F exact (canonical_jacobian), the constraints' curvature by
    /// central differences of G and ψ in q.
    void jacobian(double t, double cj, const double* y, SUNMatrix J) {
        const double *q_ = y + oQ, *v_ = y + oV, *lam = y + oL, *mu = y + oM;
        SUNMatZero(J);
        auto at = [&](std::size_t i, std::size_t j) -> double& {
            return SM_ELEMENT_D(J, static_cast<sunindextype>(i), static_cast<sunindextype>(j));
        };
        sys.canonical_jacobian(t, span(q_, n), span(v_, n), p, F, dp, dF);
        if (m > 0) sys.constraint_matrix(t, span(q_, n), G);
        for (std::size_t i = 0; i < n; ++i) {
            at(rQ + i, oQ + i) = cj;
            at(rQ + i, oV + i) = -1;
            for (std::size_t k = 0; k < mh; ++k) at(rQ + i, oM + k) = -G[holonomic[k] * n + i];
            at(rV + i, oP + i) = 1;
            at(rP + i, oP + i) = cj;
            for (std::size_t j = 0; j < n; ++j) {
                at(rV + i, oQ + j) = -dp[i * 2 * n + j];
                at(rV + i, oV + j) = -dp[i * 2 * n + n + j];
                at(rP + i, oQ + j) = -dF[i * 2 * n + j];
                at(rP + i, oV + j) = -dF[i * 2 * n + n + j];
            }
            for (std::size_t c = 0; c < m; ++c) at(rP + i, oL + c) = -G[c * n + i];
        }
        for (std::size_t c = 0; c < m; ++c)
            for (std::size_t j = 0; j < n; ++j) at(rPsi + c, oV + j) = G[c * n + j]; // ψ is linear in q'
        for (std::size_t k = 0; k < mh; ++k)
            for (std::size_t j = 0; j < n; ++j) at(rPhi + k, oQ + j) = G[holonomic[k] * n + j];
        if (m == 0) return;
        const double eps = std::cbrt(std::numeric_limits<double>::epsilon());
        for (std::size_t j = 0; j < n; ++j) {
            for (std::size_t i = 0; i < n; ++i) qt[i] = q_[i];
            const double h = eps * std::max(1.0, std::fabs(q_[j]));
            qt[j] = q_[j] + h;
            sys.constraint_matrix(t, qt, Gp);
            sys.constraint_velocity_residuals(t, qt, span(v_, n), psip);
            qt[j] = q_[j] - h;
            sys.constraint_matrix(t, qt, Gm);
            sys.constraint_velocity_residuals(t, qt, span(v_, n), psim);
            const double inv = 1 / (2 * h);
            for (std::size_t i = 0; i < n; ++i) {
                double gmu = 0, glam = 0;
                for (std::size_t k = 0; k < mh; ++k)
                    gmu += (Gp[holonomic[k] * n + i] - Gm[holonomic[k] * n + i]) * mu[k];
                for (std::size_t c = 0; c < m; ++c) glam += (Gp[c * n + i] - Gm[c * n + i]) * lam[c];
                at(rQ + i, oQ + j) -= gmu * inv;
                at(rP + i, oQ + j) -= glam * inv;
            }
            for (std::size_t c = 0; c < m; ++c) at(rPsi + c, oQ + j) = (psip[c] - psim[c]) * inv;
        }
    }

    static int residual_fn(sunrealtype t, N_Vector y, N_Vector yd, N_Vector r, void* data) {
        auto& k = *static_cast<Impl*>(data);
        try {
            return k.residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd), N_VGetArrayPointer(r));
        } catch (...) {
            k.error = std::current_exception();
            return -1; // unrecoverable: IDASolve returns, the exception is rethrown
        }
    }

    static int jacobian_fn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector, N_Vector, SUNMatrix J, void* data,
                           N_Vector, N_Vector, N_Vector) {
        auto& k = *static_cast<Impl*>(data);
        try {
            k.jacobian(t, cj, N_VGetArrayPointer(y), J);
        } catch (...) {
            k.error = std::current_exception();
            return -1;
        }
        return 0;
    }

    static void on_error(int, const char* module, const char* function, char* msg, void* data) {
        static_cast<Impl*>(data)->message = std::string(module) + "::" + function + ": " + msg;
    }

    static void check(int flag, const char* what) { sundials::check_setup(flag, "IDA", what, IDAGetReturnFlagName); }

    /// Y and Ẏ consistent with the world's (q, q') projected onto the constraints: p = ∂L/∂q',
    /// q̈ and λ from the saddle-point system, ṗ = F + Gᵀλ, μ = 0.
    void consistent_state(const World& w) {
        double* y = N_VGetArrayPointer(yy);
        double* yd = N_VGetArrayPointer(yp);
        for (std::size_t i = 0; i < n; ++i) {
            q[i] = w.at(kGQ, static_cast<Index>(i));
            v[i] = w.at(kGV, static_cast<Index>(i));
        }
        if (m > 0) {
            project_onto_constraints(sys, w.time, q, v, opt.projection);
            sys.accelerations_and_multipliers(w.time, q, v, acc, lambda);
            sys.constraint_matrix(w.time, q, G);
        } else {
            sys.accelerations(w.time, q, v, acc);
        }
        sys.momenta(w.time, q, v, p);
        sys.generalized_forces(w.time, q, v, F);
        N_VConst(0.0, yy);
        N_VConst(0.0, yp);
        for (std::size_t i = 0; i < n; ++i) {
            y[oQ + i] = q[i];
            y[oV + i] = v[i];
            y[oP + i] = p[i];
            yd[oQ + i] = v[i];
            yd[oV + i] = acc[i];
            double glam = 0;
            for (std::size_t c = 0; c < m; ++c) glam += G[c * n + i] * lambda[c];
            yd[oP + i] = F[i] + glam;
        }
        for (std::size_t c = 0; c < m; ++c) y[oL + c] = lambda[c];
    }

    ~Impl() {
        if (mem) IDAFree(&mem);
        if (LS) SUNLinSolFree(LS);
        if (A) SUNMatDestroy(A);
        if (atol) N_VDestroy(atol);
        if (id) N_VDestroy(id);
        if (yp) N_VDestroy(yp);
        if (yy) N_VDestroy(yy);
        if (ctx) SUNContext_Free(&ctx);
    }
};

Ida::Ida(LagrangianSystem system, Options options) : impl_(std::make_unique<Impl>()) {
    auto& k = *impl_;
    if (options.exact_jacobian && !system.canonical_jacobian)
        throw std::invalid_argument("Ida: the system has no canonical_jacobian (set Options.exact_jacobian = false)");
    if (!(options.rtol > 0) || !(options.atol > 0)) throw std::invalid_argument("Ida: rtol and atol must be positive");
    k.sys = std::move(system);
    k.opt = options;
    k.n = k.sys.dof;
    k.m = k.sys.n_constraints;
    for (std::size_t c = 0; c < k.m; ++c)
        if (k.sys.constraint_holonomic[c]) k.holonomic.push_back(c);
    k.mh = k.holonomic.size();
    k.N = 3 * k.n + k.m + k.mh;
    k.oQ = k.rQ = 0;
    k.oV = k.rV = k.n;
    k.oP = k.rP = 2 * k.n;
    k.oL = k.rPsi = 3 * k.n;
    k.oM = k.rPhi = 3 * k.n + k.m;
    for (auto* s : {&k.p, &k.F, &k.qt, &k.q, &k.v, &k.acc}) s->assign(k.n, 0.0);
    for (auto* s : {&k.dp, &k.dF}) s->assign(2 * k.n * k.n, 0.0);
    for (auto* s : {&k.G, &k.Gp, &k.Gm}) s->assign(k.m * k.n, 0.0);
    for (auto* s : {&k.psi, &k.phi, &k.psip, &k.psim, &k.lambda}) s->assign(k.m, 0.0);
    Impl::check(SUNContext_Create(nullptr, &k.ctx), "SUNContext_Create");
    const auto N = static_cast<sunindextype>(k.N);
    k.yy = N_VNew_Serial(N, k.ctx);
    k.yp = N_VNew_Serial(N, k.ctx);
    k.id = N_VNew_Serial(N, k.ctx);
    k.atol = N_VNew_Serial(N, k.ctx);
    k.A = SUNDenseMatrix(N, N, k.ctx);
    k.LS = k.yy && k.A ? SUNLinSol_Dense(k.yy, k.A, k.ctx) : nullptr;
    k.mem = IDACreate(k.ctx);
    if (!k.yy || !k.yp || !k.id || !k.atol || !k.A || !k.LS || !k.mem) throw std::runtime_error("Ida: out of memory");
    // q and p are differential and carry the error test; q', λ, μ are algebraic. The index-2
    // multipliers λ, μ are also left out of the Newton convergence test (an absolute
    // tolerance far above any value): their Newton corrections carry the round-off of φ and ψ
    // times c_j ~ 1/h, noise that no iteration removes. They act on the solution only through
    // ṗ and q̇, whose corrections are tested.
    double* id = N_VGetArrayPointer(k.id);
    double* at = N_VGetArrayPointer(k.atol);
    for (std::size_t i = 0; i < k.N; ++i) {
        id[i] = (i < k.oV || (i >= k.oP && i < k.oL)) ? 1.0 : 0.0;
        at[i] = i < k.oL ? options.atol : 1e300;
    }
}

Ida::~Ida() = default;

void Ida::advance(World& w, double t_end) {
    auto& k = *impl_;
    const double* y = N_VGetArrayPointer(k.yy);
    if (!k.last.matches(w, k.n)) {
        // restart from the world (projected onto the constraints), consistent Y and Ẏ
        k.consistent_state(w);
        if (!k.initialized) {
            Impl::check(IDAInit(k.mem, Impl::residual_fn, w.time, k.yy, k.yp), "IDAInit");
            Impl::check(IDASetUserData(k.mem, &k), "IDASetUserData");
            Impl::check(IDASetErrHandlerFn(k.mem, Impl::on_error, &k), "IDASetErrHandlerFn");
            Impl::check(IDASVtolerances(k.mem, k.opt.rtol, k.atol), "IDASVtolerances");
            Impl::check(IDASetLinearSolver(k.mem, k.LS, k.A), "IDASetLinearSolver");
            if (k.opt.exact_jacobian) Impl::check(IDASetJacFn(k.mem, Impl::jacobian_fn), "IDASetJacFn");
            Impl::check(IDASetMaxNumSteps(k.mem, k.opt.max_steps), "IDASetMaxNumSteps");
            Impl::check(IDASetId(k.mem, k.id), "IDASetId");
            Impl::check(IDASetSuppressAlg(k.mem, SUNTRUE), "IDASetSuppressAlg");
            k.initialized = true;
        } else {
            Impl::check(IDAReInit(k.mem, w.time, k.yy, k.yp), "IDAReInit");
        }
    }
    if (t_end == w.time) return;
    double t_reached = w.time;
    k.error = nullptr;
    k.message.clear();
    const int flag = IDASolve(k.mem, t_end, &t_reached, k.yy, k.yp, IDA_NORMAL);
    for (std::size_t i = 0; i < k.n; ++i) {
        w.at(kGQ, static_cast<Index>(i)) = y[k.oQ + i];
        w.at(kGV, static_cast<Index>(i)) = y[k.oV + i];
    }
    w.time = flag < 0 ? t_reached : t_end;
    // IDA's steps satisfy the constraints to its Newton tolerance, its interpolant between
    // them does not quite: the output is projected (IDA's own state is left as it is)
    if (k.m > 0 && flag >= 0 && !k.error)
        project_onto_constraints(k.sys, w.time, w.field(kGQ), w.field(kGV), k.opt.projection);
    k.last.remember(w, k.n);
    if (k.error) std::rethrow_exception(k.error);
    if (flag < 0)
        throw ConvergenceError("IDA stopped at t = " + std::to_string(t_reached) + ": " + flag_name(flag) +
                               (k.message.empty() ? "" : " (" + k.message + ")"));
}

Ida::Stats Ida::stats() const {
    Stats s;
    const auto& k = *impl_;
    if (!k.initialized) return s;
    IDAGetNumSteps(k.mem, &s.steps);
    IDAGetNumResEvals(k.mem, &s.residual_evaluations);
    IDAGetNumJacEvals(k.mem, &s.jacobian_evaluations);
    IDAGetNumLinResEvals(k.mem, &s.difference_quotient_residuals);
    IDAGetNumNonlinSolvIters(k.mem, &s.newton_iterations);
    IDAGetNumNonlinSolvConvFails(k.mem, &s.newton_failures);
    IDAGetNumErrTestFails(k.mem, &s.error_test_failures);
    return s;
}

NumericWorkflow lagrangian_ida(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                               const Ida::Options& options) {
    return sundials::solver_workflow("ida", std::make_shared<Ida>(s, options), s.dof, layout);
}

} // namespace phynjo::runtime
