// The contact solver's detection: the broad phase over the bodies' and model spheres' bounds, then the narrow phase (solver.hpp).
#include "solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "phynjo/runtime/core/errors.hpp"

namespace phynjo::runtime::contact_detail {

namespace {
OBB obb_of(const Body& b) {
    return OBB{Eigen::Vector3d(b.p[0], b.p[1], b.p[2]), Eigen::Vector3d(b.h[0], b.h[1], b.h[2]),
               Quaternion{b.q[0], b.q[1], b.q[2], b.q[3]}};
}
Capsule capsule_of(const Body& b) {
    const Eigen::Vector3d c(b.p[0], b.p[1], b.p[2]);
    const Eigen::Vector3d e = Quaternion{b.q[0], b.q[1], b.q[2], b.q[3]}.rotate(Eigen::Vector3d(0, b.h[1], 0));
    return Capsule{c - e, c + e, b.r};
}
SphereBB sphere_of(const Body& b) { return SphereBB{Eigen::Vector3d(b.p[0], b.p[1], b.p[2]), b.r}; }
/// A model capsule's segment (its ends p, p2) and radius.
Capsule model_capsule(const Body& b) {
    return Capsule{Eigen::Vector3d(b.p[0], b.p[1], b.p[2]), Eigen::Vector3d(b.p2[0], b.p2[1], b.p2[2]), b.r};
}
/// The fraction along [p0, p1] of the point of the axis nearest x.
double fraction_along(const Capsule& c, const Eigen::Vector3d& x) {
    const Eigen::Vector3d d = c.p1 - c.p0;
    const double l2 = d.squaredNorm();
    return l2 > 0 ? std::clamp((x - c.p0).dot(d) / l2, 0.0, 1.0) : 0.0;
}
/// A (scratch) row made a sphere row between scratch bodies a and b (b the static body and
/// `plane` its plane for a plane), nothing carried, at fractions 0 (set sa, sb after).
void start_sphere_row(Row& r, std::uint32_t a, std::uint32_t b, int plane) {
    r.a = a;
    r.b = b;
    r.plane = plane;
    r.jn = r.jt1 = r.jt2 = 0;
    r.slot = -1;
    r.point = false; // the scratch row may have been a manifold's
    r.block_size = 1;
    r.block = -1;
    r.sa = r.sb = 0;
}
/// Whether two boxes overlap.
bool overlap(const AABB& a, const AABB& b) {
    return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}
} // namespace

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
        // A box's size is its smallest half-extent (a sphere's and a capsule's their radius).
        const double r = b.shape == Shape::box ? std::min({b.h[0], b.h[1], b.h[2]}) : b.r;
        margins_[k] = uniform ? 0.5 * options_.margin
                              : std::min(r, std::max(2 * std::sqrt(dot(b.v, b.v)) * dt, std::max(options_.slop, 0.02 * r)));
    }
    if (shape_field_ >= 0) {
        detect_shapes(w, dt);
        return;
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
    spheres_to_rows(w);
    if (n_capsules_ > 0) capsule_rows(dt);
    if (n_boxes_ > 0) {
        point_rows_.clear();
        model_box_rows(dt);
        rows_.insert(rows_.end(), point_rows_.begin(), point_rows_.end());
    }
}

double Solver::model_capsule_margin(const Body& b, double dt) const {
    if (options_.margin >= 0) return 0.5 * options_.margin;
    const double v = std::sqrt(std::max(dot(b.v, b.v), dot(b.v2, b.v2)));
    return std::min(b.r, std::max(2 * v * dt, std::max(options_.slop, 0.02 * b.r)));
}

double Solver::model_box_margin(const Body& X, double dt) const {
    if (options_.margin >= 0) return 0.5 * options_.margin;
    const double size = std::min({X.h[0], X.h[1], X.h[2]});
    const double speed = std::sqrt(dot(X.v, X.v)) + std::sqrt(dot(X.w, X.w)) * std::sqrt(dot(X.h, X.h));
    return std::min(size, std::max(2 * speed * dt, std::max(options_.slop, 0.02 * size)));
}

