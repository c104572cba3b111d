// The shape statement: spheres, segments, capsules and boxes, their points, radii, half extents
// and turns. (analyzer.hpp)
#include "analyzer.hpp"

namespace phynjo::codegen::detail {

void Analyzer::visit(const grammar::ast::ShapeStmt& s) {
    const std::string what = "shape '" + s.name.text + "'";
    if (!first_of_its_name(model_.shapes, s.name, "shape")) return;
    Shape shape;
    shape.name = s.name.text;
    shape.where = span(s.name);
    bool ok = true;
    // A position-like expression (`which` of the shape, of `unit` when units are checked):
    // of t, coordinates, parameters and inputs, never of a velocity.
    auto of_q = [&](const grammar::ast::Expression& e, const std::string& which, const units::Dim& unit) -> Expr {
        auto v = expression(e);
        if (!v) {
            ok = false;
            return Expr{};
        }
        if (units_)
            if (auto d = units_->of(e)) units_->expect(e, *d, unit, "the " + which + " of " + what);
        for (Expr x : cas::free_variables(*v))
            if (x.kind() == cas::Kind::TimeDerivative) {
                error(span(e), "the " + which + " of " + what + " depends on the velocity " + cas::to_string(x) +
                                   ": a shape's position may depend on t, coordinates, parameters and inputs");
                ok = false;
                break;
            }
        return *v;
    };
    auto point = [&](const grammar::ast::Point& p, const char* which) {
        for (const grammar::ast::Expression* e : {&p.x, &p.y, &p.z}) shape.points.push_back(of_q(*e, which, units::metres()));
    };
    // `e` at the parameters' defaults (NaN when it cannot be evaluated), and its exact form there.
    auto at_defaults = [&](Expr e, Expr& exact) {
        exact = e;
        try {
            exact = cas::subs(e, parameter_values());
            return cas::evaluate(exact, {});
        } catch (const cas::Error&) {
            return std::nan("");
        }
    };
    // A radius or half extent (`noun`): a constant, positive, finite length.
    auto length = [&](const grammar::ast::Expression& e, const std::string& noun, const char* kind) -> Expr {
        auto r = expression(e);
        if (!r) {
            ok = false;
            return Expr{};
        }
        if (units_)
            if (auto d = units_->of(e)) units_->expect(e, *d, units::metres(), "the " + noun + " of " + what);
        if (!constant(*r, e, "the " + noun + " of " + what, true)) {
            ok = false;
            return *r;
        }
        Expr exact;
        const double value = at_defaults(*r, exact);
        if (!(value > 0) || !std::isfinite(value)) {
            error(span(e), "the " + noun + " of " + what + " is " + cas::to_string(*r) +
                               (exact == *r ? "" : " = " + cas::to_string(exact) + " at the parameters' defaults") + ": a " +
                               kind + " must be a positive finite length");
            ok = false;
        }
        return *r;
    };
    auto radius = [&](const grammar::ast::Expression& e) { shape.radius = length(e, "radius", "radius"); };
    if (const auto* sphere = boost::get<grammar::ast::Sphere>(&s.geometry)) {
        shape.kind = Shape::Kind::Sphere;
        radius(sphere->radius);
        point(sphere->centre, "centre");
    } else if (const auto* capsule = boost::get<grammar::ast::Capsule>(&s.geometry)) {
        shape.kind = Shape::Kind::Capsule;
        radius(capsule->radius);
        point(capsule->from, "first end");
        point(capsule->to, "second end");
    } else if (const auto* box = boost::get<grammar::ast::Box>(&s.geometry)) {
        shape.kind = Shape::Kind::Box;
        const char* axes[3] = {"x", "y", "z"};
        const grammar::ast::Expression* h[3] = {&box->half_extents.x, &box->half_extents.y, &box->half_extents.z};
        for (int d = 0; d < 3; ++d)
            shape.half_extents.push_back(length(*h[d], std::string("half extent along ") + axes[d], "half extent"));
        point(box->centre, "centre");
        for (std::size_t k = 0; k < box->rotations.size(); ++k) {
            const grammar::ast::Rotation& r = box->rotations[k];
            const std::string which = box->rotations.size() == 1 ? std::string("rotation") : "rotation " + std::to_string(k + 1);
            ShapeTurn turn;
            turn.angle = of_q(r.angle, "angle of the " + which, units::Dim{});
            // The axis: constant (a turning axis would add its own turn to ω) and not zero.
            const grammar::ast::Expression* a[3] = {&r.axis.x, &r.axis.y, &r.axis.z};
            bool constant_axis = true;
            for (int d = 0; d < 3; ++d) {
                auto v = expression(*a[d]);
                if (!v || !constant(*v, *a[d], "the axis of the " + which + " of " + what, true)) {
                    constant_axis = false;
                    continue;
                }
                turn.axis[static_cast<std::size_t>(d)] = *v;
            }
            if (!constant_axis) {
                ok = false;
                continue;
            }
            Expr exact;
            const Expr norm2 = turn.axis[0] * turn.axis[0] + turn.axis[1] * turn.axis[1] + turn.axis[2] * turn.axis[2];
            const double n2 = at_defaults(norm2, exact);
            if (!(n2 > 0) || !std::isfinite(n2)) {
                error(span(r.axis), "the axis of the " + which + " of " + what + " is (" + cas::to_string(turn.axis[0]) + ", " +
                                        cas::to_string(turn.axis[1]) + ", " + cas::to_string(turn.axis[2]) +
                                        ")" + (exact == norm2 ? "" : " (of squared length " + cas::to_string(exact) + " at the parameters' defaults)") +
                                        ": an axis must have a positive finite length");
                ok = false;
            }
            shape.turns.push_back(std::move(turn));
        }
    } else {
        const auto& segment = boost::get<grammar::ast::Segment>(s.geometry);
        shape.kind = Shape::Kind::Segment;
        point(segment.from, "first end");
        point(segment.to, "second end");
    }
    if (ok) model_.shapes.push_back(std::move(shape));
}

} // namespace phynjo::codegen::detail
