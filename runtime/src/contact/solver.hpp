#pragma once
// The contact solver (internal to runtime/src/contact): its scratch bodies and rows and the
// Solver — detection.cpp finds the contacts, model_coupling.cpp couples the model spheres of
// scenes, contact_solver.cpp solves (narrow phase → position correction → collisions →
// contact impulses), block_solver.cpp solves a manifold's points together.
// The maths is in contact_solver.hpp; here the sphere geometry is used to shorten it: every lever
// arm is along the normal (r_a = −r_a n, r_b = +r_b n), so with the right-handed frame
// (n, t1, t2 = n × t1):
//   r_a × n = 0,  r_a × t1 = −r_a t2,  r_a × t2 = r_a t1,  r_b × t1 = r_b t2,  r_b × t2 = −r_b t1,
//   v_n  = (v_a − v_b)·n,
//   v_t1 = (v_a − v_b)·t1 − r_a ω_a·t2 − r_b ω_b·t2,
//   v_t2 = (v_a − v_b)·t2 + r_a ω_a·t1 + r_b ω_b·t1,
//   K⁻¹(n) = 1/m_a + 1/m_b,  K⁻¹(t1) = 1/m_a + 1/m_b + r_a² t2·I_a⁻¹t2 + r_b² t2·I_b⁻¹t2 (t1 ↔ t2 alike),
// and a tangential impulse λ1 t1 + λ2 t2 on a (minus on b) changes the spins by
//   ω_a += r_a I_a⁻¹ u,  ω_b += r_b I_b⁻¹ u,  u = λ2 t1 − λ1 t2.
// A model sphere (scene.hpp) is a body without spin whose translational inverse mass is the
// 3×3 matrix A_s = J_s B_s instead of 1/m 𝟙: 1/m_a in K⁻¹(u) becomes uᵀA_s u, and an impulse
// Λ on it changes its model's q' by B_s Λ, hence the velocity of every sphere s' of that
// model by J_s' B_s Λ.
// A model capsule is two such points, its ends, with no spin: its point at s ∈ [0, 1] along
// the segment moves with J(s) = (1 − s) J₁ + s J₂, so B(s) = (1 − s) B₁ + s B₂ and
// A(s) = (1 − s)² A₁₁ + 2 s (1 − s) sym(A₁₂) + s² A₂₂ with A_ij = J_i B_j. Its contacts are
// sphere rows at that point (a radius-r sphere at the segment's point), s fixed for the step.
// Against a rigid box or capsule a model sphere or capsule is side b of point rows (one row
// per manifold point, no block): its anchor is the point at s plus the surface offset lb
// (world), its velocity that point's, its K⁻¹ share uᵀ A(s) u, and an impulse reaches it
// through B(s).
// A model box is a body that moves and spins with its model: G = [J_c; J_ω] (6 × dof) maps q'
// to its centre's velocity and spin, B_box = M⁻¹ Gᵀ, and A_box = G B_box (6 × 6) is its
// generalised inverse mass. It is side b of point rows against planes (the static body as side
// a, the points in the world), rigid bodies and other models' spheres, capsules and boxes (a
// model side a: at its point sa, or, a box, at its lever arm), anchored in its own frame as a rigid body is;
// a contact at the lever arm r from its centre sees g = (u, r × u) and the share gᵀ A_box g of
// K⁻¹ along u, and an impulse P reaches q' as B_box (P, r × P). A manifold's points form a
// block as two rigid bodies' do (K_pq's b-side g_pᵀ A_box g_q; one wrench per pass).
// A row of a manifold (a box or capsule against anything: a "point" row) has general lever
// arms r_a = x − p_a, r_b = x − p_b from the centres to the contact point x (the midpoint of
// its two surface points):
//   v_rel = (v_a + ω_a × r_a) − (v_b + ω_b × r_b),
//   K⁻¹(u) = 1/m_a + 1/m_b + (r_a × u)·I_a⁻¹(r_a × u) + (r_b × u)·I_b⁻¹(r_b × u),
// and an impulse P on a (−P on b) changes v_a by P/m_a and ω_a by I_a⁻¹(r_a × P) (b alike,
// negated). Its surface points are kept as anchors in the bodies' frames, so the position
// correction sees the separation at the corrected positions and orientations.
#include "phynjo/runtime/collision/manifold.hpp"
#include "phynjo/runtime/contact/contact_solver.hpp"
#include "phynjo/runtime/contact/scene.hpp"
#include "phynjo/runtime/rigid/rigid_world.hpp"

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

