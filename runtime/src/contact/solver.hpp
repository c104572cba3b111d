#pragma once
// The contact solver (internal to runtime/src/contact): its scratch bodies and rows and the
// Solver — detection.cpp finds the contacts, model_coupling.cpp couples the model spheres of
// scenes, contact_solver.cpp solves (narrow phase → position correction → collisions →
// contact impulses).
// The maths is in contact.hpp; here the sphere geometry is used to shorten it: every lever
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
#include "phynjo/runtime/contact/contact_solver.hpp"
#include "phynjo/runtime/contact/scene.hpp"

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace phynjo::runtime::contact_detail {

struct Body {
    double v[3], w[3], p[3];
    double im;    // 1/m (0 for a model sphere: see `model`)
    double ii[6]; // world inverse inertia: xx, yy, zz, xy, xz, yz
    double r;
    int model = -1;  // a model sphere: its model (ModelScratch), else −1
    int sphere = -1; // its index among that model's spheres
};

/// A model taking part in the contacts: its q, q' during the solve and, at the state of the
/// step, J (3·ns×dof), B = P M⁻¹ Jᵀ (dof×3·ns) and each sphere's A_s = J_s B_s.
struct ModelScratch {
    PlacedModel placed;
    std::size_t first = 0; // scratch index of its first sphere
    std::vector<double> q, qd, dq;
    std::vector<double> A; // 6 per sphere: xx, yy, zz, xy, xz, yz
    // Row-major: M (n × n, then its Cholesky factor), B (n × 3·ns), and for constraints
    // G (nc × n), M⁻¹Gᵀ (n × nc), S = G M⁻¹ Gᵀ (nc × nc, then its factor), G B. J (3·ns × n)
    // is sync.J, from sphere_states at the step's state (scatter overwrites it after the solve).
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
};

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

/// The tangential velocity (v_t1, v_t2) of the contact point of b relative to a's (file comment).
inline void tangent_velocity(const Row& c, const Body& A, const Body& B, double& vt1, double& vt2) {
    const double dv[3] = {A.v[0] - B.v[0], A.v[1] - B.v[1], A.v[2] - B.v[2]};
    vt1 = dot(dv, c.t1) - c.ra * dot(A.w, c.t2) - c.rb * dot(B.w, c.t2);
    vt2 = dot(dv, c.t2) + c.ra * dot(A.w, c.t1) + c.rb * dot(B.w, c.t1);
}

/// Coulomb's disk: scales (x, y) back onto the circle of radius lim if it lies outside.
inline void clamp_disk(double& x, double& y, double lim) {
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
                if (p.spheres.empty()) continue;
                ModelScratch m;
                m.placed = p;
                m.first = ids_.size();
                const LagrangianSystem& s = *p.system;
                const std::size_t n = s.dof, ns = p.spheres.size();
                m.q.resize(n), m.qd.resize(n), m.dq.resize(n);
                m.A.resize(6 * ns);
                const std::size_t nc = s.n_constraints;
                m.M.resize(n * n), m.B.resize(n * 3 * ns);
                m.G.resize(nc * n), m.MinvGt.resize(n * nc), m.S.resize(nc * nc), m.GB.resize(nc * 3 * ns);
                ids_.insert(ids_.end(), p.spheres.begin(), p.spheres.end());
                models_.push_back(std::move(m));
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
        // Scratch for kReservedContactsPerBody sphere contacts per body and one per plane,
        // reserved now so that steps allocate nothing while contacts appear (a falling pile);
        // a scene beyond that grows it once.
        const std::size_t n = ids_.size();
        const std::size_t contacts = n * (kReservedContactsPerBody + planes_.size());
        bodies_.reserve(n + 1);
        snapshot_.reserve(n + 1);
        spheres_.reserve(n);
        margins_.reserve(n);
        contacts_.reserve(contacts);
        rows_.reserve(contacts);
        delta_.reserve(3 * (n + 1));
        split_.reserve(n + 1);
        local_.reserve(layout_->components.size());
        manager_.reserve(n, n * kReservedContactsPerBody);
        if (n_rigid_ < n) model_pairs_.reserve(n * kReservedContactsPerBody);
    }

    void step(double dt, World& w);

private:
    struct Slot {
        FieldId partner, jn, jtx, jty, jtz;
    };

    void gather(const World& w);
    void detect(const World& w, double dt);
    void correct_positions();
    /// Position correction corr·n on one side of a row with a model sphere (rigid or model).
    void position_impulse(const Body& X, std::size_t index, double corr, const double* n, bool jacobi);
    void setup_rows(double dt);
    void warm_start(const World& w);
    void find_slots(const World& w);
    void collisions(double dt);
    void solve_contacts();
    void scatter(World& w);
    /// The unit normal n (from b towards a) and the signed separation at the current positions.
    double geometry(const Row& c, double* n) const;
    void store_cache(World& w) const;
    double curve(const MaterialCurve& c, double speed, bool restitution) const;

    // velocity-level kernels
    void apply_normal(Row& c, double lambda, std::vector<Body>& B);
    void apply_tangent(Row& c, double l1, double l2, std::vector<Body>& B);
    /// Impulse p on one side of a row with a model sphere; for a rigid side, u (tangential
    /// rows: the spin direction, file comment) times its lever r turns it.
    void side_impulse(Body& X, const double* p, const double* u, double r, std::vector<Body>& B);

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
    std::size_t n_rigid_ = 0; // ids_: the rigid bodies, then the models' spheres

    void gather_model(const World& w, ModelScratch& m, std::size_t index);
    void scatter_model(World& w, ModelScratch& m);
    /// Λ on model sphere X: q' += B_s Λ and every sphere of the model follows (velocity level),
    /// or q += B_s Λ and the centres follow (position level).
    void model_impulse(const Body& X, const double* lambda, std::vector<Body>& B, bool position);
    /// The translational inverse mass of X along u: 1/m, or uᵀ A_s u for a model sphere.
    double linear_inverse_mass(const Body& X, const double* u) const {
        return X.model < 0 ? X.im : quad(&models_[static_cast<std::size_t>(X.model)].A[6 * static_cast<std::size_t>(X.sphere)], u);
    }
    /// The size of X's inverse mass (1/m, or tr A_s): what "singular" is measured against.
    double inverse_mass_scale(const Body& X) const {
        if (X.model < 0) return X.im;
        const double* a = &models_[static_cast<std::size_t>(X.model)].A[6 * static_cast<std::size_t>(X.sphere)];
        return a[0] + a[1] + a[2];
    }
    /// Whether a row between a and b has a model sphere on either side.
    bool has_model(const Row& c) const { return bodies_[c.a].model >= 0 || bodies_[c.b].model >= 0; }
};

/// K⁻¹ below this fraction of the two sides' scales: the pair cannot move along u (scene.hpp).
constexpr double kSingularInverseMass = 1e-12;

/// What a contact rule writes of `bodies`: positions, velocities, spins and the warm-start cache.
Domain writes_of(const Layout& layout, const ComponentSet& bodies);
/// What it reads: masses, inertias, radii, orientations.
Domain reads_of(const Layout& layout, const ComponentSet& bodies);
/// std::invalid_argument for a plane, material curve or option out of its range.
void validate(const std::vector<Plane>& planes, const ContactMaterial& material, const ContactOptions& options);

} // namespace phynjo::runtime::contact_detail
