#include "phynjo/runtime/rigid/rigid_world.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace phynjo::runtime {

namespace {

std::string quoted(std::string_view label) { return "'" + std::string(label) + "'"; }

void check_unit(const Quaternion& q, std::string_view label) {
    const double n = q.norm();
    if (!std::isfinite(n) || std::abs(n - 1) > 1e-6) {
        std::ostringstream os;
        os.precision(17);
        os << "orientation of " << quoted(label) << " is not a unit quaternion: |q| = " << n
           << " (q = (" << q.w << ", " << q.x << ", " << q.y << ", " << q.z << "); allowed |q| - 1 within 1e-6)";
        throw InvalidBody(os.str());
    }
}

} // namespace

World make_rigid_world(const Registry& components, const std::vector<RigidBody>& bodies,
                       const std::vector<RigidInit>& init, const std::vector<std::string>& extra_fields) {
    std::vector<std::string> fields(kRigidFields.begin(), kRigidFields.end());
    const bool shaped =
        std::any_of(bodies.begin(), bodies.end(), [](const RigidBody& b) { return b.shape != Shape::sphere; });
    if (shaped) fields.insert(fields.end(), kShapeFields.begin(), kShapeFields.end());
    fields.insert(fields.end(), extra_fields.begin(), extra_fields.end());
    if (bodies.size() != components.size())
        throw std::invalid_argument("make_rigid_world: " + std::to_string(bodies.size()) + " bodies for " +
                                    std::to_string(components.size()) + " components");
    if (!init.empty() && init.size() != components.size())
        throw std::invalid_argument("make_rigid_world: " + std::to_string(init.size()) + " initial states for " +
                                    std::to_string(components.size()) + " components");
    World w(std::make_shared<Layout>(components, std::move(fields)));
    for (Index i = 0; i < w.size(); ++i) {
        const RigidBody& b = bodies[i];
        const std::string& label = components.label(i);
        b.validate(label);
        const Eigen::Matrix3d inv = b.inertia.inverse();
        w.at(kMass, i) = b.mass;
        w.at(kInvMass, i) = 1 / b.mass;
        w.at(kIxx, i) = b.inertia(0, 0);
        w.at(kIyy, i) = b.inertia(1, 1);
        w.at(kIzz, i) = b.inertia(2, 2);
        w.at(kIxy, i) = b.inertia(0, 1);
        w.at(kIxz, i) = b.inertia(0, 2);
        w.at(kIyz, i) = b.inertia(1, 2);
        w.at(kInvIxx, i) = inv(0, 0);
        w.at(kInvIyy, i) = inv(1, 1);
        w.at(kInvIzz, i) = inv(2, 2);
        w.at(kInvIxy, i) = 0.5 * (inv(0, 1) + inv(1, 0));
        w.at(kInvIxz, i) = 0.5 * (inv(0, 2) + inv(2, 0));
        w.at(kInvIyz, i) = 0.5 * (inv(1, 2) + inv(2, 1));
        w.at(kRadius, i) = b.radius;
        if (shaped) {
            const auto f = static_cast<FieldId>(kRigidFieldCount);
            w.at(f, i) = static_cast<double>(b.shape);
            for (int k = 0; k < 3; ++k) w.at(f + 1 + k, i) = b.half_extents(k);
        }
        const RigidInit s = init.empty() ? RigidInit{} : init[i];
        if (!s.position.allFinite() || !s.velocity.allFinite() || !s.angular_velocity.allFinite())
            throw InvalidBody("initial state of '" + label + "' is not finite");
        check_unit(s.orientation, label);
        set_position(w, i, s.position);
        set_velocity(w, i, s.velocity);
        set_angular_velocity(w, i, s.angular_velocity);
        set_orientation(w, i, s.orientation);
    }
    return w;
}

int shape_field(const Layout& layout) {
    const std::size_t f = kRigidFieldCount;
    if (layout.fields.size() < f + kShapeFields.size()) return -1;
    for (std::size_t k = 0; k < kShapeFields.size(); ++k)
        if (layout.fields[f + k] != kShapeFields[k]) return -1;
    return static_cast<int>(f);
}

Shape shape_of(const World& w, Index c) {
    const int f = shape_field(w.layout());
    return f < 0 ? Shape::sphere : static_cast<Shape>(static_cast<int>(w.at(static_cast<FieldId>(f), c)));
}