namespace phynjo::runtime::contact_detail {

// Aligned to a cache line: the lanes read v and ω as one 48-byte row (LaneBodies::gather),
// which then lies in one line instead of straddling two.
struct alignas(64) Body {
    double v[3], w[3], p[3];
    double im;    // 1/m (0 for a model sphere: see `model`)
    double ii[6]; // world inverse inertia: xx, yy, zz, xy, xz, yz
    double r;
    int model = -1;  // a model sphere or capsule: its model (ModelScratch), else −1
    int sphere = -1; // its index among that model's spheres (capsules, for a capsule)
    // Worlds with shape fields only (and model capsules: shape):
    double q[4] = {1, 0, 0, 0}; // orientation (w, x, y, z)
    double h[3] = {0, 0, 0};    // RigidBody::half_extents
    Shape shape = Shape::sphere;
    // A model capsule: p and v are its first end's, p2 and v2 its second's.
    double p2[3] = {0, 0, 0}, v2[3] = {0, 0, 0};
};

/// Whether X is a model capsule (its rows are at a point s along it: Row::sa, sb).
inline bool is_model_capsule(const Body& X) { return X.model >= 0 && X.shape == Shape::capsule; }
/// Whether X is a model box (it spins: its rows have lever arms, its impulses are wrenches).
inline bool is_model_box(const Body& X) { return X.model >= 0 && X.shape == Shape::box; }
/// The position (p2 = false: p, v) or velocity of X's point at s: a model capsule's
/// (1 − s) x₁ + s x₂, else X's own.
inline const double* at_fraction(const Body& X, double s, bool velocity, double* tmp) {
    const double* x1 = velocity ? X.v : X.p;
    if (!is_model_capsule(X)) return x1;
    const double* x2 = velocity ? X.v2 : X.p2;
    for (int k = 0; k < 3; ++k) tmp[k] = (1 - s) * x1[k] + s * x2[k];
    return tmp;
}

/// A model taking part in the contacts: its q, q' during the solve and, at the state of the
/// step, the Jacobians of its points — the spheres' centres, then both ends of each capsule —
/// B = P M⁻¹ Jᵀ (dof × 3·points) and each sphere's A_s = J_s B_s (each capsule's A₁₁, A₂₂, sym A₁₂).
struct ModelScratch {
    PlacedModel placed;
    std::size_t first = 0;         // scratch index of its first sphere
    std::size_t first_capsule = 0; // scratch index of its first capsule (after the static body)
    std::size_t first_box = 0;     // scratch index of its first box (after every capsule)
    std::vector<double> q, qd, dq;
    // 6 per sphere, then 18 per capsule (A₁₁, A₂₂, sym A₁₂): xx, yy, zz, xy, xz, yz each; then
    // 36 per box: G B_box (6 × 6 row-major, symmetrised) with G its centre's and spin's Jacobian
    std::vector<double> A;
    // Row-major: M (n × n, then its Cholesky factor), B (n × 3·points), and for constraints
    // G (nc × n), M⁻¹Gᵀ (n × nc), S = G M⁻¹ Gᵀ (nc × nc, then its factor), G B. The points'
    // Jacobians are sync.J and sync.Jc, from sphere_states at the step's state (scatter
    // overwrites them after the solve).
    std::vector<double> M, B, G, MinvGt, S, GB;
    SphereSync sync;
};

struct Row {
    std::uint32_t a, b; // scratch bodies (b = the static body for planes)
    int plane;
    double n[3], t1[3], t2[3];
    double ra, rb;               // radii (rb = 0 for planes)
    double mn, mt1, mt2;         // effective masses 1/K⁻¹
    double sep, bias;            // separation, minimum normal velocity
    double mu;
    double jn, jt1, jt2;         // accumulated impulses
    int slot;                    // its warm-start slot in the cache, −1 if none: a contact with
                                 // a slot carried a load in the previous step (it is resting)
    Index home;                  // find_slots: the component whose slot it is
    double sa = 0, sb = 0;       // a model capsule side: the contact's fraction s along it
    // Point rows (manifolds; file comment):
    bool point = false;
    std::uint16_t plane_a = 0;   // a model's point row with the static body as side a: its plane + 1
    std::uint32_t feature = 0;   // ManifoldPoint::feature: with b, the warm-start key
    double la[3], lb[3];         // surface points in a's and b's body frames (b's: world for a plane,
                                 // the offset from the point at sb for a model side)
    double xa[3], xb[3];         // lever arms r_a, r_b at the velocity solve (linear_positions:
                                 // until setup_rows, the world points found, la and lb unused)
    std::uint8_t block_size = 1; // on a manifold's first row: its point count (0 on the others;
                                 // 1 on each row of a manifold with a model side)
    int block = -1;              // setup_blocks: the Block of a manifold of 2+ points (all its rows)
};

/// A manifold of 2 to 4 points (setup_blocks): their normal impulses solved together, and
/// its friction at its centre — two tangents and a twist about the normal, limited by μ Σ jn
/// (and μ Σ jn times the points' mean distance from the centre) — so that the order in which
/// the points are visited leaves no net push or turn: a resting box stays put.
struct Block {
    /// Not zeroed (1 kB): fill_block writes what is read (as WideGroupOf's).
    Block() {} // NOLINT(modernize-use-equals-default): = default would zero it in emplace_back
    // What the velocity passes read, together (a block's rows only when no set of points solves it).
    std::uint32_t a = 0, b = 0; // its rows' scratch bodies
    std::size_t count = 0;
    std::size_t first = 0;      // its first row
    double n[3];                // its rows' normal
    double jn[4], bias[4];      // solve_contacts: the points' normal impulses and minimum velocities
                                // (push_positions: bias = −separation at detection − slop)
    // Point j's u_j = r_a,j × n; r_b,j × n = u_j + off with off = (p_a − p_b) × n (the lever
    // arms differ by p_a − p_b; 0 against a plane, whose static body never turns). A point's
    // normal velocity is n·(v_a − v_b) + (ω_a − ω_b)·u_j − ω_b·off, and the impulses λ_j n
    // turn a by I_a⁻¹ Σ λ_j u_j and b by −I_b⁻¹ (Σ λ_j u_j + Σ λ_j off), once per body.
    double ua[4][3];
    double off[3];
    double k[16];               // K, 4 × 4 row-major, the first count × count used
    double inv[16];             // fill_block: K's pseudo-inverse (all the points pressing)
    double ra[3], rb[3];        // lever arms of the centre (the mean of the points)
    double t1[3], t2[3];        // the tangents of its rows
    double mt1, mt2, mtw;       // effective masses along t1, t2 at the centre and of the twist
    double reach;               // mean distance of the points from the centre, m
    double mu;
    double jt1, jt2, jtw;       // accumulated friction impulses and twist (N·s, N·m·s)
    bool set_known = false;     // fill_block has filled k and inv
    // The last smaller set that solved the block and its (K_SS + 1e-9 diag)⁻¹: the iterations
    // of a step mostly find the same points pressing, tried right after the full set.
    unsigned last_set = 0;
    bool last_known = false; // last_set is set (the empty set too: points held apart)
    double last_inv[16];
    // solve_lcp's (K_SS + 1e-9 diag)⁻¹ of the smaller sets S, each computed once a step (when
    // first tried; bit i of subsets_known: the i-th set of the search order): a block's search
    // comes back to the same sets pass after pass. n × n each, packed (3-point sets, then
    // 2-point, then single points: 64 doubles for four points).
    std::uint16_t subsets_known = 0;
    double subset_inv[64];
};

/// L blocks with the same point count (or L point rows) on 2L different bodies (pack_groups),
/// laid out lane by lane so that a velocity pass solves them at once (wide_solver.cpp): their
/// per-step constants, the impulses they accumulate, and the last set of pressing points that
/// solved each, its inverse padded to the block's points (zero outside the set). L = 4 (one
/// AVX register of doubles) or 8 (one AVX-512 register).
template <int L>
struct WideGroupOf {
    static constexpr int kLanes = L;
    /// Not zeroed (3 kB at L = 4): load_groups fills what the lanes read.
    WideGroupOf() {} // NOLINT(modernize-use-equals-default): = default would zero it in emplace_back
    std::uint32_t block[L], a[L], b[L];
    int count = 0; // points per block (2 to 4; 4 takes blocks of 3 too, padded: points); 1: L
                   // point rows (block: their rows; ra, rb their lever arms xa, xb; jn[0], bias[0]
                   // and mn their normal's)
    alignas(64) double n[3][L], ra[3][L], rb[3][L], t1[3][L], t2[3][L], off[3][L];
    double mt1[L], mt2[L], mtw[L], reach[L], mu[L], mn[L];
    double jt1[L], jt2[L], jtw[L];
    double jn[4][L], bias[4][L];
    double ua[4][3][L];
    double k[16][L], inv[16][L];
    double last[16][L];
    double points[L]; // the lane's block's points (count, or fewer: the rest padded)
    double known[L];  // 1 where the lane's last set is known
    double in[4][L];  // 1 where point j is in the lane's last set
    // The lanes' bodies' inverse masses and world inverse inertias (Body::im, ii), constant in a
    // step: read here in order, not gathered from 2L bodies at every pass.
    double aim[L], bim[L], aii[6][L], bii[6][L];
};

/// The lanes ContactOptions::lanes = 0 picks: 8 where the build targets AVX-512 (32 registers
/// of eight doubles hold a group's bodies and points), else 4 (eight lanes in 16 AVX
/// registers would spill).
#if defined(__AVX512F__)
inline constexpr int kMachineLanes = 8;
#else
inline constexpr int kMachineLanes = 4;
#endif

inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void mul_sym(const double* m, const double* u, double* out) {
    out[0] = m[0] * u[0] + m[3] * u[1] + m[4] * u[2];
    out[1] = m[3] * u[0] + m[1] * u[1] + m[5] * u[2];
    out[2] = m[4] * u[0] + m[5] * u[1] + m[2] * u[2];
}
inline double quad(const double* m, const double* u) {
    double t[3];
    mul_sym(m, u, t);
    return dot(u, t);
}

inline void tangent_basis(const double* n, double* t1, double* t2) {
    // t1 ⟂ n from the world axis least aligned with n; t2 = n × t1.
    double a[3] = {0, 0, 0};
    const double ax = std::abs(n[0]), ay = std::abs(n[1]), az = std::abs(n[2]);
    a[ax <= ay && ax <= az ? 0 : (ay <= az ? 1 : 2)] = 1;
    t1[0] = n[1] * a[2] - n[2] * a[1];
    t1[1] = n[2] * a[0] - n[0] * a[2];
    t1[2] = n[0] * a[1] - n[1] * a[0];
    const double l = std::sqrt(dot(t1, t1));
    for (int k = 0; k < 3; ++k) t1[k] /= l;
    t2[0] = n[1] * t1[2] - n[2] * t1[1];
    t2[1] = n[2] * t1[0] - n[0] * t1[2];
    t2[2] = n[0] * t1[1] - n[1] * t1[0];
}

inline void cross(const double* a, const double* b, double* out) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/// A point row's v_rel = (v_a + ω_a × r_a) − (v_b + ω_b × r_b) (file comment; a model sphere or
/// capsule side has no spin and moves with its point at its fraction).
inline void point_velocity(const Row& c, const Body& A, const Body& B, double* dv) {
    double wa[3], wb[3], t[3], s[3];
    cross(A.w, c.xa, wa);
    cross(B.w, c.xb, wb);
    const double* va = at_fraction(A, c.sa, true, s);
    const double* vb = at_fraction(B, c.sb, true, t);
    for (int k = 0; k < 3; ++k) dv[k] = va[k] + wa[k] - vb[k] - wb[k];
}

/// K⁻¹(u) at lever arms ra, rb (file comment), each side's share scaled by sa, sb (Jacobi's
/// mass splitting; 1 for Gauss–Seidel).
inline double point_inverse_mass(const Body& A, const Body& B, const double* ra, const double* rb, const double* u,
                                 double sa, double sb) {
    double ua[3], ub[3];
    cross(ra, u, ua);
    cross(rb, u, ub);
    return sa * (A.im + quad(A.ii, ua)) + sb * (B.im + quad(B.ii, ub));
}

/// The tangential velocity (v_t1, v_t2) of the contact point of b relative to a's (file comment).
inline void tangent_velocity(const Row& c, const Body& A, const Body& B, double& vt1, double& vt2) {
    if (c.point) {
        double dv[3];
        point_velocity(c, A, B, dv);
        vt1 = dot(dv, c.t1);
        vt2 = dot(dv, c.t2);
        return;
    }
    double ta[3], tb[3];
    const double* va = at_fraction(A, c.sa, true, ta);
    const double* vb = at_fraction(B, c.sb, true, tb);
    const double dv[3] = {va[0] - vb[0], va[1] - vb[1], va[2] - vb[2]};
    vt1 = dot(dv, c.t1) - c.ra * dot(A.w, c.t2) - c.rb * dot(B.w, c.t2);
    vt2 = dot(dv, c.t2) + c.ra * dot(A.w, c.t1) + c.rb * dot(B.w, c.t1);
}

/// The normal velocity v_rel·n of a row.
inline double normal_velocity(const Row& c, const Body& A, const Body& B) {
    if (c.point) {
        double dv[3];
        point_velocity(c, A, B, dv);
        return dot(dv, c.n);
    }
    double ta[3], tb[3];
    const double* va = at_fraction(A, c.sa, true, ta);
    const double* vb = at_fraction(B, c.sb, true, tb);
    return (va[0] - vb[0]) * c.n[0] + (va[1] - vb[1]) * c.n[1] + (va[2] - vb[2]) * c.n[2];
}

/// The rotation of q by the small angle θ (rad, world frame): q ← normalise(q + ½ (0, θ) ⊗ q).
inline void rotate_by(double* q, const double* th) {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    q[0] = w - 0.5 * (th[0] * x + th[1] * y + th[2] * z);
    q[1] = x + 0.5 * (th[0] * w + th[1] * z - th[2] * y);
    q[2] = y + 0.5 * (th[1] * w + th[2] * x - th[0] * z);
    q[3] = z + 0.5 * (th[2] * w + th[0] * y - th[1] * x);
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; ++k) q[k] /= n;
}