void Solver::model_box_rows(double dt) {
    const bool uniform = options_.margin >= 0;
    const auto stat = static_cast<std::uint32_t>(ids_.size());
    Manifold m;
    const std::uint32_t first_capsule = stat + 1, first = first_capsule + static_cast<std::uint32_t>(n_capsules_);
    for (std::uint32_t k = first; k < first + n_boxes_; ++k) {
        const Body& X = bodies_[k];
        const double reach = std::sqrt(dot(X.h, X.h));
        const double mx = model_box_margin(X, dt);
        for (std::size_t i = 0; i < planes_.size(); ++i) { // the static body as side a, at the plane's points
            if (!collide_plane(X, planes_[i], mx, m)) continue;
            m.flip(); // the model box is side b
            add_model_manifold(m, stat, k, nullptr, nullptr, static_cast<int>(i));
        }
        const Eigen::Vector3d c(X.p[0], X.p[1], X.p[2]);
        // Rigid bodies and other models' spheres (side a; normal from the model box towards them).
        for (std::uint32_t j = 0; j < stat; ++j) {
            const Body& A = bodies_[j];
            if (A.model == X.model) continue; // one model: no pair (a rigid body's is −1)
            const double ma = uniform ? 0.5 * options_.margin : margins_[j];
            // a bounding sphere of each: enough to skip the far ones
            const double ra = A.shape == Shape::sphere ? A.r : std::sqrt(dot(A.h, A.h)) + A.r;
            const double d[3] = {A.p[0] - c.x(), A.p[1] - c.y(), A.p[2] - c.z()};
            const double within = ra + reach + ma + mx;
            if (dot(d, d) > within * within) continue;
            if (A.shape == Shape::sphere && !(A.r > 0)) continue;
            if (!collide(A, X, ma + mx, m)) continue;
            add_model_manifold(m, j, k, nullptr, nullptr);
        }
        // Other models' capsules (side a, each point at its fraction along the segment).
        for (std::uint32_t j = first_capsule; j < first; ++j) {
            const Body& A = bodies_[j];
            if (A.model == X.model) continue;
            const Capsule ca = model_capsule(A);
            const double ma = model_capsule_margin(A, dt);
            const Eigen::Vector3d mid = 0.5 * (ca.p0 + ca.p1);
            const double within = 0.5 * (ca.p1 - ca.p0).norm() + ca.radius + reach + ma + mx;
            if ((mid - c).squaredNorm() > within * within) continue;
            m.count = 0;
            capsule_box(ca, obb_of(X), ma + mx, m); // normal from the box towards the capsule
            if (m.count > 0) add_model_manifold(m, j, k, &ca, nullptr);
        }
        // Other models' boxes met before it (side a).
        for (std::uint32_t j = first; j < k; ++j) {
            const Body& A = bodies_[j];
            if (A.model == X.model) continue;
            const double ma = model_box_margin(A, dt);
            const double d[3] = {A.p[0] - c.x(), A.p[1] - c.y(), A.p[2] - c.z()};
            const double within = std::sqrt(dot(A.h, A.h)) + reach + ma + mx;
            if (dot(d, d) > within * within) continue;
            if (!collide(A, X, ma + mx, m)) continue;
            add_model_manifold(m, j, k, nullptr, nullptr);
        }
    }
}

