// The contact rule: narrow phase → position correction → collisions → contact impulses.
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

#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/rigid/rigid_world.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace phynjo::runtime {

MaterialCurve constant_curve(double value) {
    return [value](double) { return value; };
}
MaterialCurve restitution_curve(double e, double threshold) {
    return [e, threshold](double speed) { return speed > threshold ? e : 0.0; };
}

std::vector<std::string> contact_cache_fields(int slots) {
    if (slots < 1 || slots > 64) throw std::invalid_argument("contact_cache_fields: slots must be in 1..64");
    std::vector<std::string> f;
    for (const char* base : {"wc_partner#", "wc_jn#", "wc_jtx#", "wc_jty#", "wc_jtz#"})
        for (int k = 0; k < slots; ++k) f.push_back(base + std::to_string(k));
    return f;
}

namespace {

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

void tangent_basis(const double* n, double* t1, double* t2) {
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

/// L Lᵀ = A in place (row-major n×n; the lower triangle becomes L); false unless A is
/// positive definite (a pivot at or below 1e-14 of the largest diagonal entry).
bool cholesky(double* A, std::size_t n) {
    double dmax = 0;
    for (std::size_t i = 0; i < n; ++i) dmax = std::max(dmax, A[i * n + i]);
    for (std::size_t j = 0; j < n; ++j) {
        double d = A[j * n + j];
        for (std::size_t k = 0; k < j; ++k) d -= A[j * n + k] * A[j * n + k];
        if (!(d > 1e-14 * dmax)) return false;
        d = std::sqrt(d);
        A[j * n + j] = d;
        for (std::size_t i = j + 1; i < n; ++i) {
            double v = A[i * n + j];
            for (std::size_t k = 0; k < j; ++k) v -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = v / d;
        }
    }
    return true;
}

/// Solves L Lᵀ x = b in place, b's entries `stride` apart (a column of a row-major matrix).
void cholesky_solve(const double* L, std::size_t n, double* b, std::size_t stride) {
    for (std::size_t i = 0; i < n; ++i) {
        double v = b[i * stride];
        for (std::size_t k = 0; k < i; ++k) v -= L[i * n + k] * b[k * stride];
        b[i * stride] = v / L[i * n + i];
    }
    for (std::size_t i = n; i-- > 0;) {
        double v = b[i * stride];
        for (std::size_t k = i + 1; k < n; ++k) v -= L[k * n + i] * b[k * stride];
        b[i * stride] = v / L[i * n + i];
    }
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

double Solver::curve(const MaterialCurve& c, double speed, bool restitution) const {
    const double v = c(speed);
    if (restitution ? !(v >= 0 && v <= 1) : !(v >= 0 && std::isfinite(v))) {
        std::ostringstream os;
        os << "contact: the " << (restitution ? "restitution" : "friction") << " curve returned " << v << " at speed "
           << speed << " m/s; it must be " << (restitution ? "in [0, 1]" : "finite and non-negative");
        throw Error(os.str());
    }
    return v;
}

void Solver::gather(const World& w) {
    const std::size_t n = ids_.size();
    bodies_.resize(n + 1);
    for (std::size_t k = 0; k < n_rigid_; ++k) {
        const Index i = ids_[k];
        Body& b = bodies_[k];
        b.v[0] = w.at(kVX, i), b.v[1] = w.at(kVY, i), b.v[2] = w.at(kVZ, i);
        b.w[0] = w.at(kWX, i), b.w[1] = w.at(kWY, i), b.w[2] = w.at(kWZ, i);
        b.p[0] = w.at(kX, i), b.p[1] = w.at(kY, i), b.p[2] = w.at(kZ, i);
        b.im = w.at(kInvMass, i);
        b.r = w.at(kRadius, i);
        if (!std::isfinite(b.p[0] + b.p[1] + b.p[2] + b.v[0] + b.v[1] + b.v[2] + b.w[0] + b.w[1] + b.w[2]))
            throw Error("contact: the position or velocity of '" + layout_->components.label(i) + "' is not finite");
        const bool isotropic = w.at(kInvIxy, i) == 0 && w.at(kInvIxz, i) == 0 && w.at(kInvIyz, i) == 0 &&
                               w.at(kInvIxx, i) == w.at(kInvIyy, i) && w.at(kInvIxx, i) == w.at(kInvIzz, i);
        if (isotropic) { // R I⁻¹ Rᵀ = I⁻¹
            b.ii[0] = b.ii[1] = b.ii[2] = w.at(kInvIxx, i);
            b.ii[3] = b.ii[4] = b.ii[5] = 0;
        } else {
            const Eigen::Matrix3d r = orientation(w, i).to_matrix();
            const Eigen::Matrix3d m = r * body_inverse_inertia(w, i) * r.transpose();
            b.ii[0] = m(0, 0), b.ii[1] = m(1, 1), b.ii[2] = m(2, 2);
            b.ii[3] = 0.5 * (m(0, 1) + m(1, 0)), b.ii[4] = 0.5 * (m(0, 2) + m(2, 0)), b.ii[5] = 0.5 * (m(1, 2) + m(2, 1));
        }
    }
    for (std::size_t m = 0; m < models_.size(); ++m) gather_model(w, models_[m], m);
    bodies_[n] = Body{}; // the static body: no velocity, zero inverse mass and inertia
}

void Solver::gather_model(const World& w, ModelScratch& m, std::size_t index) {
    const LagrangianSystem& s = *m.placed.system;
    const std::size_t n = s.dof, ns = m.placed.spheres.size(), nb = 3 * ns, nc = s.n_constraints;
    for (std::size_t i = 0; i < n; ++i) {
        m.q[i] = w.at(q_field_, m.placed.coordinates[i]);
        m.qd[i] = w.at(qd_field_, m.placed.coordinates[i]);
        if (!std::isfinite(m.q[i]) || !std::isfinite(m.qd[i]))
            throw Error("contact: the state of model '" + m.placed.name + "' is not finite");
    }
    const double t = w.time;
    m.sync.q = m.q; // sizes fixed: no allocation
    m.sync.qd = m.qd;
    sphere_states(m.placed, t, m.sync); // centres, velocities, J (3·ns × n, row-major)
    s.mass_matrix(t, m.q, m.qd, m.M);
    if (!cholesky(m.M.data(), n))
        throw Error("contact: the mass matrix of model '" + m.placed.name + "' is not positive definite at t = " +
                    std::to_string(t) + " s: its spheres' effective masses are undefined");
    // B = M⁻¹ Jᵀ (n × 3·ns, row-major), column by column.
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < nb; ++c) m.B[i * nb + c] = m.sync.J[c * n + i];
    for (std::size_t c = 0; c < nb; ++c) cholesky_solve(m.M.data(), n, &m.B[c], nb);
    if (nc > 0) { // B ← B − M⁻¹Gᵀ (G M⁻¹ Gᵀ)⁻¹ G B: the impulses keep G Δq' = 0
        s.constraint_matrix(t, m.q, m.G); // nc × n
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < nc; ++k) m.MinvGt[i * nc + k] = m.G[k * n + i];
        for (std::size_t k = 0; k < nc; ++k) cholesky_solve(m.M.data(), n, &m.MinvGt[k], nc);
        for (std::size_t a = 0; a < nc; ++a)
            for (std::size_t b = 0; b < nc; ++b) {
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += m.G[a * n + i] * m.MinvGt[i * nc + b];
                m.S[a * nc + b] = v;
            }
        if (!cholesky(m.S.data(), nc))
            throw Error("contact: the constraints of model '" + m.placed.name + "' are dependent at t = " + std::to_string(t) +
                        " s (G M⁻¹ Gᵀ is singular)");
        for (std::size_t a = 0; a < nc; ++a)
            for (std::size_t c = 0; c < nb; ++c) {
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += m.G[a * n + i] * m.B[i * nb + c];
                m.GB[a * nb + c] = v;
            }
        for (std::size_t c = 0; c < nb; ++c) cholesky_solve(m.S.data(), nc, &m.GB[c], nb);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t c = 0; c < nb; ++c) {
                double v = 0;
                for (std::size_t a = 0; a < nc; ++a) v += m.MinvGt[i * nc + a] * m.GB[a * nb + c];
                m.B[i * nb + c] -= v;
            }
    }
    for (std::size_t j = 0; j < ns; ++j) {
        double a[3][3];
        for (std::size_t r = 0; r < 3; ++r)
            for (std::size_t c = 0; c < 3; ++c) {
                double v = 0;
                for (std::size_t i = 0; i < n; ++i) v += m.sync.J[(3 * j + r) * n + i] * m.B[i * nb + 3 * j + c];
                a[r][c] = v;
            }
        double* A = &m.A[6 * j]; // J_s B_s: symmetric up to round-off
        A[0] = a[0][0], A[1] = a[1][1], A[2] = a[2][2];
        A[3] = 0.5 * (a[0][1] + a[1][0]), A[4] = 0.5 * (a[0][2] + a[2][0]), A[5] = 0.5 * (a[1][2] + a[2][1]);
        Body& b = bodies_[m.first + j];
        b = Body{};
        b.model = static_cast<int>(index);
        b.sphere = static_cast<int>(j);
        b.r = m.placed.radii[j];
        for (std::size_t k = 0; k < 3; ++k) {
            b.p[k] = m.sync.P[3 * j + k];
            b.v[k] = m.sync.V[3 * j + k];
        }
    }
}

