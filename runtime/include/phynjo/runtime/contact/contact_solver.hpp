#pragma once
/// \file
/// Contacts between bodies (spheres, boxes, capsules: RigidBody::shape) and with static
/// planes, as a rule with a domain: the
/// impulse formulas (restitution curve e(v_n), Coulomb friction curve μ(|v_t|), effective
/// masses with world inertia tensors, Baumgarte position correction with β and slop), solved
/// by Jacobi passes or by Gauss–Seidel (sequential impulses).
///
/// One application of `contact_rule` (after the forces' kick, before the drift):
///  1. broad phase (CollisionManager) and narrow phase at the current positions;
///  2. position correction, `position_iterations` passes: for every contact with depth δ
///     beyond the slop, p_a += β (δ − slop) w_a n, p_b −= β (δ − slop) w_b n, with
///     w = (1/m)/(1/m_a + 1/m_b) (the depth split by inverse masses);
///  3. collisions, up to `restitution_iterations` passes: a contact that is approaching
///     (v_n < 0), will touch within the step (s + v_n dt < 0) and has e(|v_n|) > 0 takes the
///     impulse j_n = −(1 + e) v_n / K_n⁻¹ with friction j_t = clip(−|v_t|/K_t⁻¹, ±μ j_n)
///     (so a row of touching balls passes an impact along, as in Newton's cradle). A contact
///     that carried a load in the previous step (found in the warm-start cache) is resting,
///     not colliding, and takes no restitution: a settling pile does not rattle;
///  4. contacts, `velocity_iterations` passes of projected (accumulated, clamped) impulses:
///     v_n ≥ −max(s, 0)/dt (a gap may close within the step: speculative contacts, no
///     tunnelling) and |j_t| ≤ μ j_n on the tangent disk; warm-started from the impulses of
///     the previous step when the world has contact_cache_fields();
/// with K⁻¹(u) = 1/m_a + 1/m_b + (r_a × u)·I_a⁻¹(r_a × u) + (r_b × u)·I_b⁻¹(r_b × u),
/// I⁻¹ = R I_B⁻¹ Rᵀ, r_a = −r_a n, r_b = +r_b n, and v_rel = (v_a + ω_a × r_a) − (v_b + ω_b × r_b).
///
/// A box or capsule meets a body or a plane through a manifold (manifold.hpp: a normal and up
/// to four points), each point a contact whose lever arms run from the centres to the point
/// (the midpoint of its two surface points). The points of one manifold are solved together:
/// their position corrections (step 2, which then also turns the bodies) and normal impulses
/// (steps 3 and 4) as one linear complementarity problem — K_ij = K⁻¹ between points i and j,
/// the impulses x ≥ 0 with v_n + K x ≥ target and complementarity, from all points pressing
/// down to none — and their friction at the manifold's centre: two tangents limited by
/// μ Σ j_n and a twist about n limited by μ Σ j_n times the points' mean distance from the
/// centre. Visiting a face's points one after another would push and turn a resting box by
/// the order of the visit; together they do not. The warm-start key of a point is its partner
/// and its feature id.
#include "phynjo/runtime/collision/collision_manager.hpp"
#include "phynjo/runtime/collision/narrow_phase.hpp"
#include "phynjo/runtime/core/workflow.hpp"
#include "phynjo/runtime/rigid/rigid_rules.hpp"

#include <functional>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// A material curve: restitution e(|v_n|) ∈ [0, 1] of the approach speed, or friction
/// μ(|v_t|) ≥ 0 of the sliding speed (speeds in m/s).
using MaterialCurve = std::function<double(double speed)>;

/// The same value at every speed.
MaterialCurve constant_curve(double value);
/// e above the threshold speed (m/s), 0 below it: resting contacts do not bounce.
MaterialCurve restitution_curve(double e, double threshold);

struct ContactMaterial {
    MaterialCurve restitution = constant_curve(0);
    MaterialCurve friction = constant_curve(0);
};

enum class ContactScheme {
    gauss_seidel, ///< sequential impulses: each contact sees the impulses applied before it (default)
    /// Jacobi passes: every contact of a pass sees the state at the start of the pass and
    /// the corrections are added after it (parallel in principle). Each body's mass is split
    /// evenly among its contacts (Tonge et al. 2012) so that the corrections of a body with
    /// several contacts do not overshoot; without that a pile never comes to rest.
    jacobi,
};

