#include "phynjo/runtime/rigid/rigid_body.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <cmath>
#include <sstream>
#include <string>

namespace phynjo::runtime {

namespace {
std::string quoted(std::string_view label) { return "'" + std::string(label) + "'"; }
} // namespace

RigidBody RigidBody::solid_sphere(double mass, double radius) {
    RigidBody b;
    b.mass = mass;
    b.radius = radius;
    b.inertia = Eigen::Matrix3d::Identity() * (0.4 * mass * radius * radius);
    return b;
}

RigidBody RigidBody::box(double mass, const Eigen::Vector3d& h) {
    RigidBody b;
    b.mass = mass;
    b.inertia = Eigen::Vector3d(h.y() * h.y() + h.z() * h.z(), h.x() * h.x() + h.z() * h.z(),
                                h.x() * h.x() + h.y() * h.y())
                    .asDiagonal();
    b.inertia *= mass / 3;
    return b;
}

RigidBody RigidBody::solid_box(double mass, const Eigen::Vector3d& half_extents) {
    RigidBody b = box(mass, half_extents);
    b.shape = Shape::box;
    b.half_extents = half_extents;
    return b;
}

RigidBody RigidBody::solid_capsule(double mass, double radius, double half_length) {
    constexpr double pi = 3.141592653589793;
    const double r = radius, l = half_length;
    const double cylinder = pi * r * r * 2 * l, ball = 4.0 / 3.0 * pi * r * r * r;
    const double mc = mass * cylinder / (cylinder + ball), ms = mass - mc;
    const double axial = mc * r * r / 2 + 0.4 * ms * r * r;
    const double across = mc * (l * l / 3 + r * r / 4) + ms * (0.4 * r * r + l * l + 0.75 * l * r);
    RigidBody b;
    b.mass = mass;
    b.radius = radius;
    b.shape = Shape::capsule;
    b.half_extents = Eigen::Vector3d(0, half_length, 0);
    b.inertia = Eigen::Vector3d(across, axial, across).asDiagonal();
    return b;
}

void RigidBody::validate(std::string_view label) const {
    if (!(mass > 0) || !std::isfinite(mass)) {
        std::ostringstream os;
        os << "mass of " << quoted(label) << " must be positive and finite, got " << mass;
        throw InvalidBody(os.str());
    }
    if (!inertia.allFinite()) throw InvalidBody("inertia tensor of " + quoted(label) + " is not finite");
    const double scale = inertia.cwiseAbs().maxCoeff();
    if ((inertia - inertia.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale)
        throw InvalidBody("inertia tensor of " + quoted(label) + " is not symmetric");
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inertia, Eigen::EigenvaluesOnly);
    const Eigen::Vector3d l = es.eigenvalues(); // ascending
    if (!(l(0) > 1e-12 * scale) || !(scale > 0)) {
        std::ostringstream os;
        os << "inertia tensor of " << quoted(label) << " is not positive definite (principal moments " << l(0)
           << ", " << l(1) << ", " << l(2) << " kg m^2)";
        throw InvalidBody(os.str());
    }
    if (l(0) + l(1) < l(2) * (1 - 1e-9)) {
        std::ostringstream os;
        os << "inertia tensor of " << quoted(label) << " violates the triangle inequality I1 + I2 >= I3 (principal moments "
           << l(0) << ", " << l(1) << ", " << l(2) << " kg m^2): no mass distribution has it";
        throw InvalidBody(os.str());
    }
    if (!(radius >= 0) || !std::isfinite(radius)) {
        std::ostringstream os;
        os << "radius of " << quoted(label) << " must be non-negative and finite, got " << radius;
        throw InvalidBody(os.str());
    }
    switch (shape) {
    case Shape::sphere:
        if (!half_extents.isZero(0))
            throw InvalidBody("half-extents of " + quoted(label) + " are given, but its shape is a sphere");
        return;
    case Shape::box:
        if (!(half_extents.array() > 0).all() || !half_extents.allFinite()) {
            std::ostringstream os;
            os << "half-extents of box " << quoted(label) << " must be positive and finite, got (" << half_extents.x()
               << ", " << half_extents.y() << ", " << half_extents.z() << ") m";
            throw InvalidBody(os.str());
        }
        if (radius != 0) throw InvalidBody("box " + quoted(label) + " has a radius; a box has half-extents only");
        return;
    case Shape::capsule:
        if (!(radius > 0)) throw InvalidBody("radius of capsule " + quoted(label) + " must be positive");
        if (half_extents.x() != 0 || half_extents.z() != 0 || !(half_extents.y() >= 0) ||
            !std::isfinite(half_extents.y())) {
            std::ostringstream os;
            os << "capsule " << quoted(label) << " needs half-extents (0, L, 0) with L >= 0 finite (its half-length), got ("
               << half_extents.x() << ", " << half_extents.y() << ", " << half_extents.z() << ") m";
            throw InvalidBody(os.str());
        }
        return;
    }
    throw InvalidBody("shape of " + quoted(label) + " is not a sphere, box or capsule");
}

} // namespace phynjo::runtime
