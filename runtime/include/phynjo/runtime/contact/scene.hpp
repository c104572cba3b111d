#pragma once
/// \file
/// One world for rigid bodies and generated models (docs/language.md, *Shapes*): a Scene holds
/// the rigid bodies, then for every model instance one component per sphere of the model (its
/// *proxy*: position, velocity and radius, kept in step with the model by the rules below) and
/// one component per coordinate (fields `q`, `qd`). The contact rule (contact_solver.hpp)
/// resolves every contact — model sphere against plane, rigid sphere or another instance's
/// sphere — and acts on a model through its sphere Jacobian J_s = ∂X_s/∂q:
///   the sphere's inverse mass matrix  A_s = J_s B_s,  B_s = P M⁻¹ J_sᵀ  (dof×3),
///   an impulse Λ on sphere s:         q' ← q' + B_s Λ,
///   a position correction Δp:         q ← q + B_s Δp,
/// with P = 𝟙 − M⁻¹Gᵀ(G M⁻¹ Gᵀ)⁻¹G the projection that keeps G Δq' = 0 for a constrained
/// model (so an impulse never breaks its constraints), and K⁻¹(u) = uᵀ A_s u the inverse
/// effective mass along u. A model sphere is a point of the model: it has no spin, and an
/// impulse acts at its centre (friction does not turn the link it is on).
///
/// Documented behaviour:
/// - spheres of one instance do not collide with each other (a model's own kinematics decide
///   where its parts go);
/// - a sphere the model cannot move along a contact normal (K⁻¹(n) below 1e-12 of the two
///   sides' scales: a fixed obstacle, or a pendulum pressed along its rod) is a static side; a
///   contact between two static sides is skipped (no impulse, no NaN);
/// - a sphere overlapping something at the start is pushed out by the position correction,
///   like rigid bodies (max_penetration reports it);
/// - a sphere's velocity is J_s q' + ∂X_s/∂t (the time derivative by a central difference,
///   exactly 0 for a model without t); inputs changed between steps move a sphere without
///   giving it a velocity.
#include "phynjo/runtime/contact/contact_solver.hpp"
#include "phynjo/runtime/core/workflow.hpp"
#include "phynjo/runtime/system/constraint_projection.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"
#include "phynjo/runtime/rigid/rigid_world.hpp"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// One instance of a generated model, with its own parameters (bound in `system`, e.g.
/// `pendulum::system(P)`), for make_scene.
struct ModelInstance {
    std::string name;        ///< its components are "<name>.<sphere>" and "<name>.<coordinate>"
    LagrangianSystem system; ///< takes part in contacts through its spheres and capsules
};

/// A model instance as placed in a scene's world.
struct PlacedModel {
    std::string name;
    std::shared_ptr<const LagrangianSystem> system;
    std::vector<Index> coordinates;     ///< components holding q (field `q`) and q' (field `qd`), coordinate order
    std::vector<Index> spheres;         ///< the sphere proxies, sphere order
    std::vector<std::size_t> centre;    ///< offset of each sphere's centre in shape_positions' output
    std::vector<double> radii;          ///< m
    /// Its capsules (no proxy in the world: a contact finds the point on the segment each step).
    std::vector<std::size_t> ends;      ///< offset of each capsule's first end in shape_positions' output
    std::vector<double> capsule_radii;  ///< m
    /// Its boxes (no proxy either: a box's pose is its model's kinematics).
    std::vector<std::size_t> boxes;     ///< offset of each box's centre in shape_positions' output
    std::vector<double> box_half_extents; ///< 3 per box, m
};

/// A world with rigid bodies and model instances (file comment).
struct Scene {
    World world;
    ComponentSet bodies;        ///< the rigid bodies
    ComponentSet spheres;       ///< every model sphere proxy
    std::vector<PlacedModel> models;
    FieldId q = 0, qd = 0;      ///< the fields of the coordinates
};

/// A scene: the rigid bodies of `components` (as make_rigid_world, mass properties validated;
/// spheres, boxes and capsules — the world then has the shape fields), then the `models` at
/// their initial states, then `extra_fields` (e.g. contact_cache_fields()). Proxies have zero
/// mass fields and the sphere's radius. Throws std::invalid_argument for an
/// empty or repeated instance name, a model without shape functions, a non-positive radius or
/// half extent;
/// InvalidBody as make_rigid_world.
Scene make_scene(const Registry& components, const std::vector<RigidBody>& bodies, const std::vector<RigidInit>& init,
                 std::vector<ModelInstance> models, const std::vector<std::string>& extra_fields = {});

