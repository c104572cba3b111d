// The optimize step (optimize.hpp): Horner forms and the Jacobians of them.
#include "phynjo/codegen/optimize.hpp"

#include "box_kinematics.hpp"

#include "phynjo/cas/cas.hpp"

#include <initializer_list>

namespace phynjo::codegen {

namespace {

using cas::Expr;

/// Every expression of `vs` in Horner form, from one pass that shares the work on common
/// subexpressions.
void horner_in_place(std::initializer_list<std::vector<Expr>*> vs) {
    std::vector<Expr> all;
    for (auto* v : vs) all.insert(all.end(), v->begin(), v->end());
    const auto h = cas::horner(all);
    std::size_t k = 0;
    for (auto* v : vs)
        for (Expr& e : *v) e = h[k++];
}

} // namespace

OptimizedEquations optimize(const Model& m, const EquationsOfMotion& derived) {
    // Horner form (common factors out of sums) of everything, in one pass that shares the
    // work on common subexpressions; each function body is then CSE'd. Together: fewer
    // operations than SymPy's cse on the same system (bench/RESULTS.md).
    OptimizedEquations o;
    EquationsOfMotion& eom = o.eom;
    eom = derived;
    std::vector<Expr> energy{eom.energy};
    horner_in_place({&eom.mass_matrix, &eom.forcing, &eom.momenta, &eom.generalized_forces, &eom.constraint_matrix,
                     &eom.gamma, &eom.residuals, &eom.velocity_residuals, &energy});
    eom.energy = energy[0];
    derive_jacobians(m, eom);
    // the derivatives of the Horner forms, in Horner form again: nlink_cart(40)'s
    // canonical_jacobian 1.11 → 0.59 MB of C++, rhs_jacobian 0.61 → 0.57 MB
    horner_in_place({&eom.jacobian_r, &eom.jacobian_c, &eom.input_r, &eom.input_c, &eom.momenta_jacobian,
                     &eom.force_jacobian});

    for (const Event& e : m.events) o.guards.push_back(e.guard);
    o.guards = cas::horner(o.guards);
    for (const Event& e : m.events) {
        std::vector<Expr> values;
        for (const EventReset& r : e.resets) values.push_back(r.value);
        o.reset_values.push_back(values.empty() ? values : cas::horner(values));
    }
    const auto q = m.coordinate_symbols();
    for (const Shape& sh : m.shapes) {
        if (sh.kind == Shape::Kind::Box) {
            const auto pose = detail::box_pose(sh);
            o.shape_points.insert(o.shape_points.end(), pose.begin(), pose.end());
            const auto J = detail::box_jacobian(sh, q);
            o.box_jacobians.insert(o.box_jacobians.end(), J.begin(), J.end());
            o.box_half_extents.insert(o.box_half_extents.end(), sh.half_extents.begin(), sh.half_extents.end());
            for (std::size_t k = 0; k < sh.turns.size(); ++k) {
                const auto& a = sh.turns[k].axis;
                const Expr length2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
                if (length2.is_number()) continue; // not zero: the analyzer checked it
                o.box_axis_checks.push_back({length2, "the axis of turn " + std::to_string(k + 1) + " of box '" + sh.name + "'"});
            }
            continue;
        }
        o.shape_points.insert(o.shape_points.end(), sh.points.begin(), sh.points.end());
        if (sh.kind == Shape::Kind::Segment) continue;
        const bool sphere = sh.kind == Shape::Kind::Sphere;
        (sphere ? o.sphere_radii : o.capsule_radii).push_back(sh.radius);
        for (std::size_t a = 0; a < sh.points.size(); ++a)
            for (std::size_t i = 0; i < m.dof(); ++i)
                (sphere ? o.sphere_jacobians : o.capsule_jacobians).push_back(cas::diff(sh.points[a], q[i]));
    }
    if (!o.shape_points.empty()) o.shape_points = cas::horner(o.shape_points);
    if (!o.sphere_jacobians.empty()) o.sphere_jacobians = cas::horner(o.sphere_jacobians);
    if (!o.capsule_jacobians.empty()) o.capsule_jacobians = cas::horner(o.capsule_jacobians);
    if (!o.box_jacobians.empty()) o.box_jacobians = cas::horner(o.box_jacobians);
    o.initial_values = m.initial_q;
    o.initial_values.insert(o.initial_values.end(), m.initial_qdot.begin(), m.initial_qdot.end());
    return o;
}

} // namespace phynjo::codegen
