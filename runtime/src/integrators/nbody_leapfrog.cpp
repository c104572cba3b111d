// Leapfrog for N-body gravity, drift-kick-drift:
//   r ← r + dt/2·v;  a ← a(r);  v ← v + dt·a;  r ← r + dt/2·v
// One force evaluation per step. Order 2; symplectic and time-reversible.
// Reference: L. Verlet, Phys. Rev. 159, 98 (1967).
#include "phynjo/runtime/integrators/nbody_leapfrog.hpp"

namespace phynjo::runtime {

NumericWorkflow nbody_leapfrog(const NBodyGravity& g, const std::shared_ptr<const Layout>& layout, int partitions) {
    using W = NumericWorkflow;
    return W::seq(W::run(drift3d(0.5, layout)), nbody_accelerations(g, layout, partitions), W::run(kick3d(1.0, layout)),
                  W::run(drift3d(0.5, layout)));
}

} // namespace phynjo::runtime