void Solver::model_impulse(const Body& X, const double* lambda, std::vector<Body>& B, bool position) {
    ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
    const std::size_t n = m.q.size(), ns = m.placed.spheres.size(), nb = 3 * ns;
    const std::size_t c = 3 * static_cast<std::size_t>(X.sphere);
    for (std::size_t i = 0; i < n; ++i) {
        const double* row = &m.B[i * nb + c];
        m.dq[i] = row[0] * lambda[0] + row[1] * lambda[1] + row[2] * lambda[2];
    }
    std::vector<double>& target = position ? m.q : m.qd;
    for (std::size_t i = 0; i < n; ++i) target[i] += m.dq[i];
    for (std::size_t j = 0; j < ns; ++j) {
        Body& b = B[m.first + j];
        double* out = position ? b.p : b.v;
        for (std::size_t k = 0; k < 3; ++k) {
            const double* row = &m.sync.J[(3 * j + k) * n];
            double d = 0;
            for (std::size_t i = 0; i < n; ++i) d += row[i] * m.dq[i];
            out[k] += d;
        }
    }
}

void Solver::scatter_model(World& w, ModelScratch& m) {
    for (std::size_t i = 0; i < m.q.size(); ++i) {
        w.at(q_field_, m.placed.coordinates[i]) = m.q[i];
        w.at(qd_field_, m.placed.coordinates[i]) = m.qd[i];
    }
    sync_model_spheres(m.placed, q_field_, qd_field_, w.time, w, m.sync); // the exact centres at the corrected q
}

