#pragma once
/// \file
/// What generated models bind to: solving M q'' = f, a type-erased view of a model
/// (LagrangianSystem), and worlds of generalized coordinates. The integrators for such
/// worlds are in integrators/ (lagrangian_rk4, lagrangian_midpoint, dormand_prince).
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/workflow.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace phynjo::runtime {

/// Solves M x = b for a symmetric positive definite N×N matrix M (row-major, overwritten)
/// by LDLᵀ without pivoting; b is overwritten with x. Throws SingularMassMatrix when a pivot
/// is not positive (M not positive definite) and NonFiniteResult for NaN or infinite input.
template <std::size_t N>
inline void solve_spd(double (&M)[N * N], double (&b)[N]) {
    // L is stored below the diagonal, D on it.
    for (std::size_t j = 0; j < N; ++j) {
        double d = M[j * N + j];
        for (std::size_t k = 0; k < j; ++k) d -= M[j * N + k] * M[j * N + k] * M[k * N + k];
        if (!(d > 0)) {
            if (!std::isfinite(d)) throw NonFiniteResult("mass matrix has a non-finite entry");
            throw SingularMassMatrix("mass matrix is not positive definite (pivot " + std::to_string(j) + " is " +
                                     std::to_string(d) + ")");
        }
        M[j * N + j] = d;
        for (std::size_t i = j + 1; i < N; ++i) {
            double s = M[i * N + j];
            for (std::size_t k = 0; k < j; ++k) s -= M[i * N + k] * M[j * N + k] * M[k * N + k];
            M[i * N + j] = s / d;
        }
    }
    for (std::size_t i = 0; i < N; ++i)
        for (std::size_t k = 0; k < i; ++k) b[i] -= M[i * N + k] * b[k];
    for (std::size_t i = 0; i < N; ++i) b[i] /= M[i * N + i];
    for (std::size_t i = N; i-- > 0;)
        for (std::size_t k = i + 1; k < N; ++k) b[i] -= M[k * N + i] * b[k];
}

/// A generated model seen through std::function: what the integrators below need.
struct LagrangianSystem {
    std::size_t dof = 0;
    std::vector<std::string> coordinate_names;
    /// q'' from M q'' = f.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> qddot)>
        accelerations;
    std::function<void(double t, std::span<const double> q, std::span<double> M)> mass_matrix;
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
