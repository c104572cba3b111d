// Leapfrog / Störmer–Verlet, the symmetric composition of the two symplectic Euler maps.
//   DKD: q ← q + dt/2·p/m;  p ← p + dt·F(q);  q ← q + dt/2·p/m
//   KDK: p ← p + dt/2·F(q); q ← q + dt·p/m;   p ← p + dt/2·F(q)   (velocity Verlet)
// Order 2; symplectic and time-reversible.
// Reference: L. Verlet, Phys. Rev. 159, 98 (1967); Hairer, Lubich, Wanner, Acta Numerica
// 12, 399 (2003).
#include "phynjo/runtime/integrators/leapfrog.hpp"

namespace phynjo::runtime {

NumericWorkflow leapfrog_dkd(const Splitting& s) {
    using W = NumericWorkflow;
    return W::seq(W::run(s.drift(0.5)), W::run(s.kick(1.0)), W::run(s.drift(0.5)));
}

NumericWorkflow leapfrog_kdk(const Splitting& s) {
    using W = NumericWorkflow;
    return W::seq(W::run(s.kick(0.5)), W::run(s.drift(1.0)), W::run(s.kick(0.5)));
}

} // namespace phynjo::runtime