void Solver::detect(const World& w, double dt) {
    contacts_.clear();
    // Speculative margins (ContactOptions::margin): the given one for every pair, or per body
    // min(r, max(2|v|dt, slop, r/50)) — twice the distance it can cover in the step, and at
    // least a small fixed distance so that bodies at rest that (nearly) touch keep their
    // contacts — and a pair's margin the sum of its two.
    const bool uniform = options_.margin >= 0;
    margins_.resize(ids_.size());
    for (std::size_t k = 0; k < ids_.size(); ++k) {
        const Body& b = bodies_[k];
        margins_[k] = uniform ? 0.5 * options_.margin
                              : std::min(b.r, std::max(2 * std::sqrt(dot(b.v, b.v)) * dt, std::max(options_.slop, 0.02 * b.r)));
    }
    if (sphere_pairs_) {
        spheres_.resize(ids_.size());
        for (std::size_t k = 0; k < ids_.size(); ++k) {
            const Body& b = bodies_[k];
            spheres_[k] = SphereBB{{b.p[0], b.p[1], b.p[2]}, b.r + margins_[k]};
        }
        // The rigid bodies through the broad phase; the few model spheres, often larger than
        // the pile's (a uniform grid sizes its cells by the largest), against every body.
        manager_.update(std::span<const SphereBB>(spheres_.data(), n_rigid_));
        const std::vector<CandidatePair>* pairs = &manager_.run_broad_phase();
        if (n_rigid_ < ids_.size()) {
            model_pairs_ = *pairs;
            for (std::size_t k = n_rigid_; k < ids_.size(); ++k)
                for (std::size_t j = 0; j < k; ++j) {
                    if (j >= n_rigid_ && bodies_[j].model == bodies_[k].model) continue; // one model: no pair
                    const double reach = spheres_[j].radius + spheres_[k].radius;
                    if ((spheres_[j].center - spheres_[k].center).squaredNorm() < reach * reach)
                        model_pairs_.push_back({static_cast<Index>(j), static_cast<Index>(k)});
                }
            pairs = &model_pairs_;
        }
        if (uniform)
            sphere_sphere_contacts(w, *pairs, ids_, options_.margin, contacts_);
        else
            sphere_sphere_contacts(w, *pairs, ids_, std::span<const double>(margins_), contacts_);
    }
    if (uniform)
        sphere_plane_contacts(w, ids_, planes_, options_.margin, contacts_);
    else
        sphere_plane_contacts(w, ids_, planes_, std::span<const double>(margins_), contacts_);
    // Scratch indices instead of component indices.
    local_.resize(w.size());
    for (std::size_t k = 0; k < ids_.size(); ++k) local_[ids_[k]] = static_cast<Index>(k);
    rows_.resize(contacts_.size());
    const auto stat = static_cast<std::uint32_t>(ids_.size());
    std::size_t kept = 0;
    for (std::size_t c = 0; c < contacts_.size(); ++c) {
        const Contact& k = contacts_[c];
        const std::uint32_t a = local_[k.a], b = k.plane >= 0 ? stat : local_[k.b];
        // Spheres of one model do not collide with each other (scene.hpp).
        if (b != stat && bodies_[a].model >= 0 && bodies_[a].model == bodies_[b].model) continue;
        Row& r = rows_[kept++];
        r.a = a;
        r.b = b;
        r.plane = k.plane;
        r.jn = r.jt1 = r.jt2 = 0;
        r.slot = -1;
    }
    rows_.resize(kept);
}