void Solver::capsule_rows(double dt) {
    const bool uniform = options_.margin >= 0;
    const auto stat = static_cast<std::uint32_t>(ids_.size());
    Manifold m;
    auto add = [&](std::uint32_t a, std::uint32_t b, int plane, const Capsule& ca, const Capsule* cb) {
        for (int i = 0; i < m.count; ++i) {
            const ManifoldPoint& p = m.points[static_cast<std::size_t>(i)];
            Row& r = rows_.emplace_back();
            start_sphere_row(r, a, b, plane);
            r.sa = fraction_along(ca, p.on_a + ca.radius * m.normal); // the axis points behind the surface points
            r.sb = cb != nullptr ? fraction_along(*cb, p.on_b - cb->radius * m.normal) : 0.0;
        }
    };
    const std::uint32_t first = stat + 1;
    for (std::uint32_t k = first; k < first + n_capsules_; ++k) {
        const Body& A = bodies_[k];
        const Capsule ca = model_capsule(A);
        const double ma = model_capsule_margin(A, dt);
        AABB box{ca.p0.cwiseMin(ca.p1) - Eigen::Vector3d::Constant(ca.radius + ma),
                 ca.p0.cwiseMax(ca.p1) + Eigen::Vector3d::Constant(ca.radius + ma)};
        for (std::size_t i = 0; i < planes_.size(); ++i) {
            capsule_plane(ca, planes_[i], ma, m);
            add(k, stat, static_cast<int>(i), ca, nullptr);
        }
        for (std::uint32_t j = 0; j < stat; ++j) { // spheres: rigid, and other models'
            const Body& B = bodies_[j];
            if (B.model == A.model) continue;
            const double mb = uniform ? 0.5 * options_.margin : margins_[j];
            if (B.shape != Shape::sphere) { // a rigid box or capsule (worlds with shape fields): point rows
                if (!overlap(box, bounds_[j])) continue;
                if (B.shape == Shape::box) {
                    capsule_box(ca, obb_of(B), ma + mb, m);
                    if (m.count > 0) m.flip(); // the rigid body is side a
                } else {
                    capsule_capsule(capsule_of(B), ca, ma + mb, m);
                }
                add_model_manifold(m, j, k, nullptr, &ca);
                continue;
            }
            if (!(B.r > 0)) continue;
            capsule_sphere(ca, SphereBB{Eigen::Vector3d(B.p[0], B.p[1], B.p[2]), B.r}, ma + mb, m);
            add(k, j, -1, ca, nullptr);
        }
        for (std::uint32_t j = first; j < k; ++j) { // other models' capsules
            const Body& B = bodies_[j];
            if (B.model == A.model) continue;
            const Capsule cb = model_capsule(B);
            capsule_capsule(ca, cb, ma + model_capsule_margin(B, dt), m);
            add(k, j, -1, ca, &cb);
        }
    }
}

void Solver::spheres_to_rows(const World& w) {
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
        start_sphere_row(rows_[kept++], a, b, k.plane);
    }
    rows_.resize(kept);
}

