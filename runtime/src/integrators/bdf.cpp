// phynjo's variable-order BDF (NDF) on y = (q, q'). See integrators/bdf.hpp.
//
// The state between steps is the array D of backward differences of the solution at the
// current step size h: D₀ = y_n, D_j = ∇^j y_n (j ≤ order + 2). A step of order k predicts
// y⁽⁰⁾ = Σ_{j≤k} D_j, then solves the NDF corrector
//     (1 − κ_k) γ_k (y − y⁽⁰⁾) + Σ_{j=1..k} γ_j D_j = h f(t + h, y),   γ_k = Σ_{j≤k} 1/j,
// for d = y − y⁽⁰⁾ by Newton with (I − cJ), c = h / α_k, α_k = (1 − κ_k) γ_k; the local error
// is (κ_k γ_k + 1/(k+1)) d. After order + 1 steps of one size the order may change by one
// (the error estimates of orders k − 1 and k + 1 from D_k and D_{k+2}) and the step is
// rescaled: D := (R(ρ) U)ᵀ D, Shampine & Reichelt's quasi-constant step size.
#include "phynjo/runtime/integrators/bdf.hpp"

#include "sundials_support.hpp"
#include "velocity_schur.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace phynjo::runtime {

namespace {

constexpr int kMaxOrder = 5;
constexpr int kNewtonMaxIterations = 4;
constexpr double kMinFactor = 0.2, kMaxFactor = 10;
/// Newton: converged at a tenth of the error test's allowance; diverging when a correction
/// is over twice the last; the rate estimate decays by 0.3 a step at the most (CVODE's).
constexpr double kConvergence = 0.1, kDivergence = 2, kRateDecay = 0.3;

/// κ_k, γ_k, α_k and the error constants of the NDF orders 1–5 (κ₅ = 0: BDF5).
struct Coefficients {
    std::array<double, kMaxOrder + 2> gamma{}, alpha{}, error{};
    Coefficients() {
        const double kappa[kMaxOrder + 2] = {0, -0.1850, -1.0 / 9.0, -0.0823, -0.0415, 0, 0};
        for (int k = 1; k <= kMaxOrder; ++k) gamma[k] = gamma[k - 1] + 1.0 / k;
        for (int k = 0; k <= kMaxOrder + 1; ++k) {
            alpha[k] = (1 - kappa[k]) * gamma[k];
            error[k] = kappa[k] * gamma[k] + 1.0 / (k + 1);
        }
    }
};
const Coefficients kC;

} // namespace

struct Bdf::Impl {
    LagrangianSystem sys;
    Options opt;
    std::size_t n = 0, N = 0;
    double rate = 1; ///< Newton's rate of convergence, as last seen with the current factors
    // the history
    bool started = false;
    double t = 0, h_abs = 0;
    int order = 1, n_equal_steps = 0;
    std::vector<double> D;   ///< (kMaxOrder + 3) rows of N
    std::vector<double> old; ///< change_D's copy of D₀…D_k
    std::vector<double> J; ///< ∂y'/∂y, row-major N × N, as last evaluated
    integrators::VelocitySchur newton;
    bool factored = false; ///< newton holds the factors of I − cJ for the current J and (nearly) the current c
    // scratch, one N-vector each
    std::vector<double> y_predict, psi, weight, y, d, dy, f;
    sundials::LastState last;
    Stats stats;
    mutable std::vector<double> dense_y; ///< dense()'s scratch

    /// Internal steps until t ≥ t_end, or `one` (the errors of advance).
    void steps_until(World& w, double t_end, bool one);

    Impl(LagrangianSystem s, Options o) : sys(std::move(s)), opt(o), n(sys.dof), N(2 * sys.dof), newton(sys.dof) {
        D.assign((kMaxOrder + 3) * N, 0.0);
        old.assign((kMaxOrder + 1) * N, 0.0);
        J.assign(N * N, 0.0);
        for (auto* v : {&y_predict, &psi, &weight, &y, &d, &dy, &f, &dense_y}) v->assign(N, 0.0);
    }