double Solver::geometry(const Row& c, double* n) const {
    const Body& A = bodies_[c.a];
    if (c.plane >= 0) {
        const Plane& pl = planes_[static_cast<std::size_t>(c.plane)];
        n[0] = pl.normal.x(), n[1] = pl.normal.y(), n[2] = pl.normal.z();
        return dot(n, A.p) - pl.offset - A.r;
    }
    const Body& B = bodies_[c.b];
    const double d[3] = {A.p[0] - B.p[0], A.p[1] - B.p[1], A.p[2] - B.p[2]};
    const double l = std::sqrt(dot(d, d));
    if (l > 0) {
        n[0] = d[0] / l, n[1] = d[1] / l, n[2] = d[2] / l;
    } else {
        n[0] = 0, n[1] = 1, n[2] = 0;
    }
    return l - A.r - B.r;
}

void Solver::correct_positions() {
    const double beta = options_.baumgarte, slop = options_.slop;
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    const std::size_t nb = ids_.size();
    for (int it = 0; it < options_.position_iterations; ++it) {
        if (jacobi) delta_.assign(3 * nb, 0.0);
        bool any = false;
        for (Row& c : rows_) {
            Body& A = bodies_[c.a];
            double n[3];
            const double sep = geometry(c, n);
            const double depth = -sep - slop;
            if (depth <= 0) continue;
            Body& Bb = bodies_[c.b];
            if (has_model(c)) {
                const double wsum = linear_inverse_mass(A, n) + linear_inverse_mass(Bb, n);
                if (!(wsum > kSingularInverseMass * (inverse_mass_scale(A) + inverse_mass_scale(Bb)))) continue;
                any = true;
                const double corr = beta * depth / wsum;
                position_impulse(A, c.a, corr, n, jacobi);
                if (c.plane < 0) position_impulse(Bb, c.b, -corr, n, jacobi);
                continue;
            }
            any = true;
            const double wsum = A.im + Bb.im;
            const double corr = beta * depth / wsum;
            for (int k = 0; k < 3; ++k) {
                if (jacobi) {
                    delta_[3 * c.a + k] += corr * A.im * n[k];
                    if (c.plane < 0) delta_[3 * c.b + k] -= corr * Bb.im * n[k];
                } else {
                    A.p[k] += corr * A.im * n[k];
                    Bb.p[k] -= corr * Bb.im * n[k];
                }
            }
        }
        if (jacobi) {
            for (std::size_t b = 0; b < n_rigid_; ++b)
                for (int k = 0; k < 3; ++k) bodies_[b].p[k] += delta_[3 * b + k];
            for (std::size_t b = n_rigid_; b < nb; ++b)
                if (delta_[3 * b] != 0 || delta_[3 * b + 1] != 0 || delta_[3 * b + 2] != 0)
                    model_impulse(bodies_[b], &delta_[3 * b], bodies_, true);
        }
        if (!any) break;
    }
}