/// Coulomb's disk: scales (x, y) back onto the circle of radius lim if it lies outside.
inline void clamp_disk(double& x, double& y, double lim) {
    // |(x, y)|² against lim² first: the square root only for the friction that slides.
    if (!(x * x + y * y > lim * lim)) return;
    const double mag = std::sqrt(x * x + y * y);
    if (mag > lim) {
        const double s = mag > 0 ? lim / mag : 0;
        x *= s;
        y *= s;
    }
}

/// Contacts per body the scratch is reserved for (12 equal spheres can touch one; the
/// warm-start cache keeps 16 by default).
constexpr std::size_t kReservedContactsPerBody = 16;

class Solver {
public:
    Solver(const ComponentSet& bodies, std::vector<Plane> planes, ContactMaterial material, ContactOptions options,
           std::shared_ptr<const Layout> layout, bool sphere_pairs, const Scene* scene = nullptr)
        : ids_(bodies.indices().begin(), bodies.indices().end()), planes_(std::move(planes)),
          material_(std::move(material)), options_(options), layout_(std::move(layout)), sphere_pairs_(sphere_pairs),
          manager_(options.broad_phase) {
        n_rigid_ = ids_.size();
        if (scene != nullptr) {
            q_field_ = scene->q;
            qd_field_ = scene->qd;
            for (const PlacedModel& p : scene->models) {
                if (p.spheres.empty() && p.ends.empty() && p.boxes.empty()) continue;
                ModelScratch m;
                m.placed = p;
                m.first = ids_.size();
                m.first_capsule = n_capsules_; // made absolute once ids_ is complete
                m.first_box = n_boxes_;
                const LagrangianSystem& s = *p.system;
                const std::size_t n = s.dof, ns = p.spheres.size(), nk = p.ends.size(), nx = p.boxes.size();
                const std::size_t np = 3 * (ns + 2 * nk) + 6 * nx; // B's columns
                m.q.resize(n), m.qd.resize(n), m.dq.resize(n);
                m.A.resize(6 * ns + 18 * nk + 36 * nx);
                const std::size_t nc = s.n_constraints;
                m.M.resize(n * n), m.B.resize(n * np);
                m.G.resize(nc * n), m.MinvGt.resize(n * nc), m.S.resize(nc * nc), m.GB.resize(nc * np);
                ids_.insert(ids_.end(), p.spheres.begin(), p.spheres.end());
                n_capsules_ += nk;
                n_boxes_ += nx;
                models_.push_back(std::move(m));
            }
            for (ModelScratch& m : models_) {
                m.first_capsule += ids_.size() + 1;
                m.first_box += ids_.size() + 1 + n_capsules_;
            }
        }
        for (int k = 0;; ++k) {
            const std::string s = std::to_string(k);
            auto find = [&](const std::string& name) -> int {
                for (std::size_t f = 0; f < layout_->fields.size(); ++f)
                    if (layout_->fields[f] == name) return static_cast<int>(f);
                return -1;
            };
            const int p = find("wc_partner#" + s);
            if (p < 0) break;
            slots_.push_back({static_cast<FieldId>(p), layout_->field("wc_jn#" + s), layout_->field("wc_jtx#" + s),
                              layout_->field("wc_jty#" + s), layout_->field("wc_jtz#" + s)});
        }
        shape_field_ = shape_field(*layout_);
        lanes_ = options_.lanes == 0 ? kMachineLanes : options_.lanes;
        ids_contiguous_ = !ids_.empty();
        for (std::size_t k = 1; k < ids_.size(); ++k) ids_contiguous_ = ids_contiguous_ && ids_[k] == ids_[0] + k;
        // Scratch for kReservedContactsPerBody sphere contacts per body and one per plane,
        // reserved now so that steps allocate nothing while contacts appear (a falling pile);
        // a scene beyond that grows it once.
        const std::size_t n = ids_.size();
        const std::size_t contacts = n * (kReservedContactsPerBody + planes_.size());
        bodies_.reserve(n + 1 + n_capsules_ + n_boxes_);
        snapshot_.reserve(n + 1 + n_capsules_ + n_boxes_);
        spheres_.reserve(n);
        margins_.reserve(n);
        contacts_.reserve(contacts);
        rows_.reserve(contacts);
        schedule_.reserve(contacts);
        delta_.reserve(3 * (n + 1));
        split_.reserve(n + 1);
        local_.reserve(layout_->components.size());
        slots_used_.reserve(n);
        impacts_.reserve(contacts);
        manager_.reserve(n, n * kReservedContactsPerBody);
        if (n_rigid_ < n) model_pairs_.reserve(n * kReservedContactsPerBody);
        if (shape_field_ >= 0) { // manifolds: up to 4 points a pair
            bounds_.reserve(n);
            turns_.reserve(n);
            sphere_pairs_list_.reserve(n * kReservedContactsPerBody);
            point_rows_.reserve(5 * contacts); // as rows_: detect_shapes may swap them
            rows_.reserve(5 * contacts);
            turn_.reserve(3 * (n + 1));
            blocks_.reserve(contacts);
            schedule_.reserve(5 * contacts);
            pos_blocks_.reserve(contacts);
            impacts_.reserve(5 * contacts);
            saved_.reserve(6 * (n + 1));
            stamp_.reserve(n + 1);
            skip_.reserve(5 * contacts + 1);
            item_bodies_.reserve(5 * contacts);
            sorted_.reserve(5 * contacts);
            groups4_.reserve(lanes_ == 4 ? contacts / 4 + 1 : 0);
            groups8_.reserve(lanes_ == 8 ? contacts / 8 + 1 : 0);
            group_start_.reserve(contacts / 4 + 1);
        }
    }