/// Sets model k's q and q' (and its proxies). Throws std::invalid_argument for wrong sizes.
void set_model_state(Scene& scene, std::size_t k, std::span<const double> q, std::span<const double> qdot);
/// Model k's q and q' (dof entries each).
std::vector<double> model_q(const Scene& scene, std::size_t k);
std::vector<double> model_qdot(const Scene& scene, std::size_t k);

/// Buffers for sync_model_spheres, reused (no allocation once sized).
struct SphereSync {
    std::vector<double> q, qd, X, Xp, Xm, J;
    std::vector<double> P, V; ///< the spheres' centres and velocities, 3 per sphere
    std::vector<double> Jc;   ///< capsule_jacobians: 6 rows (both ends) per capsule
    std::vector<double> E, EV; ///< the capsules' ends and their velocities, 6 per capsule
    std::vector<double> Jb;   ///< box_jacobians: 6 rows (centre, then ω) per box
    std::vector<double> BX, BV; ///< the boxes' centres and quaternions (7 per box); v and ω (6 per box)
};
/// From s.q, s.qd at time t: s.J (sphere_jacobians), s.P = the sphere centres X_s(t, q),
/// s.V = J_s q' + ∂X_s/∂t (a central difference, h ≈ ε^(1/3): exactly 0 for a model without t),
/// and alike for the capsules' ends: s.Jc, s.E, s.EV; the boxes' poses s.BX, velocities and spins
/// s.BV (ω = J_ω q' + 2 vec(∂q/∂t ⊗ q̄)) and Jacobians s.Jb.
void sphere_states(const PlacedModel& model, double t, SphereSync& s);
/// Writes the proxies of `model` (positions X_s(t, q), velocities J_s q' + ∂X_s/∂t) from its
/// coordinates at time t.
void sync_model_spheres(const PlacedModel& model, FieldId q, FieldId qd, double t, World& w, SphereSync& scratch);

/// How model_rule advances a model over a step.
enum class ModelIntegrator {
    rk4,      ///< lagrangian_rk4 (order 4)
    midpoint, ///< lagrangian_midpoint (order 2, symplectic)
    rattle,   ///< lagrangian_rattle (order 2, symplectic; holonomic constraints only)
};

/// Advances model k by dt with `integrator` (on a private scratch world, copied in and out:
/// the step is a pure function of the model's q, q' and w.time), then syncs its proxies.
/// Domain: q, qd of its coordinates; x, y, z, vx, vy, vz of its spheres.
NumericRule model_rule(const Scene& scene, std::size_t k, ModelIntegrator integrator = ModelIntegrator::rk4,
                       const ProjectionOptions& projection = {});

/// The contact rule of a scene: contact_rule over the rigid bodies and every model sphere
/// (file comment). Domain: that of contact_rule over bodies and spheres, and q, qd of every
/// model coordinate. When run, throws Error (besides contact_rule's) if a model's mass matrix
/// is singular or its constraints are dependent at the current state.
NumericRule contact_rule(const Scene& scene, std::vector<Plane> planes, ContactMaterial material, ContactOptions options);

/// One step of a scene (semi-implicit, as rigid_contact_step):
///   kick_force3d(force) on the bodies · contact_rule(scene) ·
///   par(drift_trans · drift_rot on the bodies, model_rule for every model),
/// so contacts see the bodies after their kick and the models at the start of the step, and a
/// model steps from t to t + dt with the velocities the impulses left it (its "drift"). The
/// models and the drift run on the executor's threads, bit-identical to running them in turn.
NumericWorkflow scene_step(const Scene& scene, const Force3D& force, std::vector<Plane> planes, ContactMaterial material,
                           ContactOptions options, ModelIntegrator integrator = ModelIntegrator::rk4);

/// Kinetic energy of the rigid bodies plus every model's energy E = Σ q' ∂L/∂q' − L, J.
double scene_energy(const Scene& scene);

} // namespace phynjo::runtime