void Solver::position_impulse(const Body& X, std::size_t index, double corr, const double* n, bool jacobi) {
    const double l[3] = {corr * n[0], corr * n[1], corr * n[2]};
    if (X.model < 0) { // a rigid body moves by l/m
        for (int k = 0; k < 3; ++k) {
            if (jacobi)
                delta_[3 * index + static_cast<std::size_t>(k)] += X.im * l[k];
            else
                bodies_[index].p[k] += X.im * l[k];
        }
    } else if (jacobi) { // a model sphere: its impulse, applied through B at the end of the pass
        for (int k = 0; k < 3; ++k) delta_[3 * index + static_cast<std::size_t>(k)] += l[k];
    } else {
        model_impulse(X, l, bodies_, true);
    }
}

void Solver::setup_rows(double dt) {
    // Jacobi: split each body's mass evenly among its contacts (its inverse mass and inverse
    // inertia times its contact count), so that the simultaneous corrections of a pass add up
    // to one body's worth instead of overshooting by the contact count (Tonge, Benevolenski &
    // Voroshilov, "Mass splitting for jitter-free parallel rigid body simulation", SIGGRAPH 2012).
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    if (jacobi) {
        split_.assign(bodies_.size(), 0.0);
        for (const Row& c : rows_) {
            split_[c.a] += 1;
            split_[c.b] += 1;
        }
    }
    for (Row& c : rows_) {
        const Body& A = bodies_[c.a];
        const Body& B = bodies_[c.b];
        const double sa = jacobi ? split_[c.a] : 1.0, sb = jacobi ? split_[c.b] : 1.0;
        c.ra = A.r;
        c.rb = c.plane >= 0 ? 0.0 : B.r;
        c.sep = geometry(c, c.n);
        tangent_basis(c.n, c.t1, c.t2);
        if (has_model(c)) {
            // A model sphere's translational inverse mass depends on the direction, and a
            // direction it cannot move along (K⁻¹ ≈ 0 on both sides) takes no impulse.
            const double floor = kSingularInverseMass * (sa * inverse_mass_scale(A) + sb * inverse_mass_scale(B));
            const double kn = sa * linear_inverse_mass(A, c.n) + sb * linear_inverse_mass(B, c.n);
            const double k1 = sa * linear_inverse_mass(A, c.t1) + sb * linear_inverse_mass(B, c.t1) +
                              sa * c.ra * c.ra * quad(A.ii, c.t2) + sb * c.rb * c.rb * quad(B.ii, c.t2);
            const double k2 = sa * linear_inverse_mass(A, c.t2) + sb * linear_inverse_mass(B, c.t2) +
                              sa * c.ra * c.ra * quad(A.ii, c.t1) + sb * c.rb * c.rb * quad(B.ii, c.t1);
            c.mn = kn > floor ? 1 / kn : 0;
            c.mt1 = k1 > floor ? 1 / k1 : 0;
            c.mt2 = k2 > floor ? 1 / k2 : 0;
        } else {
            const double im = sa * A.im + sb * B.im;
            c.mn = 1 / im;
            c.mt1 = 1 / (im + sa * c.ra * c.ra * quad(A.ii, c.t2) + sb * c.rb * c.rb * quad(B.ii, c.t2));
            c.mt2 = 1 / (im + sa * c.ra * c.ra * quad(A.ii, c.t1) + sb * c.rb * c.rb * quad(B.ii, c.t1));
        }
        c.bias = -std::max(c.sep, 0.0) / dt;
        // μ from the sliding speed before the solve.
        double vt1, vt2;
        tangent_velocity(c, A, B, vt1, vt2);
        c.mu = curve(material_.friction, std::sqrt(vt1 * vt1 + vt2 * vt2), false);
    }
}

void Solver::apply_normal(Row& c, double l, std::vector<Body>& B) {
    Body& A = B[c.a];
    Body& Bb = B[c.b];
    if (A.model >= 0 || Bb.model >= 0) {
        const double pa[3] = {l * c.n[0], l * c.n[1], l * c.n[2]}, pb[3] = {-pa[0], -pa[1], -pa[2]};
        side_impulse(A, pa, nullptr, 0, B);
        side_impulse(Bb, pb, nullptr, 0, B);
        return;
    }
    for (int k = 0; k < 3; ++k) {
        A.v[k] += A.im * l * c.n[k];
        Bb.v[k] -= Bb.im * l * c.n[k];
    }
}

