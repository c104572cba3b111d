// The rigid-body Strang splitting:
//   drift_trans(½) · drift_rot(½) · kick_force3d(1) · drift_rot(½) · drift_trans(½)
// One force evaluation per step. Order 2 and symmetric with the exponential rotation update
// and the implicit-midpoint gyroscopic kick (first order with the explicit options).
// Reference: G. Strang, SIAM J. Numer. Anal. 5, 506 (1968); for the free rigid body,
// Hairer, Lubich, Wanner, Geometric Numerical Integration, §VII.5.
#include "phynjo/runtime/integrators/rigid_leapfrog.hpp"

namespace phynjo::runtime {

NumericWorkflow rigid_leapfrog(const Force3D& force, const ComponentSet& bodies,
                               const std::shared_ptr<const Layout>& layout, GyroscopicScheme scheme) {
    using W = NumericWorkflow;
    return W::seq(W::run(drift_trans(bodies, 0.5, layout)), W::run(drift_rot(bodies, 0.5, layout)),
                  W::run(kick_force3d(force, bodies, 1.0, layout, scheme)), W::run(drift_rot(bodies, 0.5, layout)),
                  W::run(drift_trans(bodies, 0.5, layout)));
}

} // namespace phynjo::runtime
