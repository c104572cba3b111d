#pragma once
/// \file
/// Locating where an event guard crosses zero between two accepted steps (docs/language.md,
/// *Events*: crossings are located, never rounded to the step): the continuous extension of
/// a step of a second-order system, and a bracketing root finder on it.
/// (source: simulate/crossing.cpp)
#include <functional>
#include <span>

namespace phynjo::runtime {

/// The continuous extension of one step of q'' = a(t, q, q') from t0 to t1: the states
/// (q, v) at both ends with their derivatives (v, a), interpolated by cubic Hermite
/// polynomials — q from (q, v), v from (v, a) — in θ = (t − t0)/(t1 − t0):
///     x(θ) = h00(θ)·x0 + h10(θ)·h·x0' + h01(θ)·x1 + h11(θ)·h·x1',
///     h00 = 2θ³ − 3θ² + 1, h10 = θ³ − 2θ² + θ, h01 = −2θ³ + 3θ², h11 = θ³ − θ².
/// Exact at both ends; between them the error is O(h⁴) (plus the integrator's own error):
/// the order of RK4, the choice for it. Holds spans: the caller owns the arrays, and
/// nothing is allocated.
class HermiteStep {
public:
    HermiteStep(double t0, double t1, std::span<const double> q0, std::span<const double> v0, std::span<const double> a0,
                std::span<const double> q1, std::span<const double> v1, std::span<const double> a1);
    /// (q, v) at time t ∈ [t0, t1] into q, v (length dof). std::invalid_argument outside.
    void at(double t, std::span<double> q, std::span<double> v) const;
    [[nodiscard]] double t0() const noexcept { return t0_; }
    [[nodiscard]] double t1() const noexcept { return t1_; }

private:
    double t0_, t1_;
    std::span<const double> q0_, v0_, a0_, q1_, v1_, a1_;
};

/// Where a guard changes sign: the final bracket [lo, hi] (hi − lo ≤ the tolerance, or two
/// adjacent doubles), `time` = hi, the first time known to be across (so that after the
/// event the guard is on its new side), and how many guard evaluations it took.
struct Crossing {
    double time = 0, lo = 0, hi = 0;
    int evaluations = 0;
};

/// A sign change of g in [a, b], given ga = g(a) and gb = g(b) of opposite signs (or one of
/// them 0: that end is the crossing), by the Illinois method — regula falsi that halves the
/// value kept at an end retained twice in a row (M. Dowell, P. Jarratt, BIT 11, 168 (1971);
/// order ≈ 1.44) — with a bisection whenever three steps have not halved the bracket, so it
/// always terminates. Throws std::invalid_argument when ga and gb have the same sign (or are
/// not finite, or a ≥ b), ConvergenceError when g is not finite inside or the bracket has
/// not closed after `max_evaluations`.
Crossing locate_crossing(const std::function<double(double)>& g, double a, double b, double ga, double gb,
                         double tolerance = 1e-12, int max_evaluations = 200);

} // namespace phynjo::runtime
