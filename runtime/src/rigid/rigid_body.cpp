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
}

} // namespace phynjo::runtime
