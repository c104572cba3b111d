// The rules of a rigid world: the runes (Physics.RigidBodyUtilities.Rigid3DNR)
// on flat state.
#include "phynjo/runtime/rigid/rigid_rules.hpp"

#include "phynjo/runtime/core/errors.hpp"

#include <cmath>
#include <string>

namespace phynjo::runtime {

namespace {

std::string num(double c) {
    std::string s = std::to_string(c);
    while (s.size() > 1 && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
    return s;
}

Domain state_domain(const Layout& layout) {
    const ComponentSet all = ComponentSet::range(0, static_cast<Index>(layout.components.size()));
    return Domain::of(layout, {"x", "y", "z", "vx", "vy", "vz", "m", "wx", "wy", "wz", "qw", "qx", "qy", "qz"}, all);
}

} // namespace

NumericRule drift_trans(const ComponentSet& bodies, double c, const std::shared_ptr<const Layout>& layout) {
    NumericRule r{"drift_trans(" + num(c) + ")", Domain::of(*layout, {"x", "y", "z"}, bodies),
                  Domain::of(*layout, {"vx", "vy", "vz"}, bodies), nullptr, layout};
    r.step = [c, idx = std::vector<Index>(bodies.indices().begin(), bodies.indices().end())](double dt, World& w) {
        const double h = c * dt;
        for (int k = 0; k < 3; ++k) {
            double* x = w.field(static_cast<FieldId>(kX + k)).data();
            const double* v = w.field(static_cast<FieldId>(kVX + k)).data();
            for (Index i : idx) x[i] += h * v[i];
        }
    };
    return r;
}

NumericRule drift_rot(const ComponentSet& bodies, double c, const std::shared_ptr<const Layout>& layout,
                      RotationUpdate update) {
    NumericRule r{"drift_rot(" + num(c) + ")", Domain::of(*layout, {"qw", "qx", "qy", "qz"}, bodies),
                  Domain::of(*layout, {"wx", "wy", "wz"}, bodies), nullptr, layout};
    r.step = [c, update, idx = std::vector<Index>(bodies.indices().begin(), bodies.indices().end())](double dt,
                                                                                                    World& w) {
        const double h = c * dt;
        for (Index i : idx) {
            const Quaternion q = orientation(w, i);
            const Eigen::Vector3d om = angular_velocity(w, i);
            // With ω_W fixed, ω_B = R(Q)ᵀ ω_W is invariant under a rotation about ω_W, so the
            // first-order form may take ω_B from the start of the step.
            const Quaternion n = update == RotationUpdate::exponential ? integrate_exponential(q, om, h)
                                                                      : integrate_first_order(q, q.rotate_inverse(om), h);
            w.at(kQW, i) = n.w;
            w.at(kQX, i) = n.x;
            w.at(kQY, i) = n.y;
            w.at(kQZ, i) = n.z;
        }
    };
    return r;
}

NumericRule kick_force3d(const Force3D& force, const ComponentSet& bodies, double c,
                         const std::shared_ptr<const Layout>& layout, GyroscopicScheme scheme) {
    NumericRule r{"kick_force3d(" + num(c) + ")", Domain::of(*layout, {"vx", "vy", "vz", "wx", "wy", "wz"}, bodies),
                  state_domain(*layout), nullptr, layout};
    r.step = [force, c, scheme, layout,
              idx = std::vector<Index>(bodies.indices().begin(), bodies.indices().end())](double dt, World& w) {
        thread_local std::vector<double> ft; // F and τ of every body, from the state at the start
        ft.resize(6 * idx.size());
        {
            const State3D s = rigid_state3d(w);
            for (std::size_t k = 0; k < idx.size(); ++k) {
                const auto [f, t] = force(s, idx[k]);
                for (int a = 0; a < 3; ++a) {
                    ft[6 * k + a] = f[a];
                    ft[6 * k + 3 + a] = t[a];
                }
            }
        }
        const double h = c * dt;
        for (std::size_t k = 0; k < idx.size(); ++k) {
            const Index i = idx[k];
            const double im = w.at(kInvMass, i);
            w.at(kVX, i) += h * im * ft[6 * k];
            w.at(kVY, i) += h * im * ft[6 * k + 1];
            w.at(kVZ, i) += h * im * ft[6 * k + 2];

            // No torque on a body with I = c𝟙 (a sphere, a cube): ω × Iω = 0, so ω stays —
            // exactly, not through the rotation to the body frame and back.
            const double* tw = &ft[6 * k + 3];
            if (tw[0] == 0 && tw[1] == 0 && tw[2] == 0 && w.at(kIxx, i) == w.at(kIyy, i) && w.at(kIxx, i) == w.at(kIzz, i) &&
                w.at(kIxy, i) == 0 && w.at(kIxz, i) == 0 && w.at(kIyz, i) == 0)
                continue;
            const Quaternion q = orientation(w, i);
            const Eigen::Matrix3d I = body_inertia(w, i), Iinv = body_inverse_inertia(w, i);
            const Eigen::Vector3d tb = q.rotate_inverse(Eigen::Vector3d(ft[6 * k + 3], ft[6 * k + 4], ft[6 * k + 5]));
            const Eigen::Vector3d w0 = q.rotate_inverse(angular_velocity(w, i));
            Eigen::Vector3d w1;
            if (scheme == GyroscopicScheme::explicit_euler) {
                w1 = w0 + h * Iinv * (tb - w0.cross(I * w0));
            } else {
                // Fixed point of ω' = ω + h I⁻¹(τ − ω̄ × I ω̄), ω̄ = (ω + ω')/2. The map contracts
                // with factor ~ h|ω|·(anisotropy of I), so a few iterations reach round-off at
                // the steps any integrator of this order would take.
                w1 = w0 + h * Iinv * (tb - w0.cross(I * w0));
                bool converged = false;
                for (int it = 0; it < 100 && !converged; ++it) {
                    const Eigen::Vector3d mid = 0.5 * (w0 + w1);
                    const Eigen::Vector3d next = w0 + h * Iinv * (tb - mid.cross(I * mid));
                    const double change = (next - w1).cwiseAbs().maxCoeff();
                    w1 = next;
                    converged = change <= 4e-16 * (1 + w1.cwiseAbs().maxCoeff());
                }
                if (!converged) {
                    // Round-off may keep the last bit flickering; accept a change at that level.
                    const Eigen::Vector3d mid = 0.5 * (w0 + w1);
                    const Eigen::Vector3d next = w0 + h * Iinv * (tb - mid.cross(I * mid));
                    if (!((next - w1).cwiseAbs().maxCoeff() <= 1e-13 * (1 + w1.cwiseAbs().maxCoeff())))
                        throw ConvergenceError("kick_force3d: the implicit midpoint step of Euler's equations for '" +
                                               layout->components.label(i) + "' did not converge (h|omega| = " +
                                               std::to_string(h * w0.norm()) + "; take a smaller step)");
                }
            }
            set_angular_velocity(w, i, q.rotate(w1));
        }
    };
    return r;
}

} // namespace phynjo::runtime