    double* row(int j) { return D.data() + static_cast<std::size_t>(j) * N; }

    /// out = y' = (q', q'') at (t, y).
    void rhs(double time, const double* at, double* out) {
        ++stats.rhs_evaluations;
        for (std::size_t i = 0; i < n; ++i) out[i] = at[n + i];
        sys.accelerations(time, std::span<const double>(at, n), std::span<const double>(at + n, n),
                          std::span<double>(out + n, n));
    }

    void jacobian(double time, const double* at) {
        ++stats.jacobian_evaluations;
        sys.rhs_jacobian(time, std::span<const double>(at, n), std::span<const double>(at + n, n), J);
        newton.set_jacobian(J.data());
        factored = false;
    }

    /// RMS of x / w with the weights w = atol + rtol |y| (weight holds 1 / w).
    [[nodiscard]] double norm(const double* x) const {
        double s = 0;
        for (std::size_t i = 0; i < N; ++i) {
            const double r = x[i] * weight[i];
            s += r * r;
        }
        return std::sqrt(s / static_cast<double>(N));
    }

    /// D₀…D_k re-expressed for the step size factor·h: D := (R(factor) U)ᵀ D, with
    /// R(ρ)_{ij} = Π_{r=1..i} (r − 1 − ρ j) / r (R₀ⱼ = 1) and U = R(1).
    void change_D(int k, double factor) {
        double R[kMaxOrder + 1][kMaxOrder + 1], U[kMaxOrder + 1][kMaxOrder + 1], RU[kMaxOrder + 1][kMaxOrder + 1];
        auto compute = [k](double rho, double (*M)[kMaxOrder + 1]) {
            for (int j = 0; j <= k; ++j) M[0][j] = 1;
            for (int i = 1; i <= k; ++i) {
                M[i][0] = 0;
                for (int j = 1; j <= k; ++j) M[i][j] = M[i - 1][j] * (i - 1 - rho * j) / i;
            }
        };
        compute(factor, R);
        compute(1.0, U);
        for (int i = 0; i <= k; ++i)
            for (int j = 0; j <= k; ++j) {
                double s = 0;
                for (int m = 0; m <= k; ++m) s += R[i][m] * U[m][j];
                RU[i][j] = s;
            }
        std::copy(D.begin(), D.begin() + static_cast<std::ptrdiff_t>((k + 1) * N), old.begin());
        for (int j = 0; j <= k; ++j) {
            double* Dj = row(j);
            std::fill(Dj, Dj + N, 0.0);
            for (int m = 0; m <= k; ++m) {
                const double r = RU[m][j];
                const double* Om = old.data() + static_cast<std::size_t>(m) * N;
                for (std::size_t c = 0; c < N; ++c) Dj[c] += r * Om[c];
            }
        }
    }

    /// Hairer, Nørsett & Wanner's first step for a method of order 1 (II.4), from f₀ = D₁/h.
    double initial_step(const double* y0, const double* f0) {
        for (std::size_t i = 0; i < N; ++i) weight[i] = 1 / (opt.atol + opt.rtol * std::fabs(y0[i]));
        const double d0 = norm(y0), d1 = norm(f0);
        const double h0 = d0 < 1e-5 || d1 < 1e-5 ? 1e-6 : 0.01 * d0 / d1;
        for (std::size_t i = 0; i < N; ++i) y[i] = y0[i] + h0 * f0[i];
        rhs(t + h0, y.data(), f.data());
        for (std::size_t i = 0; i < N; ++i) dy[i] = f[i] - f0[i];
        const double d2 = norm(dy.data()) / h0;
        const double h1 = d1 <= 1e-15 && d2 <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::sqrt(0.01 / std::max(d1, d2));
        return std::min(100 * h0, h1);
    }

