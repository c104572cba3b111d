// Symplectic Euler (kick first):  p ← p + dt·F(q);  q ← q + dt·p/m.
// Order 1; symplectic: it is the exact flow of a modified Hamiltonian H + O(dt), so the
// energy error stays bounded instead of drifting.
// Reference: E. Hairer, C. Lubich, G. Wanner, Geometric Numerical Integration, 2nd ed.,
// Springer 2006, §I.1.2.
#include "phynjo/runtime/integrators/symplectic_euler.hpp"

namespace phynjo::runtime {

NumericWorkflow symplectic_euler(const Splitting& s) {
    return NumericWorkflow::seq(NumericWorkflow::run(s.kick(1.0)), NumericWorkflow::run(s.drift(1.0)));
}

} // namespace phynjo::runtime
