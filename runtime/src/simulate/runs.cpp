// One run of an ensemble and many on one thread, in SIMD lanes where they can (runs.hpp).
#include "phynjo/runtime/simulate/runs.hpp"

#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/simulate/integrator_registry.hpp"
#include "phynjo/runtime/system/detail/lanes.hpp"

#include <algorithm>
#include <memory>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <optional>
#include <stdexcept>

#include "csv_text.hpp"
#include "strict_numbers.hpp"

namespace phynjo::runtime {

using detail::append_number;

namespace {

/// One kernel call a run asks for: rk4_step_values(t, h, t1, …) on the run's state.
struct KernelCall {
    double t, h, t1;
};

/// How a run's steps fall: `steps` whole steps of `dt`, then a last one of `last` when it
/// is not negligible (`total` steps in all).
struct StepPlan {
    long steps;
    double last;
    long total;
    double dt, t_end;
};

/// A run's bookkeeping, whichever path steps it (run_one's workflow paths, FastRun): the
/// first trajectory row, then after each whole step the state finite, the energy error
/// |E − E(0)| / max(1, |E(0)|) and a row every `every`-th step and at the last; at the end
/// the events' first times and a stop's reason.
class RunRecorder {
public:
    RunRecorder(const World& w, RunSummary& r, long every, bool event_log, std::string* trajectory,
                std::vector<double>* values = nullptr)
        : w_(w), r_(r), trajectory_(trajectory), values_(values), q_(w.field(kGQ).data()), v_(w.field(kGV).data()),
          dof_(w.field(kGQ).size()), every_(std::max(1L, every)), event_log_(event_log) {}
    /// At the initial state: E(0) = `e0`, the first row.
    void begin(double e0) {
        e0_ = e0;
        scale_ = std::max(1.0, std::abs(e0));
        if (trajectory_ || values_) row(e0);
    }
    /// After whole step `k` (the last one when `last_step`), E there = `e`.
    void operator()(long k, bool last_step, double e) {
        for (std::size_t i = 0; i < dof_; ++i)
            if (!std::isfinite(q_[i]) || !std::isfinite(v_[i])) throw Error("the state is not finite");
        r_.max_energy_error = std::max(r_.max_energy_error, std::abs(e - e0_) / scale_);
        if ((trajectory_ || values_) && (last_step || k % every_ == 0)) row(e);
    }
    /// The run is over without an error: the events' first times, a stop's reason.
    void complete(const LagrangianSystem& sys, const EventMonitor& monitor) {
        for (const EventRecord& e : monitor.log())
            if (std::isnan(r_.first_event[e.event])) r_.first_event[e.event] = e.time;
        if (event_log_) r_.events.assign(monitor.log().begin(), monitor.log().end());
        if (monitor.stopped() && !monitor.log().empty()) {
            r_.status = RunSummary::Status::stopped;
            r_.reason = "event " + sys.event_names[monitor.log().back().event];
        }
    }

private:
    void row(double e) {
        if (values_) {
            values_->push_back(w_.time);
            values_->insert(values_->end(), q_, q_ + dof_);
            values_->insert(values_->end(), v_, v_ + dof_);
            values_->push_back(e);
        }
        if (!trajectory_) return;
        std::string& out = *trajectory_;
        append_number(out, w_.time);
        for (std::size_t i = 0; i < dof_; ++i) out += ',', append_number(out, q_[i]);
        for (std::size_t i = 0; i < dof_; ++i) out += ',', append_number(out, v_[i]);
        out += ',', append_number(out, e);
        out += '\n';
    }
    const World& w_;
    RunSummary& r_;
    std::string* trajectory_;
    std::vector<double>* values_;
    const double* q_;
    const double* v_;
    std::size_t dof_;
    long every_;
    bool event_log_;
    double e0_ = 0, scale_ = 1;
};

/// run_one's path through generated code's fused kernels, one kernel call at a time: next()
/// says which call the run needs (or that it is over), done() takes its result — so that the
/// caller makes the calls, alone (run_one) or with other runs' in the lanes of one call
/// (run_many). The
/// state (q, q', the q'' at its start, E, the guards) is the run's own; the event monitor and
/// the RunRecorder (after each whole step) are run_one's. Exceptions leave next() and done()
/// where run_one's loop threw them.
class KernelRun {
public:
    KernelRun(const LagrangianSystem& sys, World& w, EventMonitor& monitor, StepPlan plan, RunRecorder& record)
        : sys_(sys), w_(w), monitor_(monitor), plan_(plan), record_(record), q_(w.field(kGQ)), v_(w.field(kGV)),
          a_(sys.dof), a0_(sys.dof), g_(sys.n_events), with_events_(sys.n_events > 0) {
        ok_ = sys.accelerations_energy_guards(w.time, q_, v_, a_, e_, g_); // false: accelerations throws there
    }
    /// The next call, or null when the run is over (finished or stopped).
    const KernelCall* next() {
        for (;;) switch (phase_) {
            case Phase::step:
                if (k_ > plan_.total) {
                    phase_ = Phase::over;
                    return nullptr;
                }
                target_ = k_ <= plan_.steps ? static_cast<double>(k_) * plan_.dt : plan_.t_end;
                h_ = k_ <= plan_.steps ? plan_.dt : plan_.last;
                if (!with_events_) {
                    if (!ok_) sys_.accelerations(w_.time + 0.0 * h_, q_, v_, a_);
                    call_ = {w_.time, h_, target_};
                    phase_ = Phase::plain_call;
                    return &call_;
                }
                monitor_.begin_run_step(h_);
                whole_ = true;
                phase_ = Phase::substep;
                continue;
            case Phase::substep: {
                if (!(w_.time < target_ - 1e-12 * h_)) { // the run step is complete
                    w_.time = target_;
                    record_(k_, k_ == plan_.total, e_);
                    ++k_;
                    phase_ = Phase::step;
                    continue;
                }
                monitor_.begin_step(w_);
                const double length = whole_ ? h_ : target_ - w_.time;
                if (!ok_) sys_.accelerations(w_.time + 0.0 * length, q_, v_, a_);
                std::copy(a_.begin(), a_.end(), a0_.begin());
                call_ = {w_.time, length, target_};
                phase_ = Phase::event_call;
                return &call_;
            }
            case Phase::plain_call:
            case Phase::event_call:
            case Phase::over: return nullptr;
            }
    }
    /// After the call next() asked for: `ok` what it returned.
    void done(bool ok) {
        ok_ = ok;
        w_.time = target_;
        if (phase_ == Phase::plain_call) {
            record_(k_, k_ == plan_.total, e_);
            ++k_;
            phase_ = Phase::step;
            return;
        }
        const EventStep es = monitor_.end_step(w_, g_, a0_, ok_ ? std::span<const double>(a_) : std::span<const double>());
        if (es.moved) ok_ = sys_.accelerations_energy_guards(w_.time, q_, v_, a_, e_, g_);
        if (es.stopped) {
            record_(k_, true, e_);
            phase_ = Phase::over;
            return;
        }
        whole_ = whole_ && !es.fired;
        phase_ = Phase::substep;
    }
    std::span<double> q() noexcept { return q_; }
    std::span<double> qdot() noexcept { return v_; }
    std::span<double> qddot() noexcept { return a_; }
    double& energy() noexcept { return e_; }
    std::span<double> guards() noexcept { return g_; }

private:
    enum class Phase { step, substep, plain_call, event_call, over };
    const LagrangianSystem& sys_;
    World& w_;
    EventMonitor& monitor_;
    StepPlan plan_;
    RunRecorder& record_;
    std::span<double> q_, v_;
    std::vector<double> a_, a0_, g_;
    double e_ = 0;
    bool ok_ = true, with_events_, whole_ = true;
    Phase phase_ = Phase::step;
    long k_ = 1;
    double target_ = 0, h_ = 0;
    KernelCall call_{};
};

/// A run through generated code's fused kernels (run_one's path for rk4 without constraints)
/// as an object: constructed at its initial state, then next() / done() per kernel call until
/// next() says it is over, then summary(). The same operations, checks and results as run_one
/// in the same order; exceptions become a `failed` summary. Not movable (the step machine
/// holds references into it).
class FastRun {
public:
    FastRun(const LagrangianSystem& sys, std::span<const std::pair<std::size_t, double>> q0,
            std::span<const std::pair<std::size_t, double>> v0, const RunSettings& settings, std::string* trajectory,
            std::vector<double>* values = nullptr)
        : sys_(sys), w_(make_lagrangian_world(sys)), record_(w_, r_, settings.every, settings.event_log, trajectory, values) {
        r_.first_event.assign(sys.n_events, std::numeric_limits<double>::quiet_NaN());
        for (const auto& [i, v] : q0) w_.at(kGQ, static_cast<Index>(i)) = v;
        for (const auto& [i, v] : v0) w_.at(kGV, static_cast<Index>(i)) = v;
        try {
            record_.begin(sys.energy(0, w_.field(kGQ), w_.field(kGV)));
            const long steps = detail::whole_steps(settings.t_end, settings.dt);
            const double last = settings.t_end - static_cast<double>(steps) * settings.dt;
            const long total = steps + (last > 1e-9 * settings.dt ? 1 : 0);
            monitor_.emplace(sys, settings.events);
            run_.emplace(sys, w_, *monitor_, StepPlan{steps, last, total, settings.dt, settings.t_end}, record_);
        } catch (const std::exception& e) {
            fail(e);
        }
    }
    FastRun(const FastRun&) = delete;
    FastRun& operator=(const FastRun&) = delete;