    void step(double dt, World& w);

private:
    /// detect for a world with shape fields: bounds of every shape through the broad phase,
    /// then spheres as before and every other pair by its manifold (point rows).
    void detect_shapes(const World& w, double dt);
    /// contacts_ (sphere contacts) → rows_, in scratch indices.
    void spheres_to_rows(const World& w);
    /// The rows of the model capsules: against planes (at an end), spheres and other models'
    /// capsules (at the closest points), within the margins; against rigid boxes and capsules
    /// point rows (side b).
    void capsule_rows(double dt);
    /// Point rows of the models' boxes (side b) against planes (the static body as side a), rigid
    /// bodies and other models' spheres, capsules and boxes (side a).
    void model_box_rows(double dt);
    /// The speculative margins of a model capsule (detect's of a sphere, at its faster end) and
    /// of a model box (detect's of a rigid box, at its fastest corner).
    double model_capsule_margin(const Body& b, double dt) const;
    double model_box_margin(const Body& X, double dt) const;
    /// detect_shapes' part for the models' spheres: against the rigid bodies (sphere rows with
    /// spheres, point rows with boxes and capsules), other models' spheres and the planes.
    void model_sphere_contacts();
    /// Point rows of a manifold between body a (rigid, the static body, or a model's shape) and
    /// model shape b (normal from b towards a); `axis_a`, `axis_b` (a model capsule's, else null)
    /// give each point's fraction s along it; `plane`: a is the static body of that plane.
    void add_model_manifold(const Manifold& m, std::uint32_t a, std::uint32_t b, const Capsule* axis_a, const Capsule* axis_b,
                            int plane = -1);