void Solver::detect_shapes(const World& w, double dt) {
    const bool uniform = options_.margin >= 0;
    auto margin_of = [&](std::size_t k) { return uniform ? 0.5 * options_.margin : margins_[k]; };
    // Bounds: a sphere's box, a box's tight AABB, a capsule's segment's box grown by its
    // radius, each grown by its margin.
    bounds_.resize(n_rigid_);
    turns_.resize(n_rigid_);
    for (std::size_t k = 0; k < n_rigid_; ++k) {
        const Body& b = bodies_[k];
        const Eigen::Vector3d c(b.p[0], b.p[1], b.p[2]);
        const Quaternion q{b.q[0], b.q[1], b.q[2], b.q[3]};
        AABB box;
        switch (b.shape) {
        case Shape::sphere: box = aabb_from_sphere(SphereBB{c, b.r}); break;
        case Shape::box: { // aabb_from_obb, its rotation matrix kept for the narrow phase
            turns_[k] = q.to_matrix();
            const Eigen::Vector3d e = turns_[k].cwiseAbs() * Eigen::Vector3d(b.h[0], b.h[1], b.h[2]);
            box = AABB{c - e, c + e};
            break;
        }
        case Shape::capsule: {
            const Eigen::Vector3d e = q.rotate(Eigen::Vector3d(0, b.h[1], 0)).cwiseAbs() + Eigen::Vector3d::Constant(b.r);
            box = AABB{c - e, c + e};
            break;
        }
        }
        const Eigen::Vector3d grow = Eigen::Vector3d::Constant(margin_of(k));
        bounds_[k] = AABB{box.lo - grow, box.hi + grow};
    }
    point_rows_.clear();
    sphere_pairs_list_.clear();
    Manifold m;
    if (sphere_pairs_) {
        manager_.update(std::span<const AABB>(bounds_.data(), n_rigid_));
        for (const CandidatePair& p : manager_.run_broad_phase()) {
            const Body& A = bodies_[p.a];
            const Body& B = bodies_[p.b];
            if (A.shape == Shape::sphere && B.shape == Shape::sphere) {
                sphere_pairs_list_.push_back(p);
                continue;
            }
            const double margin = margin_of(p.a) + margin_of(p.b);
            if (!collide(A, B, margin, m, &turns_[p.a], &turns_[p.b])) continue;
            add_manifold(m, p.a, p.b, -1);
        }
    }
    if (uniform)
        sphere_sphere_contacts(w, sphere_pairs_list_, ids_, options_.margin, contacts_);
    else
        sphere_sphere_contacts(w, sphere_pairs_list_, ids_, std::span<const double>(margins_), contacts_);
    // Planes: spheres as sphere_plane_contacts does, the other shapes by their manifolds.
    const auto stat = static_cast<std::uint32_t>(ids_.size());
    for (std::size_t k = 0; k < n_rigid_; ++k) {
        const Body& b = bodies_[k];
        for (std::size_t i = 0; i < planes_.size(); ++i) {
            const Plane& pl = planes_[i];
            if (b.shape == Shape::sphere) {
                if (!(b.r > 0)) continue;
                const double s = pl.normal.x() * b.p[0] + pl.normal.y() * b.p[1] + pl.normal.z() * b.p[2] - pl.offset - b.r;
                if (s >= margin_of(k)) continue;
                Contact c;
                c.a = ids_[k];
                c.b = ids_[k];
                c.plane = static_cast<int>(i);
                c.normal = pl.normal;
                c.separation = s;
                contacts_.push_back(c);
                continue;
            }
            // The body lies inside its bounds (grown by its margin): when their lowest corner
            // clears the plane by more than rounding, nothing of it is within the margin.
            const AABB& bb = bounds_[k];
            const Eigen::Vector3d mid = 0.5 * (bb.lo + bb.hi), half = 0.5 * (bb.hi - bb.lo);
            const double centre = pl.normal.dot(mid) - pl.offset, reach = pl.normal.cwiseAbs().dot(half);
            if (centre - reach > 1e-12 * (std::abs(centre) + reach + std::abs(pl.offset))) continue;
            if (!collide_plane(b, pl, margin_of(k), m, b.shape == Shape::box ? &turns_[k] : nullptr)) continue;
            add_manifold(m, static_cast<std::uint32_t>(k), stat, static_cast<int>(i));
        }
    }
    if (!models_.empty()) model_sphere_contacts();
    spheres_to_rows(w);
    if (n_capsules_ > 0) capsule_rows(dt);
    if (n_boxes_ > 0) model_box_rows(dt);
    if (rows_.empty())
        rows_.swap(point_rows_); // (their capacities trade places: both are reserved alike)
    else
        rows_.insert(rows_.end(), point_rows_.begin(), point_rows_.end());
}

void Solver::model_sphere_contacts() {
    const bool uniform = options_.margin >= 0;
    auto margin_of = [&](std::size_t k) { return uniform ? 0.5 * options_.margin : margins_[k]; };
    auto contact = [&](std::size_t a, std::size_t b, int plane) {
        Contact c; // spheres_to_rows takes the pair and the plane; the geometry is found again
        c.normal = Eigen::Vector3d::Zero();
        c.separation = 0;
        c.a = ids_[a];
        c.b = ids_[b];
        c.plane = plane;
        contacts_.push_back(c);
    };
    Manifold m;
    for (std::size_t j = n_rigid_; j < ids_.size(); ++j) {
        const Body& X = bodies_[j];
        const double mx = margin_of(j);
        const Eigen::Vector3d c(X.p[0], X.p[1], X.p[2]);
        const AABB box{c - Eigen::Vector3d::Constant(X.r + mx), c + Eigen::Vector3d::Constant(X.r + mx)};
        for (std::size_t k = 0; k < n_rigid_; ++k) {
            const Body& A = bodies_[k];
            if (!overlap(box, bounds_[k])) continue;
            if (A.shape == Shape::sphere) {
                if (!(A.r > 0)) continue;
                const double d[3] = {A.p[0] - X.p[0], A.p[1] - X.p[1], A.p[2] - X.p[2]};
                const double reach = A.r + X.r + margin_of(k) + mx;
                if (dot(d, d) < reach * reach) contact(k, j, -1);
                continue;
            }
            if (!collide(A, X, margin_of(k) + mx, m)) continue; // normal from the model sphere towards A
            add_model_manifold(m, static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(j), nullptr, nullptr);
        }
        for (std::size_t k = j + 1; k < ids_.size(); ++k) { // other models' spheres
            const Body& B = bodies_[k];
            if (B.model == X.model) continue;
            const double d[3] = {B.p[0] - X.p[0], B.p[1] - X.p[1], B.p[2] - X.p[2]};
            const double reach = B.r + X.r + margin_of(k) + mx;
            if (dot(d, d) < reach * reach) contact(j, k, -1);
        }
        for (std::size_t i = 0; i < planes_.size(); ++i) {
            const Plane& pl = planes_[i];
            const double s = pl.normal.x() * X.p[0] + pl.normal.y() * X.p[1] + pl.normal.z() * X.p[2] - pl.offset - X.r;
            if (s < mx) contact(j, j, static_cast<int>(i));
        }
    }
}