    void start(const World& w) {
        t = w.time;
        double* y0 = row(0);
        for (std::size_t i = 0; i < n; ++i) {
            y0[i] = w.at(kGQ, static_cast<Index>(i));
            y0[n + i] = w.at(kGV, static_cast<Index>(i));
        }
        double* f0 = row(1);
        rhs(t, y0, f0);
        h_abs = opt.first_step > 0 ? opt.first_step : initial_step(y0, f0);
        for (std::size_t i = 0; i < N; ++i) f0[i] *= h_abs;
        order = 1;
        n_equal_steps = 0;
        jacobian(t, y0);
        started = true;
    }

    /// The corrector at t_new by Newton from y_predict (y, d, and the iterations it took).
    /// Converged when the correction, scaled by the rate of convergence seen so far, is a tenth
    /// of what the error test allows — CVODE's test (Hindmarsh et al. 2005, §2.1): it needs no
    /// second iteration to estimate the rate, which carries over from step to step while the
    /// factors do. Diverging when a correction is over twice the last.
    bool solve_corrector(double t_new, double c, int k_order, int& iterations) {
        std::fill(d.begin(), d.end(), 0.0);
        std::copy(y_predict.begin(), y_predict.end(), y.begin());
        const double allowed = kConvergence / kC.error[k_order];
        double dy_norm_old = 0;
        for (int k = 0; k < kNewtonMaxIterations; ++k) {
            iterations = k + 1;
            ++stats.newton_iterations;
            rhs(t_new, y.data(), f.data());
            for (std::size_t i = 0; i < N; ++i) dy[i] = c * f[i] - psi[i] - d[i];
            newton.solve(dy.data(), dy.data());
            const double dy_norm = norm(dy.data());
            if (!std::isfinite(dy_norm)) return false; // a non-finite right side or correction
            if (k > 0) {
                if (dy_norm > kDivergence * dy_norm_old) return false;
                rate = std::max(kRateDecay * rate, dy_norm / dy_norm_old);
            }
            for (std::size_t i = 0; i < N; ++i) {
                y[i] += dy[i];
                d[i] += dy[i];
            }
            if (dy_norm * std::min(1.0, rate) <= allowed) return true;
            dy_norm_old = dy_norm;
        }
        return false;
    }