    /// Point rows from a manifold between scratch bodies a and b (b = the static body and
    /// `plane` its plane for a plane).
    void add_manifold(const Manifold& m, std::uint32_t a, std::uint32_t b, int plane);
    /// The world surface points of a point row at the current positions.
    void anchors(const Row& c, double* xa, double* xb) const;
    /// A point row's impulse P on a (−P on b) at its lever arms.
    void apply_point(const Row& c, const double* p, std::vector<Body>& B);
    /// Where a row's warm start is kept: `components` components from `first` (side a's own, or
    /// a model's coordinates, pooled, for a row whose side a has no component), the slot counter
    /// of store_cache, and its key.
    struct CacheHome {
        const Index* first = nullptr;
        std::size_t components = 0, counter = 0;
        double key = 0;
    };
    /// False for a row that is not cached (a model capsule's sphere rows).
    bool cache_home(const Row& c, CacheHome& h) const;
    struct Slot {
        FieldId partner, jn, jtx, jty, jtz;
    };

    void gather(const World& w);
    void detect(const World& w, double dt);
    void correct_positions();
    /// Position correction corr·n on one side of a row with a model sphere (rigid or model); at
    /// fraction s of a model capsule, applied at once (also under Jacobi: its points differ).
    /// The position correction `target` (β × depth beyond the slop) of a row with a model side
    /// (a sphere row, or a point row between two models) through both sides' uᵀ A u along n
    /// (at the lever arms arm_a, arm_b of model boxes); false if they cannot move along n.
    bool correct_model_sides(const Row& c, const double* n, double target, const double* arm_a, const double* arm_b, bool jacobi);
    void position_impulse(const Body& X, std::size_t index, double corr, const double* n, bool jacobi, double s,
                          const double* arm = nullptr);
    void setup_rows(double dt);
    void warm_start(const World& w);
    void find_slots(const World& w);
    void collisions(double dt);
    void solve_contacts();
    void setup_blocks();
    /// Gauss–Seidel in a world of rigid bodies with shapes (options_.wide): groups of lanes_
    /// blocks with the same point count on 2 lanes_ different bodies, each block moved ahead in
    /// the schedule only past items on other bodies (so the pass's result is the schedule's).
    void pack_groups();
    template <int L>
    void pack_groups(std::vector<WideGroupOf<L>>& groups);
    /// The groups of L lanes (groups4_ or groups8_).
    template <int L>
    std::vector<WideGroupOf<L>>& groups() {
        if constexpr (L == 8) return groups8_;
        else return groups4_;
    }
    /// f(std::integral_constant<int, lanes_>{}): where the lane count picks the code.
    template <class F>
    decltype(auto) with_lanes(F&& f) {
        if (lanes_ == 8) return f(std::integral_constant<int, 8>{});
        return f(std::integral_constant<int, 4>{});
    }
    /// The friction of a row (limited by its previous normal impulse) with the velocities of
    /// `from`, applied to bodies_.
    void solve_row_friction(Row& c, const std::vector<Body>& from);
    /// The normal impulse of a row with the velocities of `from`, applied to bodies_.
    void solve_row_normal(Row& c, const std::vector<Body>& from);
    /// A block's friction and twist at its centre, limited by μ Σ jn of the previous pass.
    void solve_block_friction(Block& k, const std::vector<Body>& from);
    /// A block's normal impulses together (solve_block), or its points as rows when no set
    /// solves them. `lanes_tried`: the lanes tried the first sets of the search already
    /// (solve_lcp).
    void solve_block_normal(Block& k, const std::vector<Body>& from, bool lanes_tried = false);
    /// WideGroups from blocks_ (after the warm start), and their impulses back into blocks_.
    /// `constants` false: only what the warm start and the position passes change (the
    /// impulses, biases and last sets), the rest loaded already this step.
    void load_groups(bool constants = true);
    template <int L>
    void load_groups(std::vector<WideGroupOf<L>>& groups, bool constants);
    void store_groups();
    /// One velocity pass over the schedule (solve_contacts), its groups in L lanes.
    template <int L>
    void velocity_pass(const std::vector<Body>& from);
    /// One velocity pass over a group of M-point blocks: solve_block_friction, then
    /// solve_block_normal, for its L blocks at once — the same operations lane by lane; a
    /// lane that neither the full set nor its last set solves goes through solve_block_normal.
    template <int M, int L>
    void solve_group(WideGroupOf<L>& g);
    /// One velocity pass over a group of L point rows: solve_row_friction, then
    /// solve_row_normal, at once.
    template <int L>
    void solve_rows(WideGroupOf<L>& g);
    /// The friction of a block at its centre (l1, l2 along t1, t2) and its twist ltw about n.
    void apply_central(const Block& k, double l1, double l2, double ltw, std::vector<Body>& B);
    /// The normal impulses of the block (k.jn, read against k.bias) with the velocities of
    /// `from`, applied to bodies_; false (nothing applied) when no set of pressing points solves it.
    bool solve_block(Block& k, const std::vector<Body>& from, bool lanes_tried = false);
    /// Normal impulses totalling `total` with moments u = Σ λ_j u_j (a's) at a block's points,
    /// side b rigid or static: v_a += total n/m_a, ω_a += I_a⁻¹u, v_b −= total n/m_b,
    /// ω_b −= I_b⁻¹(u + total off). u is overwritten.
    void apply_block_normals(const Block& k, double total, double* u);
    /// x ≥ 0 with w = b + K x ≥ bias, complementary, from the largest set of pressing points down.
    /// `lanes_tried`: the lanes (wide_solver.cpp) found that the full set, the last set, the
    /// guess and the sinking points do not solve it — the same arithmetic, so they are skipped.
    bool solve_lcp(Block& k, const double* b, const double* bias, double* x, bool lanes_tried = false) const;
    /// K of m points with lever arms ra, rb and normal n between A and B (split masses sa, sb),
    /// its pseudo-inverse, and u_j, off, n; `plane`: b is a plane's static body.
    void fill_block(const Body& A, const Body& B, const double* n, const double (*ra)[3], const double (*rb)[3],
                    std::size_t m, double sa, double sb, bool plane, Block& k) const;
    /// fill_block for m an int or a std::integral_constant (with_fixed_count: block_inverse.hpp).
    template <class Size>
    void fill_block_of(const Body& A, const Body& B, const double* n, const double (*ra)[3], const double (*rb)[3], Size m,
                       double sa, double sb, bool plane, Block& k) const;
    /// A model box X's share of K: g₁ᵀ A_box g₂ for the wrenches g = (force, moment).
    double model_box_k(const Body& X, const double* g1, const double* g2) const;
    /// The wrench (force, moment) on a model box X (about its centre) as Δq' (Δq and turns when
    /// `position`), every point of its model followed.
    void model_wrench(const Body& X, const double* force, const double* moment, std::vector<Body>& B, bool position);
    /// m.dq added to its q' (q when `position`), and every point of the model moved with it.
    void follow_model(ModelScratch& m, std::vector<Body>& B, bool position);
    /// K⁻¹ along u at lever arms ra, rb (point_inverse_mass, or with a model box as side b, and
    /// side a rigid or another model's box).
    double point_k(const Body& A, const Body& B, const double* ra, const double* rb, const double* u, double sa, double sb) const {
        if (!is_model_box(B)) return point_inverse_mass(A, B, ra, rb, u, sa, sb);
        double h[6] = {u[0], u[1], u[2], 0, 0, 0}, g[6] = {u[0], u[1], u[2], 0, 0, 0};
        cross(ra, u, h + 3);
        cross(rb, u, g + 3);
        return sa * (is_model_box(A) ? model_box_k(A, h, h) : A.im + quad(A.ii, h + 3)) + sb * model_box_k(B, g, g);
    }
    /// Whether the position passes are linear (linear_positions.cpp): Gauss–Seidel in a world
    /// of rigid bodies with shapes and no models.
    bool linear_positions() const;
    /// The linear position passes (after setup_rows; linear_positions.cpp), then the rows'
    /// separations and speculative biases at the moved positions.
    void push_positions(double dt);
    /// One linear position pass of a row or a block (bias: −separation at detection − slop;
    /// the bodies' v, w: their displacements and turns so far); false if not deeper than the
    /// slop (or, a block, no set of points solves it).
    bool push_row(Row& c);
    bool push_block(Block& k, bool lanes_tried = false);
    /// push_block and push_row of a group's L blocks or rows at once (wide_solver.cpp);
    /// true if any lane moved.
    template <int M, int L>
    bool push_group(WideGroupOf<L>& g);
    template <int L>
    bool push_rows(WideGroupOf<L>& g);
    /// One position pass over the schedule (push_positions), its groups in L lanes; true if
    /// anything moved.
    template <int L>
    bool position_pass();
    /// Gauss–Seidel position correction of the manifold from rows_[first] (k: its K, filled
    /// when !k.set_known); false if no point is deeper than the slop.
    bool correct_block(std::size_t first, Block& k);
    void scatter(World& w);
    /// The unit normal n (from b towards a) and the signed separation at the current positions.
    double geometry(const Row& c, double* n) const;
    void store_cache(World& w);
    double curve(const MaterialCurve& c, double speed, bool restitution) const;