void Solver::apply_tangent(Row& c, double l1, double l2, std::vector<Body>& B) {
    Body& A = B[c.a];
    Body& Bb = B[c.b];
    if (A.model >= 0 || Bb.model >= 0) {
        double pa[3], pb[3], u[3];
        for (int k = 0; k < 3; ++k) {
            pa[k] = l1 * c.t1[k] + l2 * c.t2[k];
            pb[k] = -pa[k];
            u[k] = l2 * c.t1[k] - l1 * c.t2[k];
        }
        side_impulse(A, pa, u, c.ra, B);
        side_impulse(Bb, pb, u, c.rb, B);
        return;
    }
    double u[3], ia[3], ib[3];
    for (int k = 0; k < 3; ++k) {
        const double p = l1 * c.t1[k] + l2 * c.t2[k];
        A.v[k] += A.im * p;
        Bb.v[k] -= Bb.im * p;
        u[k] = l2 * c.t1[k] - l1 * c.t2[k];
    }
    mul_sym(A.ii, u, ia);
    mul_sym(Bb.ii, u, ib);
    for (int k = 0; k < 3; ++k) {
        A.w[k] += c.ra * ia[k];
        Bb.w[k] += c.rb * ib[k];
    }
}

void Solver::side_impulse(Body& X, const double* p, const double* u, double r, std::vector<Body>& B) {
    if (X.model >= 0) { // no spin: the impulse acts at the sphere's centre
        model_impulse(X, p, B, false);
        return;
    }
    for (int k = 0; k < 3; ++k) X.v[k] += X.im * p[k];
    if (u != nullptr) {
        double i[3];
        mul_sym(X.ii, u, i);
        for (int k = 0; k < 3; ++k) X.w[k] += r * i[k];
    }
}

void Solver::find_slots(const World& w) {
    if (slots_.empty()) return;
    for (Row& c : rows_) {
        const Index a = ids_[c.a];
        const double key = c.plane >= 0 ? -(c.plane + 1.0) : ids_[c.b] + 1.0;
        for (std::size_t k = 0; k < slots_.size(); ++k) {
            const double p = w.at(slots_[k].partner, a);
            if (p == 0) break; // slots are filled from the front
            if (p == key) {
                c.slot = static_cast<int>(k);
                break;
            }
        }
    }
}

void Solver::warm_start(const World& w) {
    if (slots_.empty()) return;
    for (Row& c : rows_) {
        if (c.slot < 0) continue;
        const Slot* s = &slots_[static_cast<std::size_t>(c.slot)];
        const Index a = ids_[c.a];
        const double jt[3] = {w.at(s->jtx, a), w.at(s->jty, a), w.at(s->jtz, a)};
        c.jn = w.at(s->jn, a);
        c.jt1 = dot(jt, c.t1);
        c.jt2 = dot(jt, c.t2);
        clamp_disk(c.jt1, c.jt2, c.mu * c.jn);
        apply_normal(c, c.jn, bodies_);
        apply_tangent(c, c.jt1, c.jt2, bodies_);
    }
}

void Solver::collisions(double dt) {
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    for (int it = 0; it < options_.restitution_iterations; ++it) {
        bool any = false;
        if (jacobi) snapshot_ = bodies_;
        const std::vector<Body>& from = jacobi ? snapshot_ : bodies_; // read; impulses go to bodies_
        for (Row& c : rows_) {
            const Body& A = from[c.a];
            const Body& B = from[c.b];
            double dv[3] = {A.v[0] - B.v[0], A.v[1] - B.v[1], A.v[2] - B.v[2]};
            const double vn = dot(dv, c.n);
            if (c.slot >= 0 || vn >= 0 || c.sep + vn * dt >= 0) continue;
            const double e = curve(material_.restitution, -vn, true);
            if (e == 0) continue;
            any = true;
            const double j = -(1 + e) * vn * c.mn;
            double vt1, vt2;
            tangent_velocity(c, A, B, vt1, vt2);
            double l1 = -vt1 * c.mt1, l2 = -vt2 * c.mt2;
            clamp_disk(l1, l2, c.mu * j);
            apply_normal(c, j, bodies_);
            apply_tangent(c, l1, l2, bodies_);
        }
        if (!any) break;
    }
}

