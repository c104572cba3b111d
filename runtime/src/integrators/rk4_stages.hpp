// The classical RK4 step as five rules over stage fields of the world (internal): shared by
// rk4 (NState: y = (q, p)) and lagrangian_rk4 (generalized coordinates: y = (q, q')).
//   save: y0 ← y, acc ← 0;
//   stage i (c_i, w_i): k = f(t + c_i dt, y); acc += w_i k; y ← y0 + next_i dt k (the last
//   stage: y ← y0 + dt acc).
#pragma once
#include "phynjo/runtime/core/workflow.hpp"

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace phynjo::runtime::detail {

/// Where a step keeps y = (a, b) and its stage storage (y0 and the accumulator).
struct Rk4Fields {
    FieldId a, b, a0, b0, acc_a, acc_b;
};

/// f(t, world) → (k_a, k_b) for every component of `bodies` (spans indexed by component).
using Rk4Derivative = std::function<void(double t, const World& w, std::span<double> ka, std::span<double> kb)>;

inline NumericWorkflow rk4_workflow(const Rk4Fields& f, const ComponentSet& bodies, const Domain& reads,
                                    Rk4Derivative derivative, const std::shared_ptr<const Layout>& layout) {
    const Domain state = Domain(f.a, bodies) | Domain(f.b, bodies);
    const Domain storage = Domain(f.a0, bodies) | Domain(f.b0, bodies) | Domain(f.acc_a, bodies) | Domain(f.acc_b, bodies);
    const std::vector<Index> idx(bodies.indices().begin(), bodies.indices().end());
    NumericRule save{"rk4_save", storage, state, nullptr, layout};
    save.step = [f, idx](double, World& w) {
        for (Index i : idx) {
            w.at(f.a0, i) = w.at(f.a, i);
            w.at(f.b0, i) = w.at(f.b, i);
            w.at(f.acc_a, i) = w.at(f.acc_b, i) = 0;
        }
    };
    auto stage = [&](const char* name, double c, double weight, double next, bool last) {
        NumericRule r{name, state | storage, reads, nullptr, layout};
        r.step = [=](double dt, World& w) {
            thread_local std::vector<double> ka, kb;
            ka.assign(w.size(), 0.0);
            kb.assign(w.size(), 0.0);
            derivative(w.time + c * dt, w, ka, kb);
            for (Index i : idx) {
                w.at(f.acc_a, i) += weight * ka[i];
                w.at(f.acc_b, i) += weight * kb[i];
                if (last) {
                    w.at(f.a, i) = w.at(f.a0, i) + dt * w.at(f.acc_a, i);
                    w.at(f.b, i) = w.at(f.b0, i) + dt * w.at(f.acc_b, i);
                } else {
                    w.at(f.a, i) = w.at(f.a0, i) + next * dt * ka[i];
                    w.at(f.b, i) = w.at(f.b0, i) + next * dt * kb[i];
                }
            }
        };
        return NumericWorkflow::run(r);
    };
    return NumericWorkflow::seq(std::vector<NumericWorkflow>{
        NumericWorkflow::run(save), stage("rk4_k1", 0.0, 1.0 / 6, 0.5, false), stage("rk4_k2", 0.5, 2.0 / 6, 0.5, false),
        stage("rk4_k3", 0.5, 2.0 / 6, 1.0, false), stage("rk4_k4", 1.0, 1.0 / 6, 0, true)});
}

} // namespace phynjo::runtime::detail