    // velocity-level kernels
    void apply_normal(Row& c, double lambda, std::vector<Body>& B);
    void apply_tangent(Row& c, double l1, double l2, std::vector<Body>& B);
    /// Impulse p on one side of a row with a model sphere (at fraction s of a model capsule); for
    /// a rigid side, u (tangential rows: the spin direction, file comment) times its lever r turns it.
    void side_impulse(Body& X, const double* p, const double* u, double r, double s, std::vector<Body>& B);

    std::vector<Index> ids_;
    std::vector<Plane> planes_;
    ContactMaterial material_;
    ContactOptions options_;
    std::shared_ptr<const Layout> layout_;
    bool sphere_pairs_;
    CollisionManager manager_;
    std::vector<Slot> slots_;

    // scratch, reused every step (no steady-state allocation)
    std::vector<Body> bodies_; // ids_.size() bodies, then one static body
    std::vector<Body> snapshot_; // Jacobi: the bodies at the start of a pass
    std::vector<SphereBB> spheres_;
    std::vector<double> margins_; // per body (detect)
    std::vector<CandidatePair> model_pairs_; // the broad phase's pairs and those of model spheres
    std::vector<Contact> contacts_;
    std::vector<Row> rows_;
    std::vector<double> delta_; // Jacobi position accumulators: 3 per body
    std::vector<double> split_; // Jacobi: contacts per body (mass splitting)
    std::vector<Index> local_;  // component → scratch index (for pair lookup)
    std::vector<ModelScratch> models_;
    FieldId q_field_ = 0, qd_field_ = 0;
    int shape_field_ = -1;              // shape_field(layout): −1 in a world of spheres
    std::vector<AABB> bounds_;          // detect_shapes: per body
    std::vector<Eigen::Matrix3d> turns_; // detect_shapes: each box's rotation matrix
    std::vector<CandidatePair> sphere_pairs_list_; // detect_shapes: the sphere–sphere pairs
    std::vector<Row> point_rows_;       // detect_shapes: the manifolds' rows
    std::vector<double> turn_;          // Jacobi position correction: 3 rotation components per body
    std::vector<Block> blocks_;
    // setup_blocks: the velocity passes' order — a row that is no manifold's (its index), or a
    // block (−1 − its index) — so that a pass reads a block without its rows.
    std::vector<std::int64_t> schedule_;
    std::vector<Block> pos_blocks_; // correct_positions: K of each manifold, once a step
    std::vector<double> saved_;     // push_positions: each body's v and ω while the passes use them
    // pack_groups: a window stamp per body, whether each schedule item is in a group already,
    // the reordered schedule, the groups and each group's first position in schedule_.
    struct ItemBodies {
        std::uint32_t a, b, kind;
    };
    std::vector<ItemBodies> item_bodies_;
    std::vector<std::uint32_t> stamp_;
    std::vector<std::uint32_t> slots_used_; // store_cache: the slots each body (then each model's pool) has filled
    std::vector<std::size_t> impacts_;      // find_slots: the first rows of the items that may strike
    std::vector<std::uint32_t> skip_; // pack_groups: j for an open item j, else towards the next open one
    std::vector<std::int64_t> sorted_;
    int lanes_ = 0; // the groups' lanes (options_.lanes, 0 resolved): 4 or 8
    std::vector<WideGroupOf<4>> groups4_;
    std::vector<WideGroupOf<8>> groups8_;
    std::vector<std::size_t> group_start_;
    bool ids_contiguous_ = false; // ids_ are one or more consecutive components (a field's values for them: one run)
    std::size_t n_rigid_ = 0; // ids_: the rigid bodies, then the models' spheres
    std::size_t n_capsules_ = 0; // the models' capsules: scratch bodies after the static body
    std::size_t n_boxes_ = 0;    // the models' boxes: scratch bodies after the capsules

