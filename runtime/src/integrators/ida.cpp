// SUNDIALS IDA (BDF on the stabilized index-2 equations of motion, Newton, dense direct
// solver) for generated models. See integrators/ida.hpp for the equations.
#include "phynjo/runtime/integrators/ida.hpp"

#include "serial_vector_ops.hpp"
#include "sundials_support.hpp"

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace phynjo::runtime {

GglEquations::GglEquations(LagrangianSystem system) : sys_(std::move(system)) {
    n_ = sys_.dof;
    m_ = sys_.n_constraints;
    for (std::size_t c = 0; c < m_; ++c)
        if (sys_.constraint_holonomic[c]) holonomic_.push_back(c);
    mh_ = holonomic_.size();
    N_ = 3 * n_ + m_ + mh_;
    off_ = {.q = 0, .v = n_, .p = 2 * n_, .lambda = 3 * n_, .mu = 3 * n_ + m_};
    for (auto* s : {&p_, &F_, &qt_, &q_, &v_, &acc_}) s->assign(n_, 0.0);
    for (auto* s : {&dp_, &dF_}) s->assign(2 * n_ * n_, 0.0);
    for (auto* s : {&G_, &Gp_, &Gm_}) s->assign(m_ * n_, 0.0);
    for (auto* s : {&psi_, &phi_, &psip_, &psim_, &lambda_}) s->assign(m_, 0.0);
}

void GglEquations::residual(double t, std::span<const double> Y, std::span<const double> Yd, std::span<double> R) {
    const std::size_t n = n_, m = m_;
    const auto [oQ, oV, oP, oL, oM] = off_;
    const std::span<const double> q = Y.subspan(oQ, n), v = Y.subspan(oV, n);
    const double *p = Y.data() + oP, *lam = Y.data() + oL, *mu = Y.data() + oM;
    sys_.momenta(t, q, v, p_);
    sys_.generalized_forces(t, q, v, F_);
    if (m > 0) {
        sys_.constraint_matrix(t, q, G_);
        sys_.constraint_velocity_residuals(t, q, v, psi_);
        sys_.constraint_residuals(t, q, v, phi_);
    }
    for (std::size_t i = 0; i < n; ++i) {
        double gmu = 0, glam = 0;
        for (std::size_t k = 0; k < mh_; ++k) gmu += G_[holonomic_[k] * n + i] * mu[k];
        for (std::size_t c = 0; c < m; ++c) glam += G_[c * n + i] * lam[c];
        R[oQ + i] = Yd[oQ + i] - v[i] - gmu;
        R[oV + i] = p[i] - p_[i];
        R[oP + i] = Yd[oP + i] - F_[i] - glam;
    }
    for (std::size_t c = 0; c < m; ++c) R[oL + c] = psi_[c];
    for (std::size_t k = 0; k < mh_; ++k) R[oM + k] = phi_[holonomic_[k]];
}

void GglEquations::jacobian(double t, double cj, std::span<const double> Y, std::span<double> J) {
    const std::size_t n = n_, m = m_, N = N_;
    const auto [oQ, oV, oP, oL, oM] = off_;
    const std::span<const double> q = Y.subspan(oQ, n), v = Y.subspan(oV, n);
    const double *lam = Y.data() + oL, *mu = Y.data() + oM;
    // rows: q̇ rows at oQ, p rows at oV, ṗ rows at oP, ψ rows at oL, φ_h rows at oM
    const std::size_t rQ = oQ, rV = oV, rP = oP, rPsi = oL, rPhi = oM;
    auto at = [&](std::size_t i, std::size_t j) -> double& { return J[j * N + i]; };
    std::fill(J.begin(), J.end(), 0.0);
    sys_.canonical_jacobian(t, q, v, p_, F_, dp_, dF_);
    if (m > 0) sys_.constraint_matrix(t, q, G_);
    for (std::size_t i = 0; i < n; ++i) {
        at(rQ + i, oQ + i) = cj;
        at(rQ + i, oV + i) = -1;
        for (std::size_t k = 0; k < mh_; ++k) at(rQ + i, oM + k) = -G_[holonomic_[k] * n + i];
        at(rV + i, oP + i) = 1;
        at(rP + i, oP + i) = cj;
        for (std::size_t j = 0; j < n; ++j) {
            at(rV + i, oQ + j) = -dp_[i * 2 * n + j];
            at(rV + i, oV + j) = -dp_[i * 2 * n + n + j];
            at(rP + i, oQ + j) = -dF_[i * 2 * n + j];
            at(rP + i, oV + j) = -dF_[i * 2 * n + n + j];
        }
        for (std::size_t c = 0; c < m; ++c) at(rP + i, oL + c) = -G_[c * n + i];
    }
    for (std::size_t c = 0; c < m; ++c)
        for (std::size_t j = 0; j < n; ++j) at(rPsi + c, oV + j) = G_[c * n + j]; // ψ is linear in q'
    for (std::size_t k = 0; k < mh_; ++k)
        for (std::size_t j = 0; j < n; ++j) at(rPhi + k, oQ + j) = G_[holonomic_[k] * n + j];
    if (m == 0) return;
    // the curvature of the constraints: ∂(G_hᵀμ)/∂q, ∂(Gᵀλ)/∂q, ∂ψ/∂q by central differences
    const double eps = std::cbrt(std::numeric_limits<double>::epsilon());
    for (std::size_t j = 0; j < n; ++j) {
        std::copy(q.begin(), q.end(), qt_.begin());
        const double h = eps * std::max(1.0, std::fabs(q[j]));
        qt_[j] = q[j] + h;
        sys_.constraint_matrix(t, qt_, Gp_);
        sys_.constraint_velocity_residuals(t, qt_, v, psip_);
        qt_[j] = q[j] - h;
        sys_.constraint_matrix(t, qt_, Gm_);
        sys_.constraint_velocity_residuals(t, qt_, v, psim_);
        const double inv = 1 / (2 * h);
        for (std::size_t i = 0; i < n; ++i) {
            double gmu = 0, glam = 0;
            for (std::size_t k = 0; k < mh_; ++k) gmu += (Gp_[holonomic_[k] * n + i] - Gm_[holonomic_[k] * n + i]) * mu[k];
            for (std::size_t c = 0; c < m; ++c) glam += (Gp_[c * n + i] - Gm_[c * n + i]) * lam[c];
            at(rQ + i, oQ + j) -= gmu * inv;
            at(rP + i, oQ + j) -= glam * inv;
        }
        for (std::size_t c = 0; c < m; ++c) at(rPsi + c, oQ + j) = (psip_[c] - psim_[c]) * inv;
    }
}

void GglEquations::consistent_values(double t, std::span<const double> q, std::span<const double> qdot,
                                     const ProjectionOptions& projection, std::span<double> Y, std::span<double> Yd) {
    const std::size_t n = n_, m = m_;
    const auto [oQ, oV, oP, oL, oM] = off_;
    std::copy(q.begin(), q.end(), q_.begin());
    std::copy(qdot.begin(), qdot.end(), v_.begin());
    if (m > 0) {
        project_onto_constraints(sys_, t, q_, v_, projection);
        sys_.accelerations_and_multipliers(t, q_, v_, acc_, lambda_);
        sys_.constraint_matrix(t, q_, G_);
    } else {
        sys_.accelerations(t, q_, v_, acc_);
    }
    sys_.momenta(t, q_, v_, p_);
    sys_.generalized_forces(t, q_, v_, F_);
    std::fill(Y.begin(), Y.end(), 0.0);
    std::fill(Yd.begin(), Yd.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        Y[oQ + i] = q_[i];
        Y[oV + i] = v_[i];
        Y[oP + i] = p_[i];
        Yd[oQ + i] = v_[i];
        Yd[oV + i] = acc_[i];
        double glam = 0;
        for (std::size_t c = 0; c < m; ++c) glam += G_[c * n + i] * lambda_[c];
        Yd[oP + i] = F_[i] + glam;
    }
    for (std::size_t c = 0; c < m; ++c) Y[oL + c] = lambda_[c];
    (void)oM;
}

struct Ida::Impl {
    explicit Impl(LagrangianSystem s) : eq(std::move(s)) {}
    GglEquations eq;
    Options opt;
    std::size_t n = 0, N = 0; ///< dof and the size of the equations (eq's, kept at hand)
    SUNContext ctx = nullptr;
    N_Vector yy = nullptr, yp = nullptr, id = nullptr, atol = nullptr, dense_y = nullptr;
    SUNMatrix A = nullptr;
    SUNLinearSolver LS = nullptr;
    void* mem = nullptr;
    bool initialized = false;
    sundials::LastState last;
    std::vector<double> q, v;
    std::exception_ptr error; ///< thrown by the model inside a callback: rethrown after IDASolve returns
    std::string message;      ///< IDA's last error message

    std::span<double> span_of(N_Vector x) const { return {N_VGetArrayPointer(x), N}; }

    static int residual_fn(sunrealtype t, N_Vector y, N_Vector yd, N_Vector r, void* data) {
        auto& k = *static_cast<Impl*>(data);
        try {
            k.eq.residual(t, k.span_of(y), k.span_of(yd), k.span_of(r));
        } catch (...) {
            k.error = std::current_exception();
            return -1; // unrecoverable: IDASolve returns, the exception is rethrown
        }
        return 0;
    }

    static int jacobian_fn(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector, N_Vector, SUNMatrix J, void* data,
                           N_Vector, N_Vector, N_Vector) {
        auto& k = *static_cast<Impl*>(data);
        try {
            k.eq.jacobian(t, cj, k.span_of(y), std::span<double>(SM_DATA_D(J), k.N * k.N));
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

    /// Continues from w when it is where the last call left the state, else (re)starts there
    /// from consistent values.
    void prepare(const World& w);

    ~Impl() {
        if (mem) IDAFree(&mem);
        if (LS) SUNLinSolFree(LS);
        if (A) SUNMatDestroy(A);
        if (atol) N_VDestroy(atol);
        if (dense_y) N_VDestroy(dense_y);
        if (id) N_VDestroy(id);
        if (yp) N_VDestroy(yp);
        if (yy) N_VDestroy(yy);
        if (ctx) SUNContext_Free(&ctx);
    }
};

Ida::Ida(LagrangianSystem system, Options options) {
    if (options.exact_jacobian && !system.canonical_jacobian)
        throw std::invalid_argument("Ida: the system has no canonical_jacobian (set Options.exact_jacobian = false)");
    if (!(options.rtol > 0) || !(options.atol > 0)) throw std::invalid_argument("Ida: rtol and atol must be positive");
    impl_ = std::make_unique<Impl>(std::move(system));
    auto& k = *impl_;
    k.opt = options;
    k.n = k.eq.system().dof;
    k.N = k.eq.size();
    k.q.assign(k.n, 0.0);
    k.v.assign(k.n, 0.0);
    Impl::check(SUNContext_Create(nullptr, &k.ctx), "SUNContext_Create");
    const auto N = static_cast<sunindextype>(k.N);
    k.yy = N_VNew_Serial(N, k.ctx);
    k.yp = N_VNew_Serial(N, k.ctx);
    k.id = N_VNew_Serial(N, k.ctx);
    k.atol = N_VNew_Serial(N, k.ctx);
    k.dense_y = N_VNew_Serial(N, k.ctx);
    k.A = SUNDenseMatrix(N, N, k.ctx);
    k.LS = k.yy && k.A ? SUNLinSol_Dense(k.yy, k.A, k.ctx) : nullptr;
    k.mem = IDACreate(k.ctx);
    if (!k.yy || !k.yp || !k.id || !k.atol || !k.dense_y || !k.A || !k.LS || !k.mem) throw std::runtime_error("Ida: out of memory");
    for (N_Vector v : {k.yy, k.yp}) sundials::use_fast_serial_ops(v); // IDA's vectors are clones of yy
    // q and p are differential and carry the error test; q', λ, μ are algebraic. The index-2
    // multipliers λ, μ are also left out of the Newton convergence test (an absolute
    // tolerance far above any value): their Newton corrections carry the round-off of φ and ψ
    // times c_j ~ 1/h, noise that no iteration removes. They act on the solution only through
    // ṗ and q̇, whose corrections are tested.
    const auto o = k.eq.offsets();
    double* id = N_VGetArrayPointer(k.id);
    double* at = N_VGetArrayPointer(k.atol);
    for (std::size_t i = 0; i < k.N; ++i) {
        id[i] = (i < o.v || (i >= o.p && i < o.lambda)) ? 1.0 : 0.0;
        at[i] = i < o.lambda ? options.atol : 1e300;
    }
}

Ida::~Ida() = default;

void Ida::Impl::prepare(const World& w) {
    auto& k = *this;
    if (!k.last.matches(w, k.n)) {
        // restart from the world (projected onto the constraints), consistent Y and Ẏ
        for (std::size_t i = 0; i < k.n; ++i) {
            k.q[i] = w.at(kGQ, static_cast<Index>(i));
            k.v[i] = w.at(kGV, static_cast<Index>(i));
        }
        k.eq.consistent_values(w.time, k.q, k.v, k.opt.projection, k.span_of(k.yy), k.span_of(k.yp));
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
}

void Ida::advance(World& w, double t_end) {
    auto& k = *impl_;
    const double* y = N_VGetArrayPointer(k.yy);
    k.prepare(w);
    if (t_end == w.time) return;
    double t_reached = w.time;
    k.error = nullptr;
    k.message.clear();
    const int flag = IDASolve(k.mem, t_end, &t_reached, k.yy, k.yp, IDA_NORMAL);
    // IDA's steps satisfy the constraints to its Newton tolerance, its interpolant between
    // them does not quite: the output is projected
    const auto o = k.eq.offsets();
    sundials::finish_advance(w, y + o.q, y + o.v, flag, t_reached, t_end, k.eq.system(), k.opt.projection, k.last,
                             k.error, "IDA", IDAGetReturnFlagName, k.message);
}

void Ida::step(World& w, double t_end) {
    auto& k = *impl_;
    sundials::require_after(w, t_end, "Ida::step");
    const double* y = N_VGetArrayPointer(k.yy);
    k.prepare(w);
    k.error = nullptr;
    k.message.clear();
    double tn = w.time, t_reached = w.time;
    int flag = sundials::step_past(
        w.time, tn,
        [&] {
            double now = tn;
            IDAGetCurrentTime(k.mem, &now);
            return now;
        },
        [&] { return IDASolve(k.mem, t_end, &t_reached, k.yy, k.yp, IDA_ONE_STEP); });
    const double t_out = std::min(tn, t_end);
    // past t_end: IDA_NORMAL takes no step and interpolates there, as advance's call does
    if (flag >= 0 && tn >= t_end) flag = IDASolve(k.mem, t_end, &t_reached, k.yy, k.yp, IDA_NORMAL);
    else if (flag >= 0) Impl::check(IDAGetDky(k.mem, tn, 0, k.yy), "IDAGetDky");
    const auto o = k.eq.offsets();
    sundials::finish_advance(w, y + o.q, y + o.v, flag, t_reached, t_out, k.eq.system(), k.opt.projection, k.last,
                             k.error, "IDA", IDAGetReturnFlagName, k.message);
}

void Ida::dense(double t, std::span<double> q, std::span<double> qdot) const {
    auto& k = *impl_;
    if (q.size() != k.n || qdot.size() != k.n)
        throw std::invalid_argument("Ida::dense: q and qdot must have length " + std::to_string(k.n));
    if (!k.initialized) throw std::logic_error("Ida::dense: no step taken yet");
    Impl::check(IDAGetDky(k.mem, t, 0, k.dense_y), "IDAGetDky");
    const double* y = N_VGetArrayPointer(k.dense_y);
    const auto o = k.eq.offsets();
    for (std::size_t i = 0; i < k.n; ++i) {
        q[i] = y[o.q + i];
        qdot[i] = y[o.v + i];
    }
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