    /// One accepted step from t; false (t unchanged) when the step size fell too low.
    bool step() {
        const double min_step = 10 * (std::nextafter(t, std::numeric_limits<double>::infinity()) - t);
        if (h_abs > opt.max_step) {
            change_D(order, opt.max_step / h_abs);
            h_abs = opt.max_step;
            n_equal_steps = 0;
            factored = false;
        } else if (h_abs < min_step) {
            change_D(order, min_step / h_abs);
            h_abs = min_step;
            n_equal_steps = 0;
            factored = false;
        }
        bool current_jacobian = false;
        const int k = order;
        double t_new = t, error_norm = 0;
        int iterations = 0;
        for (;;) {
            if (h_abs < min_step) return false;
            t_new = t + h_abs;
            const double h = t_new - t;
            h_abs = h;
            // the predictor, the known part of the corrector, the weights
            const double inv_alpha = 1.0 / kC.alpha[k];
            std::copy(D.begin(), D.begin() + static_cast<std::ptrdiff_t>(N), y_predict.begin());
            std::fill(psi.begin(), psi.end(), 0.0);
            for (int j = 1; j <= k; ++j) {
                const double* Dj = row(j);
                const double g = kC.gamma[j];
                for (std::size_t i = 0; i < N; ++i) {
                    y_predict[i] += Dj[i];
                    psi[i] += g * Dj[i];
                }
            }
            for (std::size_t i = 0; i < N; ++i) {
                psi[i] *= inv_alpha;
                weight[i] = 1 / (opt.atol + opt.rtol * std::fabs(y_predict[i]));
            }
            const double c = h * inv_alpha;
            bool converged = false;
            for (;;) {
                // the factors stay while h does (an error-test failure shortens h and keeps
                // them: Newton converges with them all the same, as in SciPy's BDF)
                if (!factored) {
                    ++stats.factorizations;
                    factored = newton.factor(c) == 0;
                    rate = 1; // unknown for new factors
                    stats.lower_bandwidth = newton.lu().lower();
                    stats.upper_bandwidth = newton.lu().upper();
                }
                converged = factored && solve_corrector(t_new, c, k, iterations);
                if (converged || current_jacobian) break;
                jacobian(t_new, y_predict.data());
                current_jacobian = true;
            }
            if (!converged) {
                ++stats.newton_failures;
                h_abs *= 0.5;
                change_D(k, 0.5);
                n_equal_steps = 0;
                factored = false;
                continue;
            }
            for (std::size_t i = 0; i < N; ++i) {
                weight[i] = 1 / (opt.atol + opt.rtol * std::fabs(y[i]));
                dy[i] = kC.error[k] * d[i];
            }
            error_norm = norm(dy.data());
            if (error_norm <= 1) break;
            ++stats.error_test_failures;
            const double safety = 0.9 * (2 * kNewtonMaxIterations + 1) / (2 * kNewtonMaxIterations + iterations);
            const double factor = std::isfinite(error_norm) ? std::max(kMinFactor, safety * std::pow(error_norm, -1.0 / (k + 1)))
                                                            : kMinFactor;
            h_abs *= factor;
            change_D(k, factor);
            n_equal_steps = 0;
        }
        // accepted: the differences of the new solution, y = D₀
        ++stats.steps;
        ++n_equal_steps;
        t = t_new;
        {
            double *Dk1 = row(k + 1), *Dk2 = row(k + 2);
            for (std::size_t i = 0; i < N; ++i) {
                Dk2[i] = d[i] - Dk1[i];
                Dk1[i] = d[i];
            }
            for (int j = k; j >= 0; --j) {
                double* Dj = row(j);
                const double* Dj1 = row(j + 1);
                for (std::size_t i = 0; i < N; ++i) Dj[i] += Dj1[i];
            }
        }
        stats.order = order;
        if (n_equal_steps < k + 1) return true;
        // order k − 1, k or k + 1 for the next steps, whichever allows the longest step
        const double safety = 0.9 * (2 * kNewtonMaxIterations + 1) / (2 * kNewtonMaxIterations + iterations);
        const double inf = std::numeric_limits<double>::infinity();
        double norms[3] = {inf, error_norm, inf};
        if (k > 1) {
            for (std::size_t i = 0; i < N; ++i) dy[i] = kC.error[k - 1] * D[k * N + i];
            norms[0] = norm(dy.data());
        }
        if (k < kMaxOrder) {
            for (std::size_t i = 0; i < N; ++i) dy[i] = kC.error[k + 1] * D[(k + 2) * N + i];
            norms[2] = norm(dy.data());
        }
        int best = 0;
        double factors[3];
        for (int m = 0; m < 3; ++m) {
            factors[m] = norms[m] == 0 ? inf : std::pow(norms[m], -1.0 / (k + m));
            if (factors[m] > factors[best]) best = m;
        }
        order = k + best - 1;
        const double factor = std::min(kMaxFactor, safety * factors[best]);
        h_abs *= factor;
        change_D(order, factor);
        n_equal_steps = 0;
        factored = false;
        return true;
    }

    /// y at t_out ∈ [t − h, t] from the interpolating polynomial of D₀…D_order into `out`.
    void interpolate(double t_out, double* out) const {
        const double h = h_abs;
        for (std::size_t i = 0; i < N; ++i) {
            double p = 1, s = D[i];
            for (int j = 1; j <= order; ++j) {
                p *= (t_out - (t - h * (j - 1))) / (h * j);
                s += D[j * N + i] * p;
            }
            out[i] = s;
        }
    }