void Solver::solve_contacts() {
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    for (int it = 0; it < options_.velocity_iterations; ++it) {
        if (jacobi) snapshot_ = bodies_;
        const std::vector<Body>& from = jacobi ? snapshot_ : bodies_;
        for (Row& c : rows_) {
            // Friction first, limited by the normal impulse of the previous pass.
            {
                const Body& A = from[c.a];
                const Body& B = from[c.b];
                double vt1, vt2;
                tangent_velocity(c, A, B, vt1, vt2);
                double n1 = c.jt1 - vt1 * c.mt1, n2 = c.jt2 - vt2 * c.mt2;
                clamp_disk(n1, n2, c.mu * c.jn);
                const double l1 = n1 - c.jt1, l2 = n2 - c.jt2;
                c.jt1 = n1;
                c.jt2 = n2;
                if (l1 != 0 || l2 != 0) apply_tangent(c, l1, l2, bodies_);
            }
            {
                const Body& A = jacobi ? from[c.a] : bodies_[c.a];
                const Body& B = jacobi ? from[c.b] : bodies_[c.b];
                const double vn = (A.v[0] - B.v[0]) * c.n[0] + (A.v[1] - B.v[1]) * c.n[1] + (A.v[2] - B.v[2]) * c.n[2];
                const double jn = std::max(c.jn - (vn - c.bias) * c.mn, 0.0);
                const double l = jn - c.jn;
                c.jn = jn;
                if (l != 0) apply_normal(c, l, bodies_);
            }
        }
    }
}

void Solver::scatter(World& w) {
    for (ModelScratch& m : models_) scatter_model(w, m);
    for (std::size_t k = 0; k < n_rigid_; ++k) {
        const Index i = ids_[k];
        const Body& b = bodies_[k];
        w.at(kVX, i) = b.v[0], w.at(kVY, i) = b.v[1], w.at(kVZ, i) = b.v[2];
        w.at(kWX, i) = b.w[0], w.at(kWY, i) = b.w[1], w.at(kWZ, i) = b.w[2];
        w.at(kX, i) = b.p[0], w.at(kY, i) = b.p[1], w.at(kZ, i) = b.p[2];
    }
}

void Solver::store_cache(World& w) const {
    if (slots_.empty()) return;
    for (Index i : ids_)
        for (const Slot& s : slots_) w.at(s.partner, i) = 0;
    // Rows are grouped by body a (pairs sorted by a, then the planes of each body in order),
    // but a body's rows need not be contiguous: fill the first free slot of each.
    for (const Row& c : rows_) {
        if (c.jn <= 0) continue;
        const Index a = ids_[c.a];
        for (const Slot& s : slots_) {
            if (w.at(s.partner, a) != 0) continue;
            w.at(s.partner, a) = c.plane >= 0 ? -(c.plane + 1.0) : ids_[c.b] + 1.0;
            w.at(s.jn, a) = c.jn;
            w.at(s.jtx, a) = c.jt1 * c.t1[0] + c.jt2 * c.t2[0];
            w.at(s.jty, a) = c.jt1 * c.t1[1] + c.jt2 * c.t2[1];
            w.at(s.jtz, a) = c.jt1 * c.t1[2] + c.jt2 * c.t2[2];
            break;
        }
    }
}

void Solver::step(double dt, World& w) {
    if (!(dt > 0) || !std::isfinite(dt)) throw Error("contact: the step dt must be positive and finite");
    gather(w);
    detect(w, dt);
    correct_positions();
    setup_rows(dt);
    find_slots(w); // cached contacts are resting: no restitution for them
    // Collisions see the velocities before any contact impulse: the warm start is a first
    // guess at the resting impulses that the contact passes may take back, and an impact
    // computed against it would keep a bounce that the guess only lent.
    collisions(dt);
    warm_start(w);
    solve_contacts();
    scatter(w);
    store_cache(w);
}

Domain writes_of(const Layout& layout, const ComponentSet& bodies) {
    Domain d = Domain::of(layout, {"x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz"}, bodies);
    for (std::size_t f = 0; f < layout.fields.size(); ++f)
        if (layout.fields[f].rfind("wc_", 0) == 0) d = d | Domain(static_cast<FieldId>(f), bodies);
    return d;
}

void validate(const std::vector<Plane>& planes, const ContactMaterial& material, const ContactOptions& options) {
    for (const Plane& p : planes) p.validate();
    if (!material.restitution || !material.friction) throw std::invalid_argument("contact_rule: a material curve is empty");
    if (options.position_iterations < 0 || options.velocity_iterations < 0 || options.restitution_iterations < 0)
        throw std::invalid_argument("contact_rule: iteration counts must be non-negative");
    if (!(options.baumgarte >= 0 && options.baumgarte <= 1))
        throw std::invalid_argument("contact_rule: the Baumgarte factor must be in [0, 1]");
    if (!(options.slop >= 0) || !std::isfinite(options.slop))
        throw std::invalid_argument("contact_rule: the slop must be non-negative and finite");
    if (!std::isfinite(options.margin)) throw std::invalid_argument("contact_rule: the margin must be finite");
}