    void gather_model(const World& w, ModelScratch& m, std::size_t index);
    void scatter_model(World& w, ModelScratch& m);
    /// Λ on model sphere X (at fraction s of a model capsule): q' += B_s Λ and every sphere and
    /// capsule end of the model follows (velocity level), or q += B_s Λ and the points follow
    /// (position level).
    /// Λ on X (a model sphere, capsule at s, or box at the lever arm `arm` from its centre: the
    /// wrench (Λ, arm × Λ)) as Δq' (Δq when `position`), every point of the model followed.
    void model_impulse(const Body& X, const double* lambda, std::vector<Body>& B, bool position, double s = 0,
                       const double* arm = nullptr);
    /// The translational inverse mass of X along u: 1/m, uᵀ A_s u for a model sphere, uᵀ A(s) u
    /// at fraction s of a model capsule (file comment).
    double linear_inverse_mass(const Body& X, const double* u, double s = 0, const double* arm = nullptr) const {
        if (X.model < 0) return X.im;
        const ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
        const auto j = static_cast<std::size_t>(X.sphere);
        if (X.shape == Shape::box) { // gᵀ A_box g, g = (u, arm × u)
            double g[6] = {u[0], u[1], u[2], 0, 0, 0};
            if (arm != nullptr) cross(arm, u, g + 3);
            return model_box_k(X, g, g);
        }
        if (X.shape != Shape::capsule) return quad(&m.A[6 * j], u);
        const double* a = &m.A[6 * m.placed.spheres.size() + 18 * j];
        return (1 - s) * (1 - s) * quad(a, u) + s * s * quad(a + 6, u) + 2 * s * (1 - s) * quad(a + 12, u);
    }
    /// The size of X's inverse mass (1/m, tr A_s, or tr A₁₁ + tr A₂₂): what "singular" is
    /// measured against.
    double inverse_mass_scale(const Body& X) const {
        if (X.model < 0) return X.im;
        const ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
        const auto j = static_cast<std::size_t>(X.sphere);
        if (X.shape == Shape::box) {
            const double* a = &m.A[6 * m.placed.spheres.size() + 18 * m.placed.ends.size() + 36 * j];
            return a[0] + a[7] + a[14];
        }
        if (X.shape != Shape::capsule) return m.A[6 * j] + m.A[6 * j + 1] + m.A[6 * j + 2];
        const double* a = &m.A[6 * m.placed.spheres.size() + 18 * j];
        return a[0] + a[1] + a[2] + a[6] + a[7] + a[8];
    }
    /// Whether a row between a and b has a model sphere on either side.
    bool has_model(const Row& c) const { return bodies_[c.a].model >= 0 || bodies_[c.b].model >= 0; }
};