    /// y at t_out ∈ [t − h, t] (interpolate) into the world.
    void output(World& w, double t_out) {
        interpolate(t_out, y.data());
        for (std::size_t i = 0; i < n; ++i) {
            w.at(kGQ, static_cast<Index>(i)) = y[i];
            w.at(kGV, static_cast<Index>(i)) = y[n + i];
        }
        w.time = t_out;
    }
};

Bdf::Bdf(LagrangianSystem system, Options options) {
    if (!system.rhs_jacobian) throw std::invalid_argument("Bdf: the system has no rhs_jacobian");
    if (system.n_constraints > 0)
        throw std::invalid_argument("Bdf: the model has constraints; use Cvode (with its projection) or Ida");
    if (!(options.rtol > 0) || !(options.atol > 0)) throw std::invalid_argument("Bdf: rtol and atol must be positive");
    if (!(options.max_step > 0) || !(options.first_step >= 0) || options.max_steps <= 0)
        throw std::invalid_argument("Bdf: max_step and max_steps must be positive, first_step not negative");
    impl_ = std::make_unique<Impl>(std::move(system), options);
}

Bdf::~Bdf() = default;

void Bdf::Impl::steps_until(World& w, double t_end, bool one) {
    // a failure leaves the world at the last accepted step
    auto stop = [&](const std::string& why) {
        output(w, t);
        last.remember(w, n);
        throw ConvergenceError("Bdf stopped at t = " + std::to_string(t) + ": " + why);
    };
    try {
        for (long taken = 0; t < t_end && !(one && taken == 1); ++taken) {
            if (taken == opt.max_steps)
                stop("max_steps (" + std::to_string(opt.max_steps) + ") internal steps before t = " + std::to_string(t_end));
            if (!step()) stop("the step size fell below 10 ulp of t");
        }
    } catch (const ConvergenceError&) {
        throw;
    } catch (...) {
        output(w, t);
        last.remember(w, n);
        started = false; // the model threw inside a step: start afresh next time
        throw;
    }
}

void Bdf::advance(World& w, double t_end) {
    auto& k = *impl_;
    if (!(t_end >= w.time))
        throw std::invalid_argument("Bdf::advance: t_end " + std::to_string(t_end) + " is before the world's time " +
                                    std::to_string(w.time));
    if (!k.started || !k.last.matches(w, k.n)) k.start(w);
    if (t_end == w.time) {
        k.last.remember(w, k.n);
        return;
    }
    k.steps_until(w, t_end, false);
    k.output(w, t_end);
    k.last.remember(w, k.n);
}

void Bdf::step(World& w, double t_end) {
    auto& k = *impl_;
    sundials::require_after(w, t_end, "Bdf::step");
    if (!k.started || !k.last.matches(w, k.n)) k.start(w);
    // one internal step unless the last one already reaches past the world (its output was interpolated)
    if (!(k.t > w.time)) k.steps_until(w, t_end, true);
    k.output(w, std::min(k.t, t_end));
    k.last.remember(w, k.n);
}

void Bdf::dense(double t, std::span<double> q, std::span<double> qdot) const {
    const auto& k = *impl_;
    if (q.size() != k.n || qdot.size() != k.n)
        throw std::invalid_argument("Bdf::dense: q and qdot must have length " + std::to_string(k.n));
    if (!k.started) throw std::logic_error("Bdf::dense: no step taken yet");
    k.interpolate(t, k.dense_y.data());
    for (std::size_t i = 0; i < k.n; ++i) {
        q[i] = k.dense_y[i];
        qdot[i] = k.dense_y[k.n + i];
    }
}

Bdf::Stats Bdf::stats() const { return impl_->stats; }

NumericWorkflow lagrangian_bdf(const LagrangianSystem& s, const std::shared_ptr<const Layout>& layout,
                               const Bdf::Options& options) {
    return sundials::solver_workflow("bdf", std::make_shared<Bdf>(s, options), s.dof, layout);
}

} // namespace phynjo::runtime
