#pragma once
/// \file
/// What generated models bind to: solving M q'' = f, a type-erased view of a model
/// (LagrangianSystem), and worlds of generalized coordinates. The integrators for such
/// worlds are in integrators/ (lagrangian_rk4, lagrangian_midpoint, dormand_prince).
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/workflow.hpp"
#include "phynjo/runtime/system/detail/derived.hpp"
#include "phynjo/runtime/system/detail/kkt_solve.hpp"
#include "phynjo/runtime/system/detail/symmetric_solve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

namespace phynjo::runtime {

/// A model's shape (docs/language.md, *Shapes*); the codes are the kernel table's.
enum class ModelShape : unsigned char {
    segment = 0, ///< two ends (6 entries of shape_positions), drawn only
    sphere = 1,  ///< a centre (3 entries), collides; sphere_jacobians, sphere_radii
    capsule = 2, ///< two ends (6 entries), collides; capsule_jacobians, capsule_radii
    box = 3,     ///< centre and orientation quaternion w, x, y, z (7 entries); box_jacobians, box_half_extents
};
/// The entries of shape_positions a shape of this kind fills: 3 for a sphere, 7 for a box, 6
/// otherwise.
[[nodiscard]] constexpr std::size_t shape_values(ModelShape kind) noexcept {
    return kind == ModelShape::sphere ? 3 : kind == ModelShape::box ? 7 : 6;
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

    // Fused kernels of generated code (optional; a hand-made system may leave them empty: the
    // integrators then use the functions above, with the same bits).
    /// One step of classical RK4, h long, from (t, q, q') in place, with q'' at (t, q, q') given:
    /// lagrangian_rk4's operations in its order (generated `rk4_step`).
    std::function<void(double t, double h, std::span<double> q, std::span<double> qdot, std::span<const double> qddot)>
        rk4_step;
    /// q'', E and the event guards at one state, as `accelerations`, `energy`, `event_guards`
    /// give them; false where `accelerations` would throw (generated
    /// `accelerations_energy_guards`). What run_one evaluates once per step.
    std::function<bool(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> qddot,
                       double& E, std::span<double> g)>
        accelerations_energy_guards;
    /// rk4_step from (t, q, q') with q'' there in `qddot`, then accelerations_energy_guards at
    /// (t1, q, q') into qddot, E and g (generated `rk4_step_values`): a sweep's step in one call.
    std::function<bool(double t, double h, double t1, std::span<double> q, std::span<double> qdot, std::span<double> qddot,
                       double& E, std::span<double> g)>
        rk4_step_values;
    /// The runs per call of rk4_step_values_lanes_each (lanes::kWidth where the model was compiled).
    std::size_t lane_width = 0;
    /// rk4_step_values for lane_width runs at once, each with its own parameters (generated
    /// `rk4_step_values_lanes_each`, for models without constraints of one or two
    /// coordinates): arrays by component, run l's q_i at q[i*lane_width + l]; `parameters[l]` is
    /// the `parameters` of run l's system, a system of the same model (the same
    /// `parameters_type`); false when some run's values failed; throws what rk4_step_values
    /// throws for some run. Empty when the model has none.
    std::function<bool(const void* const* parameters, const double* t, const double* h, const double* t1, double* q,
                       double* qdot, double* qddot, double* E, double* g)>
        rk4_step_values_lanes_each;
    /// The parameters the functions above read (the generated code's `Parameters`, opaque here;
    /// owned when the system holds a copy) and an address naming their type, which names the
    /// model (generated code's &typeid(Parameters), a model kernel's byte of its own): runs whose
    /// systems have the same address share the lanes of rk4_step_values_lanes_each. Null when
    /// the model has no lane kernels.
    std::shared_ptr<const void> parameters;
    const void* parameters_type = nullptr;

    // Constraints (docs/language.md, *Constraints*), file order; none when n_constraints = 0.
    std::size_t n_constraints = 0;
    std::vector<std::string> constraint_names;
    /// Per constraint: 1 for holonomic φ(q, t) = 0, 0 for nonholonomic a(q, t)·q' + b(q, t) = 0.
    std::vector<unsigned char> constraint_holonomic;
    /// φ: φ(q, t) for holonomic rows, a·q' + b for nonholonomic rows.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> phi)>
        constraint_residuals;
    /// The velocity-level constraints: φ' = G q' + ∂φ/∂t (holonomic rows), φ (nonholonomic rows).
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> psi)>
        constraint_velocity_residuals;
    /// The scales of the residuals (2·n_constraints): Σ|terms| of each φ, then of each
    /// velocity constraint.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> scale)>
        constraint_scales;
    /// G (n_constraints×dof, row-major).
    std::function<void(double t, std::span<const double> q, std::span<double> G)> constraint_matrix;
    /// q'' and λ of M q'' = f + Gᵀλ, G q'' = γ (`accelerations` gives the same q'').
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> qddot,
                       std::span<double> lambda)>
        accelerations_and_multipliers;

    // Events (docs/language.md, *Events*), file order; none when n_events = 0. Driven by
    // EventMonitor (simulate/events.hpp).
    std::size_t n_events = 0;
    std::vector<std::string> event_names;
    /// Per event: −1 when it fires as g falls through 0 (`A < B`), +1 as g rises (`A > B`).
    std::vector<int> event_directions;
    /// Per event: 1 when its action is `stop`.
    std::vector<unsigned char> event_stops;
    /// g = A − B of every event.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> g)>
        event_guards;
    /// The resets of event k, every right side evaluated on (q, q') as given, then stored.
    std::function<void(std::size_t k, double t, std::span<double> q, std::span<double> qdot)> apply_event;

    // Shapes (docs/language.md, *Shapes*), file order; none when n_shapes = 0.
    std::size_t n_shapes = 0;
    std::vector<std::string> shape_names;
    /// Per shape, its kind.
    std::vector<ModelShape> shape_kinds;
    std::size_t n_spheres = 0, n_capsules = 0, n_boxes = 0;
    /// Centres of spheres, ends of segments and capsules (m), boxes' centres (m) and orientation
    /// quaternions (w, x, y, z): file order, shape_values(kind) entries each.
    std::function<void(double t, std::span<const double> q, std::span<double> X)> shape_positions;
    /// Each sphere's ∂(X, Y, Z)/∂q: 3×dof, row-major, spheres in file order.
    std::function<void(double t, std::span<const double> q, std::span<double> J)> sphere_jacobians;
    /// The spheres' radii, m (they follow the parameters).
    std::function<void(std::span<double> r)> sphere_radii;
    /// Each capsule's ∂(X₁, Y₁, Z₁, X₂, Y₂, Z₂)/∂q of its two ends: 6×dof, row-major, capsules in
    /// file order.
    std::function<void(double t, std::span<const double> q, std::span<double> J)> capsule_jacobians;
    /// The capsules' radii, m.
    std::function<void(std::span<double> r)> capsule_radii;
    /// Each box's ∂(X, Y, Z)/∂q of its centre (rows 0–2) and its angular-velocity Jacobian
    /// (rows 3–5: ω = J_ω q', rad/s, world frame): 6×dof, row-major, boxes in file order.
    std::function<void(double t, std::span<const double> q, std::span<double> J)> box_jacobians;
    /// The boxes' half extents (HX, HY, HZ) along the box's own axes, m: 3 per box.
    std::function<void(std::span<double> h)> box_half_extents;
    /// The number of entries of shape_positions: Σ shape_values(kind).
    [[nodiscard]] std::size_t n_shape_values() const noexcept {
        std::size_t n = 0;
        for (ModelShape k : shape_kinds) n += shape_values(k);
        return n;
    }

    // Exact Jacobians (generated code provides them; may be empty for a hand-made system).
    /// ∂y'/∂y of y = (q, q'), y' = (q', q''): (2·dof)×(2·dof), row-major.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> J)>
        rhs_jacobian;
    /// p, F (as `momenta`, `generalized_forces`) and dp = ∂p/∂(q, q'), dF = ∂F/∂(q, q')
    /// (dof×2·dof each, row-major): what the Newton iteration of lagrangian_midpoint needs.
    std::function<void(double t, std::span<const double> q, std::span<const double> qdot, std::span<double> p,
                       std::span<double> F, std::span<double> dp, std::span<double> dF)>
        canonical_jacobian;
};

/// Field ids of a world of generalized coordinates: q (coordinate), qd (velocity), then the
/// stage storage of lagrangian_rk4 (y0 and the accumulator of q and q').
inline constexpr FieldId kGQ = 0, kGV = 1, kGRkQ0 = 2, kGRkV0 = 3, kGRkAQ = 4, kGRkAV = 5;
/// The field names of a world of generalized coordinates, in id order.
inline constexpr std::array<std::string_view, 6> kLagrangianFields{"q", "qd", "rk_q0", "rk_v0", "rk_aq", "rk_av"};

/// A world whose components are the coordinates of `system`, at its initial state.
World make_lagrangian_world(const LagrangianSystem& system);

} // namespace phynjo::runtime