Domain reads_of(const Layout& layout, const ComponentSet& bodies) {
    return Domain::of(layout, {"m", "inv_m", "iIxx", "iIyy", "iIzz", "iIxy", "iIxz", "iIyz", "radius", "qw", "qx", "qy", "qz"},
                      bodies);
}

} // namespace

NumericRule contact_rule(const ComponentSet& bodies, std::vector<Plane> planes, ContactMaterial material,
                         ContactOptions options, const std::shared_ptr<const Layout>& layout, bool sphere_pairs) {
    validate(planes, material, options);
    for (Index i : bodies.indices())
        if (i >= layout->components.size()) throw std::invalid_argument("contact_rule: a body is not in the world");
    auto solver = std::make_shared<Solver>(bodies, planes, std::move(material), options, layout, sphere_pairs);
    NumericRule r{sphere_pairs ? (planes.empty() ? "contact_spheres" : "contacts") : "contact_planes",
                  writes_of(*layout, bodies), reads_of(*layout, bodies), nullptr, layout};
    r.step = [solver](double dt, World& w) { solver->step(dt, w); };
    return r;
}

NumericRule contact_rule(const Scene& scene, std::vector<Plane> planes, ContactMaterial material, ContactOptions options) {
    validate(planes, material, options);
    const auto& layout = scene.world.layout_ptr();
    const ComponentSet all = scene.bodies | scene.spheres;
    Domain writes = writes_of(*layout, all);
    std::vector<Index> coordinates;
    for (const PlacedModel& p : scene.models) coordinates.insert(coordinates.end(), p.coordinates.begin(), p.coordinates.end());
    if (!coordinates.empty()) {
        const ComponentSet c(std::move(coordinates));
        writes = writes | Domain(scene.q, c) | Domain(scene.qd, c);
    }
    auto solver = std::make_shared<Solver>(scene.bodies, planes, std::move(material), options, layout, true, &scene);
    NumericRule r{"contacts", std::move(writes), reads_of(*layout, all), nullptr, layout};
    r.step = [solver](double dt, World& w) { solver->step(dt, w); };
    return r;
}

NumericRule contact_ground(const ComponentSet& bodies, ContactMaterial material, ContactOptions options,
                           const std::shared_ptr<const Layout>& layout) {
    return contact_rule(bodies, {Plane::ground()}, std::move(material), options, layout, false);
}

NumericRule contact_spheres(const ComponentSet& bodies, ContactMaterial material, ContactOptions options,
                            const std::shared_ptr<const Layout>& layout) {
    return contact_rule(bodies, {}, std::move(material), options, layout, true);
}

NumericWorkflow rigid_contact_step(const Force3D& force, const ComponentSet& bodies, std::vector<Plane> planes,
                                   ContactMaterial material, ContactOptions options,
                                   const std::shared_ptr<const Layout>& layout) {
    using W = NumericWorkflow;
    return W::seq(W::run(kick_force3d(force, bodies, 1.0, layout)),
                  W::run(contact_rule(bodies, std::move(planes), std::move(material), options, layout)),
                  W::run(drift_trans(bodies, 1.0, layout)), W::run(drift_rot(bodies, 1.0, layout)));
}

double max_penetration(const World& w, const ComponentSet& bodies, std::span<const Plane> planes) {
    std::vector<Index> ids(bodies.indices().begin(), bodies.indices().end());
    std::vector<AABB> boxes(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k)
        boxes[k] = aabb_from_sphere(SphereBB{position(w, ids[k]), w.at(kRadius, ids[k])});
    std::vector<CandidatePair> pairs;
    UniformGrid().find_pairs(boxes, pairs);
    std::vector<Contact> contacts;
    sphere_sphere_contacts(w, pairs, ids, 0, contacts);
    sphere_plane_contacts(w, ids, planes, 0, contacts);
    double worst = 0;
    for (const Contact& c : contacts) worst = std::max(worst, -c.separation);
    return worst;
}

} // namespace phynjo::runtime