struct ContactOptions {
    ContactScheme scheme = ContactScheme::gauss_seidel;
    /// Position passes a step, before the velocity passes: each removes β of every contact's
    /// depth beyond the slop that is left. Gauss–Seidel among rigid bodies with shapes (boxes,
    /// capsules; no models): linear in each body's displacement and turn on the step's contacts
    /// and effective masses (solved like the velocity passes' normal impulses, four at once
    /// where `wide`); otherwise on the geometry of the current positions, pass by pass.
    int position_iterations = 4;
    int restitution_iterations = 16;
    int velocity_iterations = 10;
    double baumgarte = 0.2; ///< β ∈ [0, 1]: fraction of the depth beyond the slop removed per pass
    double slop = 1e-4;     ///< m: depth left alone (no micro-corrections)
    /// m: contacts are made this far apart; < 0: per body, min(r, max(2 |v| dt, slop, r/50)), a
    /// pair's margin the sum of its two bodies' — a resting pile beside a fast body keeps its
    /// small margins; r/50 (Bullet's and Box2D's fixed speculative distances are of that size)
    /// keeps the contacts of bodies at rest that nearly touch, so an impact passes down a row
    /// within one step even when the row has opened by a fraction of a millimetre
    double margin = -1;
    BroadPhase broad_phase = BroadPhase::uniform_grid;
    /// Gauss–Seidel among rigid boxes and capsules (no models): `lanes` manifolds with the
    /// same point count, on 2 × lanes different bodies and close together in the pass, solved
    /// at once in SIMD lanes — each moved only past contacts of other bodies, so the pass's
    /// result is that of one at a time (bit for bit wherever the compiler forms the same fused
    /// multiply–adds in both: always without -march=native). false: one at a time.
    bool wide = true;
    /// The lanes of `wide`: 4 or 8; 0 picks 8 where the build targets AVX-512 (one register
    /// holds eight doubles), else 4. The same results whichever.
    int lanes = 0;
};

/// Fields to add to a rigid world (make_rigid_world's extra_fields) for warm starting: per
/// body, `slots` remembered contacts (partner, normal impulse, friction impulse vector). A
/// box's manifolds take up to four each: piles of boxes want 32.
std::vector<std::string> contact_cache_fields(int slots = 16);

/// The contact rule over `bodies` (spheres with radius > 0, boxes, capsules) and the static
/// `planes`; `sphere_pairs` = false skips body–body contacts. Domain: positions, velocities, angular
/// velocities (and the cache fields) of `bodies`, and in a world with shape fields their
/// orientations; reads their mass properties, orientations, radii and shapes. Throws
/// std::invalid_argument for bad options or planes. When run, throws phynjo::runtime::Error
/// if a material curve leaves its range, or a box or capsule is in a scene with models (their
/// spheres meet spheres only, for now).
NumericRule contact_rule(const ComponentSet& bodies, std::vector<Plane> planes, ContactMaterial material,
                         ContactOptions options, const std::shared_ptr<const Layout>& layout, bool sphere_pairs = true);
/// Spheres on the ground y = 0 (contactGroundF).
NumericRule contact_ground(const ComponentSet& bodies, ContactMaterial material, ContactOptions options,
                           const std::shared_ptr<const Layout>& layout);
/// Sphere–sphere contacts only (contactSpheresF).
NumericRule contact_spheres(const ComponentSet& bodies, ContactMaterial material, ContactOptions options,
                            const std::shared_ptr<const Layout>& layout);

/// kick_force3d(force) · contact_rule · drift_trans · drift_rot: one step of a rigid scene
/// with contacts (semi-implicit Euler: forces, then constraints, then positions).
NumericWorkflow rigid_contact_step(const Force3D& force, const ComponentSet& bodies, std::vector<Plane> planes,
                                   ContactMaterial material, ContactOptions options,
                                   const std::shared_ptr<const Layout>& layout);

/// The deepest overlap between two bodies of `bodies` or a body and a plane, m (0 if none).
double max_penetration(const World& w, const ComponentSet& bodies, std::span<const Plane> planes);

} // namespace phynjo::runtime
