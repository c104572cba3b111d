// A box shape's pose and velocity Jacobian (box_kinematics.hpp).
#include "box_kinematics.hpp"

#include "phynjo/cas/cas.hpp"

#include <array>

namespace phynjo::codegen::detail {

namespace {

using cas::Expr;
using Vec = std::array<Expr, 3>;

Expr dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The unit axis â = a/|a| of a turn.
Vec unit_axis(const ShapeTurn& t) {
    const Expr norm = cas::sqrt(dot(t.axis, t.axis));
    return {t.axis[0] / norm, t.axis[1] / norm, t.axis[2] / norm};
}

/// R(â, A) v = v cos A + (â × v) sin A + â (â·v)(1 − cos A) (Rodrigues).
Vec rotate(const Vec& axis, Expr angle, const Vec& v) {
    const Expr c = cas::cos(angle), s = cas::sin(angle), along = dot(axis, v) * (cas::integer(1) - c);
    const Vec w = cross(axis, v);
    Vec out;
    for (std::size_t d = 0; d < 3; ++d) out[d] = v[d] * c + w[d] * s + axis[d] * along;
    return out;
}

} // namespace

std::vector<Expr> box_pose(const Shape& box) {
    std::vector<Expr> pose(box.points.begin(), box.points.end());
    Expr w = cas::integer(1);
    Vec v{cas::integer(0), cas::integer(0), cas::integer(0)};
    for (const ShapeTurn& t : box.turns) { // q ← q_k ⊗ q
        const Expr half = t.angle / cas::integer(2), c = cas::cos(half), s = cas::sin(half);
        const Vec a = unit_axis(t);
        const Vec u{s * a[0], s * a[1], s * a[2]};
        const Vec uv = cross(u, v);
        const Expr w2 = c * w - dot(u, v);
        Vec v2;
        for (std::size_t d = 0; d < 3; ++d) v2[d] = c * v[d] + w * u[d] + uv[d];
        w = w2;
        v = v2;
    }
    pose.push_back(w);
    pose.insert(pose.end(), v.begin(), v.end());
    return pose;
}

std::vector<Expr> box_jacobian(const Shape& box, std::span<const Expr> q) {
    const std::size_t n = q.size(), turns = box.turns.size();
    std::vector<Expr> J(6 * n, cas::integer(0));
    for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t i = 0; i < n; ++i) J[a * n + i] = cas::diff(box.points[a], q[i]);
    for (std::size_t k = 0; k < turns; ++k) {
        Vec u = unit_axis(box.turns[k]);
        for (std::size_t j = k + 1; j < turns; ++j) u = rotate(unit_axis(box.turns[j]), box.turns[j].angle, u);
        for (std::size_t i = 0; i < n; ++i) {
            const Expr rate = cas::diff(box.turns[k].angle, q[i]);
            for (std::size_t d = 0; d < 3; ++d) J[(3 + d) * n + i] = J[(3 + d) * n + i] + rate * u[d];
        }
    }
    return J;
}

} // namespace phynjo::codegen::detail