/// The manifold of two bodies that are not both spheres (normal from B towards A), or of a
/// body that is not a sphere and a plane; false if there is none.
/// ra, rb (optional): the bodies' rotation matrices, when known (a box's are used).
bool collide(const Body& A, const Body& B, double margin, Manifold& m, const Eigen::Matrix3d* ra = nullptr,
             const Eigen::Matrix3d* rb = nullptr);
bool collide_plane(const Body& A, const Plane& plane, double margin, Manifold& m, const Eigen::Matrix3d* ra = nullptr);
/// A rigid body of a world with shape fields as a scratch body: its position, orientation,
/// shape and size (for the narrow phase only).
Body shape_body(const World& w, Index i, int shape_field);

/// K⁻¹ below this fraction of the two sides' scales: the pair cannot move along u (scene.hpp).
constexpr double kSingularInverseMass = 1e-12;

/// What a contact rule writes of `bodies`: positions, velocities, spins and the warm-start cache.
Domain writes_of(const Layout& layout, const ComponentSet& bodies);
/// What it reads: masses, inertias, radii, orientations.
Domain reads_of(const Layout& layout, const ComponentSet& bodies);
/// std::invalid_argument for a plane, material curve or option out of its range.
void validate(const std::vector<Plane>& planes, const ContactMaterial& material, const ContactOptions& options);

} // namespace phynjo::runtime::contact_detail
