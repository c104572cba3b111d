// The shape statement: spheres, segments and capsules, their points and radii. (analyzer.hpp)
#include "analyzer.hpp"

namespace phynjo::codegen::detail {

void Analyzer::visit(const grammar::ast::ShapeStmt& s) {
    const std::string what = "shape '" + s.name.text + "'";
    if (!first_of_its_name(model_.shapes, s.name, "shape")) return;
    Shape shape{s.name.text, Shape::Kind::Sphere, Expr{}, {}, span(s.name)};
    bool ok = true;
    auto point = [&](const grammar::ast::Point& p, const char* which) {
        for (const grammar::ast::Expression* e : {&p.x, &p.y, &p.z}) {
            auto v = expression(*e);
            if (!v) {
                ok = false;
                continue;
            }
            if (units_)
                if (auto d = units_->of(*e)) units_->expect(*e, *d, units::metres(), std::string("the ") + which + " of " + what);
            for (Expr x : cas::free_variables(*v))
                if (x.kind() == cas::Kind::TimeDerivative) {
                    error(span(*e), std::string("the ") + which + " of " + what + " depends on the velocity " + cas::to_string(x) +
                                        ": a shape's position may depend on t, coordinates, parameters and inputs");
                    ok = false;
                    break;
                }
            shape.points.push_back(*v);
        }
    };
    // A radius: a constant, positive, finite length.
    auto radius = [&](const grammar::ast::Expression& e) {
        auto r = expression(e);
        if (!r) {
            ok = false;
            return;
        }
        if (units_)
            if (auto d = units_->of(e)) units_->expect(e, *d, units::metres(), "the radius of " + what);
        if (!constant(*r, e, "the radius of " + what, true)) {
            ok = false;
            return;
        }
        double value = 0;
        Expr exact = *r;
        try {
            exact = cas::subs(*r, parameter_values());
            value = cas::evaluate(exact, {});
        } catch (const cas::Error&) {
            value = std::nan("");
        }
        if (!(value > 0) || !std::isfinite(value)) {
            error(span(e), "the radius of " + what + " is " + cas::to_string(*r) +
                               (exact == *r ? "" : " = " + cas::to_string(exact) + " at the parameters' defaults") +
                               ": a radius must be a positive finite length");
            ok = false;
        }
        shape.radius = *r;
    };
    if (const auto* sphere = boost::get<grammar::ast::Sphere>(&s.geometry)) {
        shape.kind = Shape::Kind::Sphere;
        radius(sphere->radius);
        point(sphere->centre, "centre");
    } else if (const auto* capsule = boost::get<grammar::ast::Capsule>(&s.geometry)) {
        shape.kind = Shape::Kind::Capsule;
        radius(capsule->radius);
        point(capsule->from, "first end");
        point(capsule->to, "second end");
    } else {
        const auto& segment = boost::get<grammar::ast::Segment>(s.geometry);
        shape.kind = Shape::Kind::Segment;
        point(segment.from, "first end");
        point(segment.to, "second end");
    }
    if (ok) model_.shapes.push_back(std::move(shape));
}

} // namespace phynjo::codegen::detail