    /// The kernel call the run needs next, or null when it is over.
    const KernelCall* next() {
        if (over_) return nullptr;
        try {
            const KernelCall* c = run_->next();
            if (!c) {
                over_ = true;
                record_.complete(sys_, *monitor_);
            }
            return c;
        } catch (const std::exception& e) {
            fail(e);
            return nullptr;
        }
    }
    /// After the kernel wrote the call's results into q(), qdot(), qddot(), energy(), guards().
    void done(bool ok) {
        try {
            run_->done(ok);
        } catch (const std::exception& e) {
            fail(e);
        }
    }
    /// The kernel threw for this run (q() and qdot() as the kernel left them).
    void fail(const std::exception& e) {
        r_.status = RunSummary::Status::failed;
        r_.reason = e.what();
        over_ = true;
    }
    /// What the run ended with (after next() returned null).
    RunSummary summary() {
        r_.t = w_.time;
        r_.q.assign(w_.field(kGQ).begin(), w_.field(kGQ).end());
        r_.qdot.assign(w_.field(kGV).begin(), w_.field(kGV).end());
        return std::move(r_);
    }
    std::span<double> q() noexcept { return run_->q(); }
    std::span<double> qdot() noexcept { return run_->qdot(); }
    std::span<double> qddot() noexcept { return run_->qddot(); }
    double& energy() noexcept { return run_->energy(); }
    std::span<double> guards() noexcept { return run_->guards(); }

private:
    const LagrangianSystem& sys_;
    RunSummary r_;
    World w_;
    RunRecorder record_;
    std::optional<EventMonitor> monitor_;
    std::optional<KernelRun> run_;
    bool over_ = false;
};

/// run_one takes FastRun's path: rk4, no constraints, generated code's fused kernels.
bool fast_path(const LagrangianSystem& sys, const RunSettings& settings) {
    const IntegratorEntry* e = find_integrator(settings.integrator);
    return e && e->fused_kernels && !settings.control && sys.n_constraints == 0 && sys.rk4_step_values &&
           sys.accelerations_energy_guards;
}

} // namespace

RunSummary run_one(const LagrangianSystem& sys, std::span<const std::pair<std::size_t, double>> q0,
                   std::span<const std::pair<std::size_t, double>> v0, const RunSettings& settings,
                   std::string* trajectory, std::vector<double>* values) {
    const IntegratorEntry* entry = find_integrator(settings.integrator);
    if (!entry || !entry->sweeps)
        throw std::invalid_argument("run_one: integrator '" + settings.integrator + "' does not run in sweeps (" +
                                    integrator_names([](const IntegratorEntry& e) { return e.sweeps; }) + ")");
    if (fast_path(sys, settings)) {
        // Generated code's fused kernels: per step one call, rk4_step_values — the RK4 step,
        // then q'', E and the guards at its end, whose q'' is the next step's first stage and
        // whose guards the monitor reads (a state's sines and cosines computed once). The
        // same bits as the workflow below: the same functions' arithmetic in the same order,
        // the exceptions thrown where they would be (tests/codegen/test_kernels.cpp).
        FastRun f(sys, q0, v0, settings, trajectory, values);
        while (const KernelCall* c = f.next()) {
            bool ok = false;
            try {
                ok = sys.rk4_step_values(c->t, c->h, c->t1, f.q(), f.qdot(), f.qddot(), f.energy(), f.guards());
            } catch (const std::exception& e) {
                f.fail(e);
                break;
            }
            f.done(ok);
        }
        return f.summary();
    }
    RunSummary r;
    r.first_event.assign(sys.n_events, std::numeric_limits<double>::quiet_NaN());
    World w = make_lagrangian_world(sys);
    for (const auto& [i, v] : q0) w.at(kGQ, static_cast<Index>(i)) = v;
    for (const auto& [i, v] : v0) w.at(kGV, static_cast<Index>(i)) = v;
    auto finish = [&] {
        r.t = w.time;
        r.q.assign(w.field(kGQ).begin(), w.field(kGQ).end());
        r.qdot.assign(w.field(kGV).begin(), w.field(kGV).end());
    };
    try {
        if (sys.n_constraints > 0) check_constraints(sys, 0, w.field(kGQ), w.field(kGV));
        RunRecorder record(w, r, settings.every, settings.event_log, trajectory, values);
        record.begin(sys.energy(0, w.field(kGQ), w.field(kGV)));
        const long steps = detail::whole_steps(settings.t_end, settings.dt);
        const double last = settings.t_end - static_cast<double>(steps) * settings.dt;
        const long total = steps + (last > 1e-9 * settings.dt ? 1 : 0);
        EventMonitor monitor(sys, settings.events);
        const bool with_events = sys.n_events > 0;
        // after each step: E there from `energy` (the kernels' E: the same bits)
        auto after_step = [&](long k, bool last_step) {
            record(k, last_step, sys.energy(w.time, w.field(kGQ), w.field(kGV)));
        };
        IntegratorSettings is;
        is.dt = settings.dt;
        is.projection = settings.projection;
        is.rtol = settings.rtol;
        is.atol = settings.atol;
        const std::unique_ptr<RunIntegrator> run = entry->make(sys, w, is, with_events);
        const long control_every = std::max(1L, settings.control_every);
        for (long k = 1; k <= total; ++k) {
            const double target = k <= steps ? static_cast<double>(k) * settings.dt : settings.t_end;
            const double h = k <= steps ? settings.dt : last;
            if (settings.control && (k - 1) % control_every == 0) settings.control(w.time, w.field(kGQ), w.field(kGV));
            auto step_to = [&](double t, double dt) { run->step_to(w, t, dt); };
            if (!with_events) {
                step_to(target, h);
                w.time = target;
            } else if (!advance_with_events(monitor, w, target, h, step_to, run->dense())) {
                after_step(k, true);
                break;
            }
            after_step(k, k == total);
        }
        record.complete(sys, monitor);
    } catch (const std::exception& e) {
        r.status = RunSummary::Status::failed;
        r.reason = e.what();
    }
    finish();
    return r;
}

void run_many(const LagrangianSystem& sys, std::span<const RunStart> starts, const RunSettings& settings,
              std::span<RunSummary> out, const std::function<void(std::size_t)>& finished) {
    if (out.size() != starts.size())
        throw std::invalid_argument("run_many: " + std::to_string(starts.size()) + " runs but " +
                                    std::to_string(out.size()) + " summaries");
    auto system_of = [&](std::size_t k) -> const LagrangianSystem& { return starts[k].system ? *starts[k].system : sys; };
    // lanes when every run's system is of one model with lane kernels (the same parameters'
    // type), stepped by the first run's kernel with each run's parameters
    bool lanes = settings.lanes && !starts.empty() && system_of(0).rk4_step_values_lanes_each && system_of(0).parameters_type;
    for (std::size_t k = 0; lanes && k < starts.size(); ++k) {
        const LagrangianSystem& s = system_of(k);
        lanes = fast_path(s, settings) && s.rk4_step_values_lanes_each && s.parameters && s.parameters_type &&
                s.parameters_type == system_of(0).parameters_type; // one model: one lane width
    }
    if (!lanes) {
        for (std::size_t k = 0; k < starts.size(); ++k) {
            out[k] = run_one(system_of(k), starts[k].q0, starts[k].v0, settings, starts[k].trajectory);
            if (finished) finished(k);
        }
        return;
    }
    // lane_width slots, each holding a run until it is over, then the next run in order. Each call
    // of the lane kernel steps every slot's run once, with that run's parameters; an empty slot
    // repeats an occupied one (its results unused). A lane's results depend on its own operands
    // only, so a run's bits do not depend on the company it keeps.
    const LagrangianSystem& model = system_of(0);
    const auto& each = model.rk4_step_values_lanes_each;
    const std::size_t W = model.lane_width; // the width the model's code was compiled with
    if (W == 0) throw std::invalid_argument("run_many: the system's rk4_step_values_lanes_each has lane_width 0");
    const std::size_t n = model.dof, ne = model.n_events;
    std::vector<std::unique_ptr<FastRun>> slot(W);
    std::vector<std::size_t> index(W);
    std::vector<const KernelCall*> call(W);
    std::vector<double> t(W), h(W), t1(W), q(n * W), v(n * W), a(n * W), e(W), g(ne * W);
    std::vector<const void*> parameters(W), slot_parameters(W); // slot_parameters: each slot's run's, set in fill
    std::size_t next = 0;
    auto retire = [&](std::size_t l) {
        out[index[l]] = slot[l]->summary();
        if (finished) finished(index[l]);
        slot[l].reset();
    };
    auto fill = [&](std::size_t l) { // the next run that needs a call, in order
        while (!slot[l] && next < starts.size()) {
            index[l] = next;
            slot_parameters[l] = system_of(next).parameters.get();
            slot[l] = std::make_unique<FastRun>(system_of(next), starts[next].q0, starts[next].v0, settings, starts[next].trajectory);
            ++next;
            call[l] = slot[l]->next();
            if (!call[l]) retire(l);
        }
    };
    // lane `l` of the buffers from slot `s`'s run, and back
    auto gather = [&](std::size_t l, std::size_t s) {
        FastRun& f = *slot[s];
        parameters[l] = slot_parameters[s];
        t[l] = call[s]->t;
        h[l] = call[s]->h;
        t1[l] = call[s]->t1;
        for (std::size_t i = 0; i < n; ++i) {
            q[i * W + l] = f.q()[i];
            v[i * W + l] = f.qdot()[i];
            a[i * W + l] = f.qddot()[i];
        }
    };
    auto scatter = [&](std::size_t l, std::size_t s) {
        FastRun& f = *slot[s];
        for (std::size_t i = 0; i < n; ++i) {
            f.q()[i] = q[i * W + l];
            f.qdot()[i] = v[i * W + l];
            f.qddot()[i] = a[i * W + l];
        }
        f.energy() = e[l];
        for (std::size_t k = 0; k < ne; ++k) f.guards()[k] = g[k * W + l];
    };
    auto kernel = [&] {
        return each(parameters.data(), t.data(), h.data(), t1.data(), q.data(), v.data(), a.data(), e.data(), g.data());
    };
    for (std::size_t l = 0; l < W; ++l) fill(l);
    for (;;) {
        std::size_t first = W;
        for (std::size_t l = 0; l < W && first == W; ++l)
            if (slot[l]) first = l;
        if (first == W) break;
        for (std::size_t l = 0; l < W; ++l) gather(l, slot[l] ? l : first);
        bool ok = false, threw = false;
        try {
            ok = kernel();
        } catch (const std::exception&) {
            threw = true;
        }
        for (std::size_t l = 0; l < W; ++l) {
            if (!slot[l]) continue;
            if (!threw && ok) {
                scatter(l, l);
                slot[l]->done(true);
                continue;
            }
            // some run failed: each again alone, in every lane (the same bits, its own verdict)
            for (std::size_t m = 0; m < W; ++m) gather(m, l);
            try {
                const bool alone = kernel();
                scatter(0, l);
                slot[l]->done(alone);
            } catch (const std::exception& err) {
                slot[l]->fail(err); // the state at the step's start (the kernel stores only at its end)
            }
        }
        for (std::size_t l = 0; l < W; ++l) {
            if (!slot[l]) continue;
            call[l] = slot[l]->next();
            if (!call[l]) {
                retire(l);
                fill(l);
            }
        }
    }
}

} // namespace phynjo::runtime
