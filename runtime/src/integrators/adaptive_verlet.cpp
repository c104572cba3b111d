// Adaptive velocity Verlet for N-body gravity (see adaptive_verlet.hpp for the step criterion).
//   p ← p + dt/2·F(q);  q ← q + dt·p/m;  F ← F(q);  p ← p + dt/2·F(q)
// with dt chosen before each step from the accelerations of its start. Order 2; symplectic
// only at fixed dt. Reference: L. Verlet, Phys. Rev. 159, 98 (1967).
#include "phynjo/runtime/integrators/adaptive_verlet.hpp"

#include <algorithm>
#include <cmath>

namespace phynjo::runtime {

AdaptiveVerlet::AdaptiveVerlet(const NBodyGravity& g, std::shared_ptr<const Layout> layout, Options options,
                               Executor* executor)
    : g_(g), options_(options), accelerations_(nbody_accelerations(g, layout, options.partitions).process(), executor),
      kick_(NumericWorkflow::run(kick3d(0.5, layout)).process()),
      drift_(NumericWorkflow::run(drift3d(1.0, layout)).process()) {}

void AdaptiveVerlet::prepare(World& w) {
    const double t = w.time;
    accelerations_.step(w, 0.0);
    w.time = t;
}

double AdaptiveVerlet::choose_dt(const World& w) const {
    double dt = options_.dt_max;
    for (Index i = 0; i < w.size(); ++i) {
        const double a = std::sqrt(w.at(kAX, i) * w.at(kAX, i) + w.at(kAY, i) * w.at(kAY, i) + w.at(kAZ, i) * w.at(kAZ, i));
        if (a == 0) continue;
        const double v = std::sqrt(w.at(kVX, i) * w.at(kVX, i) + w.at(kVY, i) * w.at(kVY, i) + w.at(kVZ, i) * w.at(kVZ, i));
        dt = std::min(dt, options_.eta * (v + std::sqrt(g_.softening * a)) / a);
    }
    return std::clamp(dt, options_.dt_min, options_.dt_max);
}

double AdaptiveVerlet::step(World& w) {
    const double dt = choose_dt(w);
    const double t = w.time;
    kick_.step(w, dt);
    drift_.step(w, dt);
    accelerations_.step(w, dt);
    kick_.step(w, dt);
    w.time = t + dt;
    return dt;
}

} // namespace phynjo::runtime
