#pragma once
/// \file
/// Adaptive Dormand–Prince 5(4) for generated models. Order 5 (4 for the error estimate),
/// not symplectic. (source: integrators/dormand_prince.cpp)
#include "phynjo/runtime/system/constraint_projection.hpp"

#include <cstddef>
#include <span>
#include <vector>

namespace phynjo::runtime {

/// Dormand–Prince 5(4) with local error control (FSAL, PI-free classic controller):
/// err = ‖(y5 − y4)/(atol + rtol·|y|)‖_rms ≤ 1 accepts; dt_new = dt·clamp(0.9·err^(−1/5), 0.2, 5).
/// Constrained models (n_constraints > 0): the state is projected onto the constraints
/// after every accepted step (constraint_projection.hpp).
/// Reference: J. R. Dormand, P. J. Prince, J. Comput. Appl. Math. 6, 19 (1980).
class DormandPrince45 {
public:
    struct Options {
        double rtol = 1e-9, atol = 1e-12;
        double dt_min = 1e-12, dt_max = 1.0;
        /// Constrained models: the projection after every accepted step.
        ProjectionOptions projection{};
    };
    DormandPrince45(LagrangianSystem system, Options options);
    /// Advances `w` by one accepted step starting with a trial step `dt` (clipped to
    /// `t_end − w.time`); returns the step taken. Throws ConvergenceError below dt_min.
    double step(World& w, double dt, double t_end);
    /// The step proposed for the next call.
    [[nodiscard]] double next_dt() const noexcept { return next_; }
    /// Continues as the integrator whose next_dt() was `dt` (a run resumed from an archive's
    /// snapshot: the step size is all Dormand–Prince carries from one step to the next).
    void set_next_dt(double dt) noexcept { next_ = dt; }
    [[nodiscard]] std::size_t rejected() const noexcept { return rejected_; }
    /// The continuous extension of the last accepted step (Shampine's dense output of
    /// order 4, as in Hairer's DOPRI5: L. F. Shampine, Math. Comp. 46, 135 (1986)): (q, q')
    /// at time t in [t0, t0 + h] of that step, before any projection. What events are
    /// located on (simulate/events.hpp). std::logic_error before the first step,
    /// std::invalid_argument outside the step.
    void dense(double t, std::span<double> q, std::span<double> v) const;

private:
    LagrangianSystem sys_;
    Options opt_;
    double next_ = 0;
    std::size_t rejected_ = 0;
    std::vector<double> y_, k_[7], tmp_, acc_;
    double dense_t0_ = 0, dense_h_ = 0;
    std::vector<double> rcont_[5]; ///< the dense output's coefficients, 2·dof each
};

} // namespace phynjo::runtime