void Solver::add_model_manifold(const Manifold& m, std::uint32_t a, std::uint32_t b, const Capsule* axis_a,
                                const Capsule* axis_b, int plane) {
    const Body& A = bodies_[a];
    const Body& B = bodies_[b];
    // A model sphere or capsule side keeps its point's offset from the point at its fraction
    // (world); a rigid body or model box its point in its own frame (it turns).
    auto anchor = [this](const Body& X, const Eigen::Vector3d& on, double s, double* l) {
        double t[3];
        const double* x = at_fraction(X, s, false, t);
        const Eigen::Vector3d d(on(0) - x[0], on(1) - x[1], on(2) - x[2]);
        const Eigen::Vector3d local = X.model >= 0 && X.shape != Shape::box ? d : Quaternion{X.q[0], X.q[1], X.q[2], X.q[3]}.rotate_inverse(d);
        for (int i = 0; i < 3; ++i) l[i] = local(i);
    };
    for (int k = 0; k < m.count; ++k) {
        const ManifoldPoint& p = m.points[static_cast<std::size_t>(k)];
        Row r{};
        r.a = a;
        r.b = b;
        r.plane = -1; // (b is no plane's static body)
        r.point = true;
        r.plane_a = plane + 1 <= 65535 ? static_cast<std::uint16_t>(plane + 1) : 0; // (0: not cached)
        r.feature = p.feature;
        r.n[0] = m.normal.x(), r.n[1] = m.normal.y(), r.n[2] = m.normal.z();
        r.sa = axis_a != nullptr ? fraction_along(*axis_a, p.on_a + axis_a->radius * m.normal) : 0.0;
        r.sb = axis_b != nullptr ? fraction_along(*axis_b, p.on_b - axis_b->radius * m.normal) : 0.0;
        anchor(A, p.on_a, r.sa, r.la);
        anchor(B, p.on_b, r.sb, r.lb);
        r.sep = p.separation;
        r.slot = -1;
        // each point its own row when a side is a model sphere or capsule (no spin, no block); a
        // model box's points against a rigid body, a plane or another model's box solved
        // together, as two rigid bodies' (block_solver.cpp)
        const bool block = B.shape == Shape::box && (A.model < 0 || A.shape == Shape::box);
        r.block_size = !block ? 1 : k == 0 ? static_cast<std::uint8_t>(m.count) : 0;
        point_rows_.push_back(r);
    }
}


