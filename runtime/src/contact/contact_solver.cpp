// The contact rule: narrow phase → position correction → collisions → contact impulses;
// the maths in solver.hpp.
#include "solver.hpp"

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

namespace contact_detail {

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
    bodies_.resize(n + 1 + n_capsules_ + n_boxes_); // then the static body, the model capsules and boxes
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
        if (shape_field_ >= 0) {
            const auto f = static_cast<FieldId>(shape_field_);
            b.shape = static_cast<Shape>(static_cast<int>(w.at(f, i)));
            for (int j = 0; j < 3; ++j) b.h[j] = w.at(f + 1 + static_cast<FieldId>(j), i);
            b.q[0] = w.at(kQW, i), b.q[1] = w.at(kQX, i), b.q[2] = w.at(kQY, i), b.q[3] = w.at(kQZ, i);
        }
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

void Solver::anchors(const Row& c, double* xa, double* xb) const {
    const Body& A = bodies_[c.a];
    if (A.model >= 0 && A.shape != Shape::box) { // a model side a (against a model box): its point at sa, offset
        double t[3];
        const double* x = at_fraction(A, c.sa, false, t);
        for (int k = 0; k < 3; ++k) xa[k] = x[k] + c.la[k];
    } else {
        const Eigen::Vector3d a = Quaternion{A.q[0], A.q[1], A.q[2], A.q[3]}.rotate(Eigen::Vector3d(c.la[0], c.la[1], c.la[2]));
        for (int k = 0; k < 3; ++k) xa[k] = A.p[k] + a(k);
    }
    if (c.plane >= 0) {
        for (int k = 0; k < 3; ++k) xb[k] = c.lb[k];
        return;
    }
    const Body& B = bodies_[c.b];
    if (B.model >= 0 && B.shape != Shape::box) { // a model side: its point at sb, offset to the surface
        double t[3];
        const double* x = at_fraction(B, c.sb, false, t);
        for (int k = 0; k < 3; ++k) xb[k] = x[k] + c.lb[k];
        return;
    }
    const Eigen::Vector3d b = Quaternion{B.q[0], B.q[1], B.q[2], B.q[3]}.rotate(Eigen::Vector3d(c.lb[0], c.lb[1], c.lb[2]));
    for (int k = 0; k < 3; ++k) xb[k] = B.p[k] + b(k);
}

void Solver::apply_point(const Row& c, const double* p, std::vector<Body>& B) {
    Body& A = B[c.a];
    Body& Bb = B[c.b];
    double u[3], i[3];
    if (A.model >= 0) { // P on a model side a (against a model box) at its point sa
        model_impulse(A, p, B, false, c.sa, is_model_box(A) ? c.xa : nullptr);
    } else {
        for (int k = 0; k < 3; ++k) A.v[k] += A.im * p[k];
        cross(c.xa, p, u);
        mul_sym(A.ii, u, i);
        for (int k = 0; k < 3; ++k) A.w[k] += i[k];
    }
    if (Bb.model >= 0) { // −P on the model at its point sb
        const double q[3] = {-p[0], -p[1], -p[2]};
        model_impulse(Bb, q, B, false, c.sb, is_model_box(Bb) ? c.xb : nullptr);
        return;
    }
    for (int k = 0; k < 3; ++k) Bb.v[k] -= Bb.im * p[k];
    cross(c.xb, p, u);
    mul_sym(Bb.ii, u, i);
    for (int k = 0; k < 3; ++k) Bb.w[k] -= i[k];
}

double Solver::geometry(const Row& c, double* n) const {
    if (c.point) { // the manifold's normal, fixed for the step; the separation at the anchors
        double xa[3], xb[3];
        anchors(c, xa, xb);
        if (n != c.n) n[0] = c.n[0], n[1] = c.n[1], n[2] = c.n[2];
        return (xa[0] - xb[0]) * c.n[0] + (xa[1] - xb[1]) * c.n[1] + (xa[2] - xb[2]) * c.n[2];
    }
    const Body& A = bodies_[c.a];
    double ta[3], tb[3];
    const double* pa = at_fraction(A, c.sa, false, ta); // a model capsule's point at s
    if (c.plane >= 0) {
        const Plane& pl = planes_[static_cast<std::size_t>(c.plane)];
        n[0] = pl.normal.x(), n[1] = pl.normal.y(), n[2] = pl.normal.z();
        return dot(n, pa) - pl.offset - A.r;
    }
    const Body& B = bodies_[c.b];
    const double* pb = at_fraction(B, c.sb, false, tb);
    const double d[3] = {pa[0] - pb[0], pa[1] - pb[1], pa[2] - pb[2]};
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
        // (and the static body's, side a of a model box's rows against a plane: never applied)
        if (jacobi) delta_.assign(3 * (nb + 1), 0.0);
        if (jacobi && (shape_field_ >= 0 || n_boxes_ > 0)) turn_.assign(3 * (nb + 1), 0.0);
        bool any = false;
        std::size_t block = 0;
        for (std::size_t i = 0; i < rows_.size(); ++i) {
            Row& c = rows_[i];
            if (c.point && c.block_size >= 2) { // a manifold's points together
                if (it == 0 && block == pos_blocks_.size()) pos_blocks_.push_back(Block{});
                if (it == 0) pos_blocks_[block].set_known = false;
                any = correct_block(i, pos_blocks_[block++]) || any;
                i += c.block_size - 1u;
                continue;
            }
            Body& A = bodies_[c.a];
            double n[3];
            const double sep = geometry(c, n);
            const double depth = -sep - slop;
            if (depth <= 0) continue;
            Body& Bb = bodies_[c.b];
            if (c.point) {
                // At the contact point: K = 1/m_a + 1/m_b + (r_a × n)·I_a⁻¹(r_a × n) + (b alike),
                // P = β depth / K n, moving and turning both bodies.
                any = true;
                double xa[3], xb[3], ra[3], rb[3], ua[3], ub[3];
                anchors(c, xa, xb);
                for (int k = 0; k < 3; ++k) {
                    const double mid = 0.5 * (xa[k] + xb[k]);
                    ra[k] = mid - A.p[k];
                    rb[k] = mid - Bb.p[k];
                }
                cross(ra, n, ua);
                cross(rb, n, ub);
                if (A.model >= 0 || Bb.model >= 0) { // a model side: uᵀ A(s) u, and its correction through B(s)
                    const double* arm = is_model_box(Bb) ? rb : nullptr;
                    if (A.model >= 0) { // both sides models (a model box's row against another model)
                        correct_model_sides(c, n, beta * depth, is_model_box(A) ? ra : nullptr, arm, jacobi);
                        continue;
                    }
                    const double k_inv = A.im + quad(A.ii, ua) + linear_inverse_mass(Bb, n, c.sb, arm);
                    if (!(k_inv > kSingularInverseMass * (A.im + inverse_mass_scale(Bb)))) continue;
                    const double corr = beta * depth / k_inv;
                    double ta[3];
                    mul_sym(A.ii, ua, ta);
                    for (int k = 0; k < 3; ++k) ta[k] *= corr;
                    if (jacobi) {
                        for (int k = 0; k < 3; ++k) {
                            delta_[3 * c.a + k] += corr * A.im * n[k];
                            turn_[3 * c.a + k] += ta[k];
                        }
                    } else {
                        for (int k = 0; k < 3; ++k) A.p[k] += corr * A.im * n[k];
                        rotate_by(A.q, ta);
                    }
                    position_impulse(Bb, c.b, -corr, n, jacobi, c.sb, arm);
                    continue;
                }
                // (A plane's static body has no inverse mass or inertia: its terms vanish.)
                const double k_inv = A.im + Bb.im + quad(A.ii, ua) + quad(Bb.ii, ub);
                const double corr = beta * depth / k_inv;
                double ta[3], tb[3];
                mul_sym(A.ii, ua, ta);
                mul_sym(Bb.ii, ub, tb);
                for (int k = 0; k < 3; ++k) ta[k] *= corr, tb[k] *= -corr;
                if (jacobi) {
                    for (int k = 0; k < 3; ++k) {
                        delta_[3 * c.a + k] += corr * A.im * n[k];
                        turn_[3 * c.a + k] += ta[k];
                        if (c.plane < 0) {
                            delta_[3 * c.b + k] -= corr * Bb.im * n[k];
                            turn_[3 * c.b + k] += tb[k];
                        }
                    }
                } else {
                    for (int k = 0; k < 3; ++k) {
                        A.p[k] += corr * A.im * n[k];
                        Bb.p[k] -= corr * Bb.im * n[k];
                    }
                    rotate_by(A.q, ta);
                    if (c.plane < 0) rotate_by(Bb.q, tb);
                }
                continue;
            }
            if (has_model(c)) {
                any = correct_model_sides(c, n, beta * depth, nullptr, nullptr, jacobi) || any;
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
            if (shape_field_ >= 0)
                for (std::size_t b = 0; b < n_rigid_; ++b)
                    if (turn_[3 * b] != 0 || turn_[3 * b + 1] != 0 || turn_[3 * b + 2] != 0) rotate_by(bodies_[b].q, &turn_[3 * b]);
            for (std::size_t b = n_rigid_; b < nb; ++b)
                if (delta_[3 * b] != 0 || delta_[3 * b + 1] != 0 || delta_[3 * b + 2] != 0)
                    model_impulse(bodies_[b], &delta_[3 * b], bodies_, true);
        }
        if (!any) break;
    }
}

bool Solver::correct_model_sides(const Row& c, const double* n, double target, const double* arm_a, const double* arm_b,
                                 bool jacobi) {
    const Body& A = bodies_[c.a];
    const Body& B = bodies_[c.b];
    const double wsum = linear_inverse_mass(A, n, c.sa, arm_a) + linear_inverse_mass(B, n, c.sb, arm_b);
    if (!(wsum > kSingularInverseMass * (inverse_mass_scale(A) + inverse_mass_scale(B)))) return false;
    const double corr = target / wsum;
    position_impulse(A, c.a, corr, n, jacobi, c.sa, arm_a);
    if (c.plane < 0) position_impulse(B, c.b, -corr, n, jacobi, c.sb, arm_b);
    return true;
}

void Solver::position_impulse(const Body& X, std::size_t index, double corr, const double* n, bool jacobi, double s,
                              const double* arm) {
    const double l[3] = {corr * n[0], corr * n[1], corr * n[2]};
    if (is_model_capsule(X) || is_model_box(X)) { // at once, also under Jacobi: its point moves with the model
        model_impulse(X, l, bodies_, true, s, arm);
        return;
    }
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
    const bool linear = linear_positions();
    if (jacobi) {
        split_.assign(bodies_.size(), 0.0);
        for (const Row& c : rows_) {
            split_[c.a] += 1;
            split_[c.b] += 1;
        }
    }
    // A row's minimum normal velocity: the speculative −max(sep, 0)/dt, or, before linear
    // position passes, their target −sep − slop (push_positions sets the speculative one after).
    const double slop = options_.slop;
    auto bias = [&](double sep) { return linear ? -sep - slop : -std::max(sep, 0.0) / dt; };
    // The rows of a manifold of 2+ points form a block (setup_blocks), whose friction acts at
    // its centre with the block's own effective masses and the first row's μ: its rows need
    // only their normal's (solve_block_normal's fallback).
    std::size_t block_left = 0;
    for (Row& c : rows_) {
        const Body& A = bodies_[c.a];
        const Body& B = bodies_[c.b];
        const double sa = jacobi ? split_[c.a] : 1.0, sb = jacobi ? split_[c.b] : 1.0;
        const bool first_of_block = c.point && c.block_size >= 2;
        if (first_of_block) block_left = c.block_size;
        const bool in_block = block_left > 0;
        if (in_block) --block_left;
        if (c.point) {
            double xa[3], xb[3];
            if (linear) { // the points as found (add_manifold)
                for (int k = 0; k < 3; ++k) xa[k] = c.xa[k], xb[k] = c.xb[k];
            } else {
                anchors(c, xa, xb);
            }
            // a model sphere or capsule does not spin; a model box does
            const bool spin_a = A.model < 0 || A.shape == Shape::box, spin_b = c.plane < 0 && (B.model < 0 || B.shape == Shape::box);
            for (int k = 0; k < 3; ++k) {
                const double mid = 0.5 * (xa[k] + xb[k]);
                c.xa[k] = spin_a ? mid - A.p[k] : 0.0;
                c.xb[k] = spin_b ? mid - B.p[k] : 0.0;
            }
            c.ra = c.rb = 0;
            c.sep = (xa[0] - xb[0]) * c.n[0] + (xa[1] - xb[1]) * c.n[1] + (xa[2] - xb[2]) * c.n[2];
            tangent_basis(c.n, c.t1, c.t2);
            if (B.model >= 0) { // a model side b (file comment of solver.hpp): uᵀ A(s) u for it
                const double floor = kSingularInverseMass * (sa * inverse_mass_scale(A) + sb * inverse_mass_scale(B));
                auto inverse_mass = [&](const double* u) {
                    double ua[3];
                    cross(c.xa, u, ua);
                    // (a model side a, against a model box: its own uᵀ A u at its point)
                    const double ka = A.model >= 0 ? linear_inverse_mass(A, u, c.sa, is_model_box(A) ? c.xa : nullptr) : A.im + quad(A.ii, ua);
                    const double k = sa * ka + sb * linear_inverse_mass(B, u, c.sb, is_model_box(B) ? c.xb : nullptr);
                    return k > floor ? 1 / k : 0.0;
                };
                c.mn = inverse_mass(c.n);
                c.mt1 = inverse_mass(c.t1);
                c.mt2 = inverse_mass(c.t2);
            } else { // a block's rows: their normal's only where no set solves it (solve_block_normal)
                c.mn = in_block ? 0.0 : 1 / point_inverse_mass(A, B, c.xa, c.xb, c.n, sa, sb);
                c.mt1 = in_block ? 0.0 : 1 / point_inverse_mass(A, B, c.xa, c.xb, c.t1, sa, sb);
                c.mt2 = in_block ? 0.0 : 1 / point_inverse_mass(A, B, c.xa, c.xb, c.t2, sa, sb);
            }
            c.bias = bias(c.sep);
            if (in_block && !first_of_block) {
                c.mu = 0;
                continue;
            }
            double vt1, vt2;
            tangent_velocity(c, A, B, vt1, vt2);
            c.mu = curve(material_.friction, std::sqrt(vt1 * vt1 + vt2 * vt2), false);
            continue;
        }
        c.ra = is_model_capsule(A) ? 0.0 : A.r; // a model capsule does not spin
        c.rb = c.plane >= 0 || is_model_capsule(B) ? 0.0 : B.r;
        c.sep = geometry(c, c.n);
        tangent_basis(c.n, c.t1, c.t2);
        if (has_model(c)) {
            // A model sphere's translational inverse mass depends on the direction, and a
            // direction it cannot move along (K⁻¹ ≈ 0 on both sides) takes no impulse.
            const double floor = kSingularInverseMass * (sa * inverse_mass_scale(A) + sb * inverse_mass_scale(B));
            const double kn = sa * linear_inverse_mass(A, c.n, c.sa) + sb * linear_inverse_mass(B, c.n, c.sb);
            const double k1 = sa * linear_inverse_mass(A, c.t1, c.sa) + sb * linear_inverse_mass(B, c.t1, c.sb) +
                              sa * c.ra * c.ra * quad(A.ii, c.t2) + sb * c.rb * c.rb * quad(B.ii, c.t2);
            const double k2 = sa * linear_inverse_mass(A, c.t2, c.sa) + sb * linear_inverse_mass(B, c.t2, c.sb) +
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
        c.bias = bias(c.sep);
        // μ from the sliding speed before the solve.
        double vt1, vt2;
        tangent_velocity(c, A, B, vt1, vt2);
        c.mu = curve(material_.friction, std::sqrt(vt1 * vt1 + vt2 * vt2), false);
    }
    setup_blocks();
}

void Solver::apply_central(const Block& k, double l1, double l2, double ltw, std::vector<Body>& B) {
    Body& A = B[k.a];
    Body& Bb = B[k.b];
    double p[3], u[3], i[3];
    for (int d = 0; d < 3; ++d) {
        p[d] = l1 * k.t1[d] + l2 * k.t2[d];
        A.v[d] += A.im * p[d];
        Bb.v[d] -= Bb.im * p[d];
    }
    cross(k.ra, p, u);
    for (int d = 0; d < 3; ++d) u[d] += ltw * k.n[d];
    if (is_model_box(A)) { // another model's box as side a (b is one too): p and the moment r_a × p + ltw n
        model_wrench(A, p, u, B, false);
    } else {
        mul_sym(A.ii, u, i);
        for (int d = 0; d < 3; ++d) A.w[d] += i[d];
    }
    cross(k.rb, p, u);
    for (int d = 0; d < 3; ++d) u[d] += ltw * k.n[d];
    if (is_model_box(Bb)) { // −p at its centre of the block and the moment −(r_b × p + ltw n)
        const double force[3] = {-p[0], -p[1], -p[2]}, moment[3] = {-u[0], -u[1], -u[2]};
        model_wrench(Bb, force, moment, B, false);
        return;
    }
    mul_sym(Bb.ii, u, i);
    for (int d = 0; d < 3; ++d) Bb.w[d] -= i[d];
}

void Solver::apply_normal(Row& c, double l, std::vector<Body>& B) {
    if (c.point) {
        const double p[3] = {l * c.n[0], l * c.n[1], l * c.n[2]};
        apply_point(c, p, B);
        return;
    }
    Body& A = B[c.a];
    Body& Bb = B[c.b];
    if (A.model >= 0 || Bb.model >= 0) {
        const double pa[3] = {l * c.n[0], l * c.n[1], l * c.n[2]}, pb[3] = {-pa[0], -pa[1], -pa[2]};
        side_impulse(A, pa, nullptr, 0, c.sa, B);
        side_impulse(Bb, pb, nullptr, 0, c.sb, B);
        return;
    }
    for (int k = 0; k < 3; ++k) {
        A.v[k] += A.im * l * c.n[k];
        Bb.v[k] -= Bb.im * l * c.n[k];
    }
}

void Solver::apply_tangent(Row& c, double l1, double l2, std::vector<Body>& B) {
    if (c.point) {
        const double p[3] = {l1 * c.t1[0] + l2 * c.t2[0], l1 * c.t1[1] + l2 * c.t2[1], l1 * c.t1[2] + l2 * c.t2[2]};
        apply_point(c, p, B);
        return;
    }
    Body& A = B[c.a];
    Body& Bb = B[c.b];
    if (A.model >= 0 || Bb.model >= 0) {
        double pa[3], pb[3], u[3];
        for (int k = 0; k < 3; ++k) {
            pa[k] = l1 * c.t1[k] + l2 * c.t2[k];
            pb[k] = -pa[k];
            u[k] = l2 * c.t1[k] - l1 * c.t2[k];
        }
        side_impulse(A, pa, u, c.ra, c.sa, B);
        side_impulse(Bb, pb, u, c.rb, c.sb, B);
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

void Solver::side_impulse(Body& X, const double* p, const double* u, double r, double s, std::vector<Body>& B) {
    if (X.model >= 0) { // no spin: the impulse acts at the sphere's centre (the capsule's point at s)
        model_impulse(X, p, B, false, s);
        return;
    }
    for (int k = 0; k < 3; ++k) X.v[k] += X.im * p[k];
    if (u != nullptr) {
        double i[3];
        mul_sym(X.ii, u, i);
        for (int k = 0; k < 3; ++k) X.w[k] += r * i[k];
    }
}

bool Solver::cache_home(const Row& c, CacheHome& h) const {
    const std::size_t stat = ids_.size();
    // The other side's tag: a component's index + 1, a plane's −(index + 1) (b's plane, or
    // plane_a for a's), or, a model's capsule or box (no component), the count of components +
    // its place among them; and a key: the tag, a point row's feature times 2³² beyond it.
    auto tag = [&](std::uint32_t x) {
        if (x == stat) return x == c.b ? -(c.plane + 1.0) : -static_cast<double>(c.plane_a);
        if (x < stat) return ids_[x] + 1.0;
        return static_cast<double>(layout_->components.size() + (x - stat));
    };
    auto keyed = [&](double partner) {
        if (!c.point) return partner;
        const double f = 4294967296.0 * c.feature;
        return partner > 0 ? partner + f : partner - f;
    };
    // A model capsule's rows that are not a manifold's keep no cache (their point moves along
    // the segment, and nothing names which end they are).
    if (!c.point && (c.a > stat || c.b > stat)) return false;
    if (c.a < stat) { // side a's component, b tagged
        h.first = &ids_[c.a];
        h.components = 1;
        h.counter = c.a;
        h.key = keyed(tag(c.b));
        return true;
    }
    // Side a has no component (a plane's static body, or a model capsule or box): the row is
    // kept in the slots of the coordinates of the model of a (of b against a plane), pooled,
    // keyed by the other side's tag and the shape's place among its model's capsules and
    // boxes (2²² apart: up to 4,194,303 tags and 1,024 shapes a model, else not cached).
    const std::uint32_t own = c.a == stat ? c.b : c.a;
    const Body& X = bodies_[own];
    const ModelScratch& m = models_[static_cast<std::size_t>(X.model)];
    const double partner = tag(own == c.a ? c.b : c.a);
    const std::size_t local = X.shape == Shape::box ? m.placed.ends.size() + static_cast<std::size_t>(X.sphere) : static_cast<std::size_t>(X.sphere);
    constexpr double kTags = 4194304.0;
    if (partner == 0 || !(std::abs(partner) < kTags) || local >= 1024 || m.placed.coordinates.empty()) return false;
    const double base = std::abs(partner) + kTags * static_cast<double>(local);
    h.first = m.placed.coordinates.data();
    h.components = m.placed.coordinates.size();
    h.counter = stat + 1 + static_cast<std::size_t>(X.model); // after the bodies' counters
    h.key = keyed(partner > 0 ? base : -base);
    return true;
}

void Solver::find_slots(const World& w) {
    // Each item (a row, or a manifold's rows together) that may strike: one without a slot
    // at some point (collisions visits them alone, in order).
    impacts_.clear();
    auto strike = [&](std::size_t i) {
        const Row& c = rows_[i];
        if (c.slot >= 0) return;
        const std::size_t item = c.block >= 0 ? blocks_[static_cast<std::size_t>(c.block)].first : i;
        if (impacts_.empty() || impacts_.back() != item) impacts_.push_back(item);
    };
    if (slots_.empty()) {
        for (std::size_t i = 0; i < rows_.size(); ++i) strike(i);
        return;
    }
    CacheHome h;
    for (std::size_t r = 0; r < rows_.size(); ++r) {
        Row& c = rows_[r];
        if (!cache_home(c, h)) {
            strike(r);
            continue;
        }
        // slots are filled from the front, component after component of a pool
        bool done = false;
        for (std::size_t i = 0; i < h.components && !done; ++i) {
            const Index a = h.first[i];
            for (std::size_t k = 0; k < slots_.size(); ++k) {
                const double p = w.at(slots_[k].partner, a);
                if (p == 0) {
                    done = true;
                    break;
                }
                if (p == h.key) {
                    c.slot = static_cast<int>(k);
                    c.home = a;
                    done = true;
                    break;
                }
            }
        }
        strike(r);
    }
}

void Solver::warm_start(const World& w) {
    if (slots_.empty()) return;
    for (Row& c : rows_) {
        if (c.slot < 0) continue;
        const Slot* s = &slots_[static_cast<std::size_t>(c.slot)];
        const Index a = c.home;
        const double jt[3] = {w.at(s->jtx, a), w.at(s->jty, a), w.at(s->jtz, a)};
        c.jn = w.at(s->jn, a);
        apply_normal(c, c.jn, bodies_);
        if (c.block >= 0) { // a manifold's friction is its centre's: summed over its points
            Block& k = blocks_[static_cast<std::size_t>(c.block)];
            k.jt1 += dot(jt, k.t1);
            k.jt2 += dot(jt, k.t2);
            continue;
        }
        c.jt1 = dot(jt, c.t1);
        c.jt2 = dot(jt, c.t2);
        clamp_disk(c.jt1, c.jt2, c.mu * c.jn);
        apply_tangent(c, c.jt1, c.jt2, bodies_);
    }
    for (std::size_t i = 0; i < rows_.size(); ++i) {
        const Row& c = rows_[i];
        if (c.block < 0 || c.block_size == 0) continue;
        Block& k = blocks_[static_cast<std::size_t>(c.block)];
        double load = 0;
        for (std::size_t j = 0; j < k.count; ++j) load += rows_[i + j].jn;
        clamp_disk(k.jt1, k.jt2, k.mu * load);
        if (k.jt1 != 0 || k.jt2 != 0) apply_central(k, k.jt1, k.jt2, 0, bodies_);
    }
}

void Solver::collisions(double dt) {
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    for (int it = 0; it < options_.restitution_iterations; ++it) {
        bool any = false;
        if (jacobi) snapshot_ = bodies_;
        const std::vector<Body>& from = jacobi ? snapshot_ : bodies_; // read; impulses go to bodies_
        // A manifold resting at every point (each carried a load: a cache slot) has no
        // impact, nor has a resting row: find_slots lists the others.
        for (std::size_t i : impacts_) {
            Row& c = rows_[i];
            const Body& A = from[c.a];
            const Body& B = from[c.b];
            if (c.block >= 0) { // a manifold's points together (solve_lcp)
                Block& k = blocks_[static_cast<std::size_t>(c.block)];
                const std::size_t m = k.count;
                double vn[4] = {0, 0, 0, 0}, target[4] = {0, 0, 0, 0}, x[4];
                bool hit = false;
                for (std::size_t j = 0; j < m; ++j) {
                    const Row& r = rows_[i + j];
                    vn[j] = normal_velocity(r, A, B);
                    if (r.slot >= 0 || vn[j] >= 0 || r.sep + vn[j] * dt >= 0) continue;
                    const double e = curve(material_.restitution, -vn[j], true);
                    target[j] = -e * vn[j];
                    hit = hit || e > 0;
                }
                i += m - 1;
                if (!hit || !solve_lcp(k, vn, target, x)) continue;
                any = true;
                double load = 0;
                for (std::size_t j = 0; j < m; ++j) {
                    apply_normal(rows_[i + 1 - m + j], x[j], bodies_);
                    load += x[j];
                }
                double wa[3], wb[3], dv[3];
                cross(A.w, k.ra, wa);
                cross(B.w, k.rb, wb);
                for (int d = 0; d < 3; ++d) dv[d] = A.v[d] + wa[d] - B.v[d] - wb[d];
                double l1 = -dot(dv, k.t1) * k.mt1, l2 = -dot(dv, k.t2) * k.mt2;
                clamp_disk(l1, l2, k.mu * load);
                if (l1 != 0 || l2 != 0) apply_central(k, l1, l2, 0, bodies_);
                continue;
            }
            if (c.slot >= 0) continue; // resting
            const double vn = normal_velocity(c, A, B);
            if (vn >= 0 || c.sep + vn * dt >= 0) continue;
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

void Solver::solve_row_friction(Row& c, const std::vector<Body>& from) {
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

void Solver::solve_row_normal(Row& c, const std::vector<Body>& from) {
    const double vn = normal_velocity(c, from[c.a], from[c.b]);
    const double jn = std::max(c.jn - (vn - c.bias) * c.mn, 0.0);
    const double l = jn - c.jn;
    c.jn = jn;
    if (l != 0) apply_normal(c, l, bodies_);
}

void Solver::solve_block_friction(Block& k, const std::vector<Body>& from) {
    const Body& A = from[k.a];
    const Body& B = from[k.b];
    double wa[3], wb[3], dv[3];
    cross(A.w, k.ra, wa);
    cross(B.w, k.rb, wb);
    for (int d = 0; d < 3; ++d) dv[d] = A.v[d] + wa[d] - B.v[d] - wb[d];
    double load = 0;
    for (std::size_t j = 0; j < k.count; ++j) load += k.jn[j];
    const double limit = k.mu * load;
    double n1 = k.jt1 - dot(dv, k.t1) * k.mt1, n2 = k.jt2 - dot(dv, k.t2) * k.mt2;
    clamp_disk(n1, n2, limit);
    const double wn = (A.w[0] - B.w[0]) * k.n[0] + (A.w[1] - B.w[1]) * k.n[1] + (A.w[2] - B.w[2]) * k.n[2];
    const double ntw = std::clamp(k.jtw - wn * k.mtw, -limit * k.reach, limit * k.reach);
    const double l1 = n1 - k.jt1, l2 = n2 - k.jt2, ltw = ntw - k.jtw;
    k.jt1 = n1, k.jt2 = n2, k.jtw = ntw;
    if (l1 != 0 || l2 != 0 || ltw != 0) apply_central(k, l1, l2, ltw, bodies_);
}

void Solver::solve_block_normal(Block& k, const std::vector<Body>& from, bool lanes_tried) {
    if (solve_block(k, from, lanes_tried)) return;
    Row* r = &rows_[k.first]; // its points one by one, as rows
    const Body& A = bodies_[k.a];
    const Body& B = bodies_[k.b];
    if (B.model < 0) { // their normal's effective masses, which setup_rows leaves to this rare case
        const bool jacobi = options_.scheme == ContactScheme::jacobi;
        const double sa = jacobi ? split_[k.a] : 1.0, sb = jacobi ? split_[k.b] : 1.0;
        for (std::size_t j = 0; j < k.count; ++j) r[j].mn = 1 / point_inverse_mass(A, B, r[j].xa, r[j].xb, r[j].n, sa, sb);
    }
    for (std::size_t j = 0; j < k.count; ++j) {
        r[j].jn = k.jn[j];
        solve_row_normal(r[j], from);
        k.jn[j] = r[j].jn;
    }
}

template <int L>
void Solver::velocity_pass(const std::vector<Body>& from) {
    std::vector<WideGroupOf<L>>& gs = groups<L>();
    std::size_t group = 0;
    for (std::size_t at = 0; at < schedule_.size(); ++at) {
        if (group < gs.size() && group_start_[group] == at) {
            WideGroupOf<L>& g = gs[group++];
            switch (g.count) {
            case 1: solve_rows(g); break;
            case 2: solve_group<2>(g); break;
            case 3: solve_group<3>(g); break;
            default: solve_group<4>(g); break;
            }
            at += L - 1;
            continue;
        }
        const std::int64_t item = schedule_[at];
        if (item >= 0) {
            Row& c = rows_[static_cast<std::size_t>(item)];
            solve_row_friction(c, from);
            solve_row_normal(c, from);
            continue;
        }
        // A manifold: friction at its centre, then its points' normal impulses together.
        Block& k = blocks_[static_cast<std::size_t>(-1 - item)];
        solve_block_friction(k, from);
        solve_block_normal(k, from);
    }
}

void Solver::solve_contacts() {
    const bool jacobi = options_.scheme == ContactScheme::jacobi;
    for (Block& k : blocks_)
        for (std::size_t j = 0; j < k.count; ++j) k.jn[j] = rows_[k.first + j].jn, k.bias[j] = rows_[k.first + j].bias;
    load_groups(!linear_positions()); // push_positions loaded them
    for (int it = 0; it < options_.velocity_iterations; ++it) {
        if (jacobi) snapshot_ = bodies_;
        // Friction first, limited by the normal impulse of the previous pass; Gauss–Seidel's
        // normal impulses see the friction just applied, Jacobi's the pass's start.
        const std::vector<Body>& from = jacobi ? snapshot_ : bodies_;
        with_lanes([&](auto lanes) { velocity_pass<lanes()>(from); });
    }
    store_groups();
    // Back into the rows (store_cache): the normal impulses, and the centre's friction cached
    // with the first pressing point (warm_start sums them).
    for (const Block& k : blocks_) {
        Row* r = &rows_[k.first];
        for (std::size_t j = 0, held = 0; j < k.count; ++j) {
            r[j].jn = k.jn[j];
            const bool carry = held == 0 && r[j].jn > 0;
            r[j].jt1 = carry ? k.jt1 : 0.0;
            r[j].jt2 = carry ? k.jt2 : 0.0;
            held += carry ? 1 : 0;
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
        if (shape_field_ >= 0) // turned by the position correction
            w.at(kQW, i) = b.q[0], w.at(kQX, i) = b.q[1], w.at(kQY, i) = b.q[2], w.at(kQZ, i) = b.q[3];
    }
}

void Solver::store_cache(World& w) {
    if (slots_.empty()) return;
    for (const Slot& s : slots_) {
        if (ids_contiguous_) // one run of the field (an all_bodies set)
            std::fill_n(&w.at(s.partner, ids_.front()), ids_.size(), 0.0);
        else
            for (Index i : ids_) w.at(s.partner, i) = 0;
        for (const ModelScratch& m : models_)
            if (!m.placed.ends.empty() || !m.placed.boxes.empty()) // its capsules' and boxes' pool
                for (Index i : m.placed.coordinates) w.at(s.partner, i) = 0;
    }
    // Rows are grouped by body a (pairs sorted by a, then the planes of each body in order),
    // but a body's rows need not be contiguous: each fills its body's next slot (a model's
    // pool: the next of its coordinates' slots), from the front (find_slots stops at the first
    // empty one; a key is never 0).
    slots_used_.assign(ids_.size() + 1 + models_.size(), 0);
    CacheHome h;
    for (const Row& c : rows_) {
        if (c.jn <= 0 || !cache_home(c, h)) continue;
        std::uint32_t& used = slots_used_[h.counter];
        if (used == h.components * slots_.size()) continue; // every slot taken: the contact is not cached
        const Slot& s = slots_[used % slots_.size()];
        const Index a = h.first[used / slots_.size()];
        ++used;
        w.at(s.partner, a) = h.key;
        w.at(s.jn, a) = c.jn;
        w.at(s.jtx, a) = c.jt1 * c.t1[0] + c.jt2 * c.t2[0];
        w.at(s.jty, a) = c.jt1 * c.t1[1] + c.jt2 * c.t2[1];
        w.at(s.jtz, a) = c.jt1 * c.t1[2] + c.jt2 * c.t2[2];
    }
}

void Solver::step(double dt, World& w) {
    if (!(dt > 0) || !std::isfinite(dt)) throw Error("contact: the step dt must be positive and finite");
    gather(w);
    detect(w, dt);
    if (linear_positions()) {
        setup_rows(dt);
        push_positions(dt);
    } else {
        correct_positions();
        setup_rows(dt);
    }
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
    // With boxes or capsules, the position correction turns bodies too.
    if (shape_field(layout) >= 0) d = d | Domain::of(layout, {"qw", "qx", "qy", "qz"}, bodies);
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
    if (options.lanes != 0 && options.lanes != 4 && options.lanes != 8)
        throw std::invalid_argument("contact_rule: lanes must be 0 (the machine's), 4 or 8");
}

Domain reads_of(const Layout& layout, const ComponentSet& bodies) {
    Domain d = Domain::of(layout, {"m", "inv_m", "iIxx", "iIyy", "iIzz", "iIxy", "iIxz", "iIyz", "radius", "qw", "qx", "qy", "qz"},
                          bodies);
    if (shape_field(layout) >= 0) d = d | Domain::of(layout, {"shape", "hx", "hy", "hz"}, bodies);
    return d;
}

} // namespace contact_detail

using contact_detail::reads_of;
using contact_detail::Solver;
using contact_detail::validate;
using contact_detail::writes_of;

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
    if (const int f = shape_field(w.layout()); f >= 0) { // every shape: the manifolds' deepest points
        std::vector<contact_detail::Body> b(ids.size());
        std::vector<AABB> boxes(ids.size());
        for (std::size_t k = 0; k < ids.size(); ++k) {
            b[k] = contact_detail::shape_body(w, ids[k], f);
            const Eigen::Vector3d c = position(w, ids[k]);
            const Eigen::Vector3d h(b[k].h[0], b[k].h[1], b[k].h[2]);
            const double reach = b[k].shape == Shape::box ? h.norm() : b[k].r + h.y();
            boxes[k] = aabb_from_sphere(SphereBB{c, reach});
        }
        std::vector<CandidatePair> pairs;
        UniformGrid().find_pairs(boxes, pairs);
        double worst = 0;
        Manifold m;
        auto deepest = [&] {
            for (int k = 0; k < m.count; ++k) worst = std::max(worst, -m.points[static_cast<std::size_t>(k)].separation);
        };
        for (const CandidatePair& p : pairs) {
            const contact_detail::Body& A = b[p.a];
            const contact_detail::Body& B = b[p.b];
            if (A.shape == Shape::sphere && B.shape == Shape::sphere) {
                const Eigen::Vector3d d(A.p[0] - B.p[0], A.p[1] - B.p[1], A.p[2] - B.p[2]);
                if (A.r > 0 && B.r > 0) worst = std::max(worst, A.r + B.r - d.norm());
                continue;
            }
            if (contact_detail::collide(A, B, 0, m)) deepest();
        }
        for (std::size_t k = 0; k < ids.size(); ++k)
            for (const Plane& pl : planes) {
                if (b[k].shape == Shape::sphere) {
                    if (b[k].r > 0)
                        worst = std::max(worst, b[k].r + pl.offset - pl.normal.dot(Eigen::Vector3d(b[k].p[0], b[k].p[1], b[k].p[2])));
                    continue;
                }
                if (contact_detail::collide_plane(b[k], pl, 0, m)) deepest();
            }
        return worst;
    }
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