Eigen::Vector3d half_extents(const World& w, Index c) {
    const int f = shape_field(w.layout());
    if (f < 0) return Eigen::Vector3d::Zero();
    const auto h = static_cast<FieldId>(f + 1);
    return {w.at(h, c), w.at(h + 1, c), w.at(h + 2, c)};
}

ComponentSet all_bodies(const World& w) { return ComponentSet::range(0, static_cast<Index>(w.size())); }

Eigen::Vector3d position(const World& w, Index c) { return {w.at(kX, c), w.at(kY, c), w.at(kZ, c)}; }
Eigen::Vector3d velocity(const World& w, Index c) { return {w.at(kVX, c), w.at(kVY, c), w.at(kVZ, c)}; }
Eigen::Vector3d angular_velocity(const World& w, Index c) { return {w.at(kWX, c), w.at(kWY, c), w.at(kWZ, c)}; }
Quaternion orientation(const World& w, Index c) { return {w.at(kQW, c), w.at(kQX, c), w.at(kQY, c), w.at(kQZ, c)}; }

void set_position(World& w, Index c, const Eigen::Vector3d& r) {
    w.at(kX, c) = r.x();
    w.at(kY, c) = r.y();
    w.at(kZ, c) = r.z();
}
void set_velocity(World& w, Index c, const Eigen::Vector3d& v) {
    w.at(kVX, c) = v.x();
    w.at(kVY, c) = v.y();
    w.at(kVZ, c) = v.z();
}
void set_angular_velocity(World& w, Index c, const Eigen::Vector3d& om) {
    w.at(kWX, c) = om.x();
    w.at(kWY, c) = om.y();
    w.at(kWZ, c) = om.z();
}
void set_orientation(World& w, Index c, const Quaternion& q) {
    check_unit(q, w.layout().components.label(c));
    const Quaternion u = q.normalized();
    w.at(kQW, c) = u.w;
    w.at(kQX, c) = u.x;
    w.at(kQY, c) = u.y;
    w.at(kQZ, c) = u.z;
}

namespace {
/// The symmetric matrix stored as six fields, from the xx field on: xx, yy, zz, xy, xz, yz.
Eigen::Matrix3d symmetric(const World& w, Index c, FieldId xx) {
    const double a = w.at(xx, c), b = w.at(xx + 1, c), d = w.at(xx + 2, c);
    const double xy = w.at(xx + 3, c), xz = w.at(xx + 4, c), yz = w.at(xx + 5, c);
    Eigen::Matrix3d m;
    m << a, xy, xz, xy, b, yz, xz, yz, d;
    return m;
}
} // namespace

Eigen::Matrix3d body_inertia(const World& w, Index c) { return symmetric(w, c, kIxx); }
Eigen::Matrix3d body_inverse_inertia(const World& w, Index c) { return symmetric(w, c, kInvIxx); }
Eigen::Matrix3d world_inertia(const World& w, Index c) {
    const Eigen::Matrix3d r = orientation(w, c).to_matrix();
    return r * body_inertia(w, c) * r.transpose();
}
Eigen::Vector3d spin_angular_momentum(const World& w, Index c) { return world_inertia(w, c) * angular_velocity(w, c); }

Eigen::Vector3d total_angular_momentum(const World& w) {
    Eigen::Vector3d l = Eigen::Vector3d::Zero();
    for (Index i = 0; i < w.size(); ++i)
        l += w.at(kMass, i) * position(w, i).cross(velocity(w, i)) + spin_angular_momentum(w, i);
    return l;
}
Eigen::Vector3d total_linear_momentum(const World& w) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (Index i = 0; i < w.size(); ++i) p += w.at(kMass, i) * velocity(w, i);
    return p;
}
double rotational_energy(const World& w, Index c) {
    const Eigen::Vector3d ob = orientation(w, c).rotate_inverse(angular_velocity(w, c));
    return 0.5 * ob.dot(body_inertia(w, c) * ob);
}
double rigid_kinetic_energy(const World& w) {
    double e = 0;
    for (Index i = 0; i < w.size(); ++i) e += 0.5 * w.at(kMass, i) * velocity(w, i).squaredNorm() + rotational_energy(w, i);
    return e;
}

State3D rigid_state3d(const World& w) {
    return State3D{w.field(kX),  w.field(kY),  w.field(kZ),  w.field(kVX), w.field(kVY), w.field(kVZ),
                   w.field(kMass), w.field(kWX), w.field(kWY), w.field(kWZ), w.field(kQW), w.field(kQX),
                   w.field(kQY), w.field(kQZ)};
}

} // namespace phynjo::runtime