bool collide(const Body& A, const Body& B, double margin, Manifold& m, const Eigen::Matrix3d* ra, const Eigen::Matrix3d* rb) {
    m.count = 0;
    if (A.shape == Shape::box && B.shape == Shape::box && ra != nullptr && rb != nullptr) {
        box_box(obb_of(A), *ra, obb_of(B), *rb, margin, m);
        return m.count > 0;
    }
    // Each pair of shapes once, a's shape the first; the other order by flipping.
    auto pair = [&](const Body& X, const Body& Y, bool flip) {
        switch (X.shape) {
        case Shape::box:
            switch (Y.shape) {
            case Shape::box: box_box(obb_of(X), obb_of(Y), margin, m); break;
            case Shape::sphere: sphere_box(sphere_of(Y), obb_of(X), margin, m), flip = !flip; break;
            case Shape::capsule: capsule_box(capsule_of(Y), obb_of(X), margin, m), flip = !flip; break;
            }
            break;
        case Shape::capsule:
            switch (Y.shape) {
            case Shape::capsule: capsule_capsule(capsule_of(X), capsule_of(Y), margin, m); break;
            case Shape::sphere: capsule_sphere(capsule_of(X), sphere_of(Y), margin, m); break;
            case Shape::box: capsule_box(capsule_of(X), obb_of(Y), margin, m); break;
            }
            break;
        case Shape::sphere: break; // sphere–sphere pairs are rows of their own
        }
        if (flip && m.count > 0) m.flip();
    };
    if (A.shape == Shape::sphere)
        pair(B, A, true);
    else
        pair(A, B, false);
    return m.count > 0;
}

bool collide_plane(const Body& A, const Plane& plane, double margin, Manifold& m, const Eigen::Matrix3d* ra) {
    m.count = 0;
    if (A.shape == Shape::box && ra != nullptr)
        box_plane(obb_of(A), *ra, plane, margin, m);
    else if (A.shape == Shape::box)
        box_plane(obb_of(A), plane, margin, m);
    else if (A.shape == Shape::capsule)
        capsule_plane(capsule_of(A), plane, margin, m);
    return m.count > 0;
}

Body shape_body(const World& w, Index i, int shape_field) {
    Body b{};
    b.p[0] = w.at(kX, i), b.p[1] = w.at(kY, i), b.p[2] = w.at(kZ, i);
    b.q[0] = w.at(kQW, i), b.q[1] = w.at(kQX, i), b.q[2] = w.at(kQY, i), b.q[3] = w.at(kQZ, i);
    b.r = w.at(kRadius, i);
    const auto f = static_cast<FieldId>(shape_field);
    b.shape = static_cast<Shape>(static_cast<int>(w.at(f, i)));
    for (int k = 0; k < 3; ++k) b.h[k] = w.at(f + 1 + static_cast<FieldId>(k), i);
    return b;
}

void Solver::add_manifold(const Manifold& m, std::uint32_t a, std::uint32_t b, int plane) {
    const Body& A = bodies_[a];
    const Body& B = bodies_[b];
    const Quaternion qa{A.q[0], A.q[1], A.q[2], A.q[3]}, qb{B.q[0], B.q[1], B.q[2], B.q[3]};
    // With linear position passes the bodies stay where they were found until setup_rows:
    // it takes the points themselves (xa, xb), not their anchors in the bodies' frames.
    const bool found = linear_positions();
    for (int k = 0; k < m.count; ++k) {
        const ManifoldPoint& p = m.points[static_cast<std::size_t>(k)];
        Row& r = point_rows_.emplace_back();
        r.a = a;
        r.b = b;
        r.plane = plane;
        r.point = true;
        r.feature = p.feature;
        r.n[0] = m.normal.x(), r.n[1] = m.normal.y(), r.n[2] = m.normal.z();
        if (found) {
            for (int i = 0; i < 3; ++i) r.xa[i] = p.on_a(i), r.xb[i] = p.on_b(i);
        } else {
            const Eigen::Vector3d la = qa.rotate_inverse(p.on_a - Eigen::Vector3d(A.p[0], A.p[1], A.p[2]));
            const Eigen::Vector3d lb = plane >= 0 ? p.on_b : qb.rotate_inverse(p.on_b - Eigen::Vector3d(B.p[0], B.p[1], B.p[2]));
            for (int i = 0; i < 3; ++i) r.la[i] = la(i), r.lb[i] = lb(i);
        }
        r.sep = p.separation;
        r.slot = -1;
        r.block_size = static_cast<std::uint8_t>(k == 0 ? m.count : 0);
    }
}

} // namespace phynjo::runtime::contact_detail
