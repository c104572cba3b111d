#pragma once
/// \file
/// What generated models bind to: solving M q'' = f, a type-erased view of a model
/// (LagrangianSystem), and worlds of generalized coordinates. The integrators for such
/// worlds are in integrators/ (lagrangian_rk4, lagrangian_midpoint, dormand_prince).
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/workflow.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::runtime {

/// A model parameter defined from others in the model file (`I = 1/2*Mp*R^2`): the generated
/// code computes it from their current values — it follows them — until a value is assigned
/// to it (`P.I = 0.3`), which fixes it. `P.I = Derived::following(v)` makes it follow again.
class Derived {
public:
    /// Assigning a number fixes the parameter at that value.
    constexpr Derived(double value) noexcept : value_(value), set_(true) {} // NOLINT: implicit on purpose
    /// Following its definition; `file_default` is its value at the file's defaults.
    static constexpr Derived following(double file_default) noexcept {
        Derived d(file_default);
        d.set_ = false;
        return d;
    }
    /// True once a value was assigned.
    [[nodiscard]] constexpr bool is_set() const noexcept { return set_; }
    /// The assigned value, or (while following) the value at the file's defaults.
    [[nodiscard]] constexpr double value() const noexcept { return value_; }

private:
    double value_;
    bool set_;
};

/// The relative size below which a pivot (or a 2×2 determinant) counts as zero: the mass
/// matrix is then singular at that state.
inline constexpr double kSingularTolerance = 1e-13;

/// Solves M x = b for a symmetric N×N mass matrix M (row-major; only its lower triangle is
/// read; overwritten); b is overwritten with x. LDLᵀ without pivoting first (every positive
/// definite M: the usual kinetic energy); when a pivot is not positive — an indefinite but
/// invertible M, e.g. Bateman's dual oscillator — LU with partial pivoting on the same M.
/// Throws SingularMassMatrix only when M is singular (a pivot below kSingularTolerance times
/// the largest entry), NonFiniteResult for NaN or infinite input. Allocates nothing.
template <std::size_t N>
inline void solve_symmetric(double (&M)[N * N], double (&b)[N]) {
    double A[N * N]; // the untouched lower triangle, for the pivoted fallback
    for (std::size_t i = 0; i < N * N; ++i) A[i] = M[i];
    // LDLᵀ: L below the diagonal, D on it.
    bool positive = true;
    for (std::size_t j = 0; j < N && positive; ++j) {
        double d = M[j * N + j];
        for (std::size_t k = 0; k < j; ++k) d -= M[j * N + k] * M[j * N + k] * M[k * N + k];
        if (!std::isfinite(d)) throw NonFiniteResult("mass matrix has a non-finite entry");
        if (!(d > 0)) {
            positive = false;
            break;
        }
        M[j * N + j] = d;
        for (std::size_t i = j + 1; i < N; ++i) {
            double s = M[i * N + j];
            for (std::size_t k = 0; k < j; ++k) s -= M[i * N + k] * M[j * N + k] * M[k * N + k];
            M[i * N + j] = s / d;
        }
    }
    if (positive) {
        for (std::size_t i = 0; i < N; ++i)
            for (std::size_t k = 0; k < i; ++k) b[i] -= M[i * N + k] * b[k];
        for (std::size_t i = 0; i < N; ++i) b[i] /= M[i * N + i];
        for (std::size_t i = N; i-- > 0;)
            for (std::size_t k = i + 1; k < N; ++k) b[i] -= M[k * N + i] * b[k];
        return;
    }
    // LU with partial pivoting on the full symmetric matrix rebuilt from its lower triangle.
    double scale = 0;
    for (std::size_t i = 0; i < N; ++i)
        for (std::size_t j = 0; j < N; ++j) {
            M[i * N + j] = i >= j ? A[i * N + j] : A[j * N + i];
            scale = std::max(scale, std::fabs(M[i * N + j]));
        }
    for (std::size_t c = 0; c < N; ++c) {
        std::size_t piv = c;
        for (std::size_t r = c + 1; r < N; ++r)
            if (std::fabs(M[r * N + c]) > std::fabs(M[piv * N + c])) piv = r;
        if (!(std::fabs(M[piv * N + c]) > kSingularTolerance * scale))
            throw SingularMassMatrix("mass matrix is singular (pivot " + std::to_string(c) + " is " +
                                     std::to_string(M[piv * N + c]) + ")");
        if (piv != c) {
            for (std::size_t j = 0; j < N; ++j) std::swap(M[c * N + j], M[piv * N + j]);
            std::swap(b[c], b[piv]);
        }
        for (std::size_t r = c + 1; r < N; ++r) {
            const double f = M[r * N + c] / M[c * N + c];
            for (std::size_t j = c; j < N; ++j) M[r * N + j] -= f * M[c * N + j];
            b[r] -= f * b[c];
        }
    }
    for (std::size_t i = N; i-- > 0;) {
        double x = b[i];
        for (std::size_t j = i + 1; j < N; ++j) x -= M[i * N + j] * b[j];
        b[i] = x / M[i * N + i];
    }
}

/// A generated model seen through std::function: what the integrators below need.
struct LagrangianSystem {
    std::size_t dof = 0;
    std::vector<std::string> coordinate_names;
    /// q'' from M q'' = f.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> qddot)>
        accelerations;
    /// M = ∂²L/∂q'∂q' at (t, q, q') (models whose M does not depend on q' ignore it).
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> M)> mass_matrix;
    /// True when M depends on q' (L not quadratic in the velocities).
    bool mass_depends_on_velocities = false;
    /// p = ∂L/∂q'.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> p)> momenta;
    /// ∂L/∂q + Q − ∂R/∂q': p' in canonical form.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> F)>
        generalized_forces;
    /// E = Σ q' ∂L/∂q' − L.
    std::function<double(double t, std::span<const double> q, std::span<const double> qdot)> energy;
    std::function<void(std::span<double> q, std::span<double> qdot)> initial_state;
};

/// Field ids of a world of generalized coordinates: q (coordinate), qd (velocity), then the
/// stage storage of lagrangian_rk4 (y0 and the accumulator of q and q').
inline constexpr FieldId kGQ = 0, kGV = 1, kGRkQ0 = 2, kGRkV0 = 3, kGRkAQ = 4, kGRkAV = 5;
/// The field names of a world of generalized coordinates, in id order.
inline constexpr std::array<std::string_view, 6> kLagrangianFields{"q", "qd", "rk_q0", "rk_v0", "rk_aq", "rk_av"};

/// A world whose components are the coordinates of `system`, at its initial state.
World make_lagrangian_world(const LagrangianSystem& system);

} // namespace phynjo::runtime
