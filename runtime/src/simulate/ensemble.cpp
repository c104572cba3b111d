// Ensembles: sweep plans, one run, and the sweep driver of the simulators (ensemble.hpp).
#include "phynjo/runtime/simulate/ensemble.hpp"

#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/executor.hpp"
#include "phynjo/runtime/simulate/integrator_registry.hpp"
#include "phynjo/runtime/system/detail/lanes.hpp"

#include <algorithm>
#include <memory>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <limits>
#include <optional>
#include <stdexcept>
#include <unistd.h>

#include "strict_numbers.hpp"

namespace phynjo::runtime {

namespace {

using detail::finite_number;

/// NAME=A:B[:C] split; throws with the option's own wording.
std::vector<std::string> fields_of(std::string_view text, std::string& name, std::size_t count, const char* form) {
    const auto eq = text.find('=');
    if (eq == std::string_view::npos || eq == 0)
        throw std::invalid_argument("expected " + std::string(form) + ", got '" + std::string(text) + "'");
    name = std::string(text.substr(0, eq));
    std::vector<std::string> parts;
    std::string_view rest = text.substr(eq + 1);
    for (;;) {
        const auto colon = rest.find(':');
        parts.emplace_back(rest.substr(0, colon));
        if (colon == std::string_view::npos) break;
        rest = rest.substr(colon + 1);
    }
    if (parts.size() != count)
        throw std::invalid_argument("expected " + std::string(form) + ", got '" + std::string(text) + "'");
    return parts;
}

double bound(const std::string& s, const std::string& text) {
    if (auto v = finite_number(s)) return *v;
    throw std::invalid_argument("'" + s + "' is not a finite number (in '" + text + "')");
}

/// SplitMix64 (Steele, Lea, Flood 2014): a counter-based stream of 64-bit values.
std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) {
        if (c == '"') q += '"';
        q += c == '\n' || c == '\r' ? ' ' : c;
    }
    return q + "\"";
}

void append_number(std::string& out, double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    out += buf;
}

} // namespace

SweepAxis parse_grid_axis(std::string_view text) {
    SweepAxis a;
    const auto p = fields_of(text, a.name, 3, "NAME=LO:HI:N");
    const std::string t(text);
    a.lo = bound(p[0], t);
    a.hi = bound(p[1], t);
    const auto whole = detail::whole_number(p[2]);
    const long n = whole ? *whole : 0;
    if (n < 1)
        throw std::invalid_argument("'" + p[2] + "' is not a positive whole number of points (in '" + t + "')");
    if (n > 100000000) throw std::invalid_argument("more than 10^8 points on one axis (in '" + t + "')");
    a.n = static_cast<std::size_t>(n);
    return a;
}

SweepAxis parse_uniform_axis(std::string_view text) {
    SweepAxis a;
    const auto p = fields_of(text, a.name, 2, "NAME=LO:HI");
    const std::string t(text);
    a.lo = bound(p[0], t);
    a.hi = bound(p[1], t);
    if (!(a.lo <= a.hi)) throw std::invalid_argument("LO must not exceed HI (in '" + t + "')");
    a.n = 0;
    return a;
}

std::size_t SweepPlan::size() const {
    std::size_t n = samples;
    for (const SweepAxis& a : grid) n *= a.n;
    return n;
}

std::vector<std::string> SweepPlan::names() const {
    std::vector<std::string> n;
    for (const SweepAxis& a : grid) n.push_back(a.name);
    for (const SweepAxis& a : uniform) n.push_back(a.name);
    return n;
}

void SweepPlan::values(std::size_t run, std::span<double> out) const {
    std::size_t point = run / samples;
    for (std::size_t k = grid.size(); k-- > 0;) { // the last axis fastest
        const SweepAxis& a = grid[k];
        const std::size_t i = point % a.n;
        point /= a.n;
        out[k] = a.n == 1 ? a.lo : a.lo + static_cast<double>(i) * (a.hi - a.lo) / static_cast<double>(a.n - 1);
    }
    for (std::size_t j = 0; j < uniform.size(); ++j) {
        const std::uint64_t r = splitmix64(seed ^ splitmix64(run * 0x100000001b3ull + j));
        const double u = static_cast<double>(r >> 11) * 0x1.0p-53; // [0, 1)
        out[grid.size() + j] = uniform[j].lo + u * (uniform[j].hi - uniform[j].lo);
    }
}

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
    RunRecorder(const World& w, RunSummary& r, long every, std::string* trajectory)
        : w_(w), r_(r), trajectory_(trajectory), q_(w.field(kGQ).data()), v_(w.field(kGV).data()), dof_(w.field(kGQ).size()),
          every_(std::max(1L, every)) {}
    /// At the initial state: E(0) = `e0`, the first row.
    void begin(double e0) {
        e0_ = e0;
        scale_ = std::max(1.0, std::abs(e0));
        if (trajectory_) row(e0);
    }
    /// After whole step `k` (the last one when `last_step`), E there = `e`.
    void operator()(long k, bool last_step, double e) {
        for (std::size_t i = 0; i < dof_; ++i)
            if (!std::isfinite(q_[i]) || !std::isfinite(v_[i])) throw Error("the state is not finite");
        r_.max_energy_error = std::max(r_.max_energy_error, std::abs(e - e0_) / scale_);
        if (trajectory_ && (last_step || k % every_ == 0)) row(e);
    }
    /// The run is over without an error: the events' first times, a stop's reason.
    void complete(const LagrangianSystem& sys, const EventMonitor& monitor) {
        for (const EventRecord& e : monitor.log())
            if (std::isnan(r_.first_event[e.event])) r_.first_event[e.event] = e.time;
        if (monitor.stopped() && !monitor.log().empty()) {
            r_.status = RunSummary::Status::stopped;
            r_.reason = "event " + sys.event_names[monitor.log().back().event];
        }
    }

private:
    void row(double e) {
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
    const double* q_;
    const double* v_;
    std::size_t dof_;
    long every_;
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
            std::span<const std::pair<std::size_t, double>> v0, const RunSettings& settings, std::string* trajectory)
        : sys_(sys), w_(make_lagrangian_world(sys)), record_(w_, r_, settings.every, trajectory) {
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
    return e && e->fused_kernels && sys.n_constraints == 0 && sys.rk4_step_values && sys.accelerations_energy_guards;
}

} // namespace

RunSummary run_one(const LagrangianSystem& sys, std::span<const std::pair<std::size_t, double>> q0,
                   std::span<const std::pair<std::size_t, double>> v0, const RunSettings& settings,
                   std::string* trajectory) {
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
        FastRun f(sys, q0, v0, settings, trajectory);
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
        RunRecorder record(w, r, settings.every, trajectory);
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
        const std::unique_ptr<RunIntegrator> run = entry->make(sys, w, is, with_events);
        for (long k = 1; k <= total; ++k) {
            const double target = k <= steps ? static_cast<double>(k) * settings.dt : settings.t_end;
            const double h = k <= steps ? settings.dt : last;
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
                *s.parameters_type == *system_of(0).parameters_type; // one model: one lane width
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

namespace {

/// Where each swept name goes: a parameter (its setter), an initial value, an initial velocity.
struct Target {
    enum Kind { parameter, position, velocity } kind;
    std::size_t index; // into model.parameters, or a coordinate
};

} // namespace

int run_sweep(const SweepCommand& cmd, const ModelCommandLine& model, const char* program) {
    SweepProcesses* const processes = cmd.processes;
    const unsigned rank = processes ? processes->rank() : 0, ranks = processes ? processes->size() : 1;
    // every rank checks the same command and reaches the same verdict; rank 0 says it
    auto usage = [&](const std::string& m) {
        if (rank == 0) std::fprintf(stderr, "%s: %s\n", program, m.c_str());
        return 2;
    };
    const LagrangianSystem base = model.system();
    const auto& coords = base.coordinate_names;
    // Each swept name, and each fixed --init, resolved once.
    auto resolve = [&](const std::string& name) -> std::optional<Target> {
        for (std::size_t k = 0; k < model.parameters.size(); ++k)
            if (model.parameters[k].first == name) return Target{Target::parameter, k};
        const bool vel = !name.empty() && name.back() == '\'';
        const std::string c = vel ? name.substr(0, name.size() - 1) : name;
        const auto it = std::find(coords.begin(), coords.end(), c);
        if (it == coords.end()) return std::nullopt;
        return Target{vel ? Target::velocity : Target::position, static_cast<std::size_t>(it - coords.begin())};
    };
    const std::vector<std::string> names = cmd.plan.names();
    std::vector<Target> targets;
    bool parameters_swept = false;
    for (std::size_t k = 0; k < names.size(); ++k) {
        const auto t = resolve(names[k]);
        if (!t) return usage("sweep: '" + names[k] + "' is not a parameter, an input, a coordinate or a coordinate's velocity (try --help)");
        for (std::size_t j = 0; j < k; ++j)
            if (names[j] == names[k]) return usage("sweep: '" + names[k] + "' is swept twice");
        parameters_swept = parameters_swept || t->kind == Target::parameter;
        targets.push_back(*t);
    }
    std::vector<std::pair<std::size_t, double>> fixed_q, fixed_v;
    for (const auto& [name, v] : cmd.inits) {
        const auto t = resolve(name);
        if (!t || t->kind == Target::parameter) return usage("--init: '" + name + "' is not a coordinate (try --help)");
        (t->kind == Target::position ? fixed_q : fixed_v).emplace_back(t->index, v);
    }
    if (const IntegratorEntry* e = find_integrator(cmd.settings.integrator); !e || !e->sweeps)
        return usage("sweeps run with --integrator " + integrator_names([](const IntegratorEntry& x) { return x.sweeps; }) +
                     ", not '" + cmd.settings.integrator + "'");

    const std::size_t total = cmd.plan.size();
    const std::string first_line = "# phynjo sweep: " + cmd.signature;
    std::string header = "run";
    for (const std::string& n : names) header += "," + n;
    header += ",status,t";
    for (const auto& c : coords) header += ",end_" + c;
    for (const auto& c : coords) header += ",end_" + c + "'";
    for (const auto& e : base.event_names) header += ",first_" + e;
    header += ",max_energy_error,reason";

    const unsigned threads = std::max(1u, cmd.threads);
    // Rank 0 opens the summary (resuming it) and the trajectories' folder, then tells every
    // rank the verdict, where the sweep goes on, and the batch size.
    std::FILE* out = nullptr;
    std::uint64_t shared[3] = {0, 0, std::max<std::uint64_t>(64, 16 * std::uint64_t{threads})}; // status, done, batch
    auto open_summary = [&]() -> int {
        // Resume: keep the complete rows of a summary this same command began.
        std::size_t done = 0;
        if (std::FILE* old = std::fopen(cmd.summary.c_str(), "r")) {
            std::string text;
            char buf[65536];
            for (std::size_t got; (got = std::fread(buf, 1, sizeof buf, old)) > 0;) text.append(buf, got);
            std::fclose(old);
            if (!text.empty()) {
                const auto nl = text.find('\n');
                if (nl == std::string::npos || text.substr(0, nl) != first_line)
                    return usage("--summary " + cmd.summary + " was written by another command (its first line is not '" +
                                 first_line + "'); remove it or choose another file");
                const auto nl2 = text.find('\n', nl + 1);
                std::size_t keep = nl2 == std::string::npos ? 0 : nl2 + 1; // after the header
                if (keep > 0) {
                    if (text.substr(nl + 1, nl2 - nl - 1) != header)
                        return usage("--summary " + cmd.summary + ": its header does not match this model's");
                    for (std::size_t p = keep; (p = text.find('\n', p)) != std::string::npos; ++p) {
                        ++done;
                        keep = p + 1;
                    }
                }
                if (done > total) return usage("--summary " + cmd.summary + " holds more rows than this sweep has runs");
                if (keep < text.size() || keep == 0) { // drop a partial row (or a partial header)
                    if (::truncate(cmd.summary.c_str(), static_cast<off_t>(keep)) != 0) {
                        std::fprintf(stderr, "%s: cannot truncate %s\n", program, cmd.summary.c_str());
                        return 1;
                    }
                }
                if (keep == 0) done = 0;
            }
        }
        if (!cmd.trajectories.empty()) {
            std::error_code ec;
            std::filesystem::create_directories(cmd.trajectories, ec);
            if (ec || !std::filesystem::is_directory(cmd.trajectories)) {
                std::fprintf(stderr, "%s: --trajectories: cannot make the folder %s\n", program, cmd.trajectories.c_str());
                return 1;
            }
        }
        out = std::fopen(cmd.summary.c_str(), "a");
        if (!out) {
            std::fprintf(stderr, "%s: cannot write %s\n", program, cmd.summary.c_str());
            return 1;
        }
        std::fseek(out, 0, SEEK_END);
        if (std::ftell(out) == 0) std::fprintf(out, "%s\n%s\n", first_line.c_str(), header.c_str());
        std::fflush(out);
        if (done > 0) std::fprintf(stderr, "%s: resuming %s after its %zu of %zu runs\n", program, cmd.summary.c_str(), done, total);
        shared[1] = done;
        return 0;
    };
    if (rank == 0) shared[0] = static_cast<std::uint64_t>(open_summary());
    if (processes) processes->broadcast(shared);
    if (shared[0] != 0) return static_cast<int>(shared[0]);
    const std::size_t done = shared[1], batch = shared[2];
    const std::size_t batches = (total - done + batch - 1) / batch;

    // A trajectory file's name: run numbers zero-padded to the width of the last one's.
    const int width = static_cast<int>(std::to_string(total > 0 ? total - 1 : 0).size());
    std::string trajectory_header = "t";
    for (const auto& c : coords) trajectory_header += "," + c;
    for (const auto& c : coords) trajectory_header += "," + c + "'";
    trajectory_header += ",E\n";

    Executor executor(threads);
    std::vector<LagrangianSystem> systems;
    std::vector<std::vector<std::pair<std::size_t, double>>> q0s(batch), v0s(batch);
    std::vector<RunSummary> results(batch);
    std::vector<double> values(names.size());
    std::vector<std::vector<double>> batch_values(batch);
    std::vector<std::string> trajectory_failed(threads); // a file a thread could not write
    // Batch b (runs done + b·batch …): run on this rank's threads, its summary rows returned.
    auto run_batch = [&](std::size_t b) {
        const std::size_t first = done + b * batch, count = std::min(batch, total - first);
        systems.clear();
        for (std::size_t j = 0; j < count; ++j) { // on this thread: the setters share the model's parameters
            cmd.plan.values(first + j, values);
            batch_values[j] = values;
            q0s[j] = fixed_q;
            v0s[j] = fixed_v;
            for (std::size_t k = 0; k < names.size(); ++k) {
                const Target& t = targets[k];
                if (t.kind == Target::parameter) model.parameters[t.index].second(values[k]);
                else (t.kind == Target::position ? q0s[j] : v0s[j]).emplace_back(t.index, values[k]);
            }
            if (parameters_swept) systems.push_back(model.system());
        }
        auto task = [&](unsigned i) {
            // this thread's runs: i, i + threads, … (run_many's results do not depend on the grouping)
            std::vector<std::size_t> mine;
            for (std::size_t j = i; j < count; j += threads) mine.push_back(j);
            std::vector<std::string> rows(cmd.trajectories.empty() ? 0 : mine.size());
            auto write = [&](std::size_t k) { // run mine[k] is over: its trajectory file
                if (rows.empty()) return;
                char name[48];
                std::snprintf(name, sizeof name, "run_%0*zu.csv", width, first + mine[k]);
                const std::string path = (std::filesystem::path(cmd.trajectories) / name).string();
                std::FILE* f = std::fopen(path.c_str(), "w");
                const bool ok = f && std::fwrite(rows[k].data(), 1, rows[k].size(), f) == rows[k].size();
                if ((f && std::fclose(f) != 0) || !ok) trajectory_failed[i] = path;
                std::string().swap(rows[k]);
            };
            std::vector<RunSummary> mine_results(mine.size());
            std::vector<RunStart> starts; // a system per run when parameters are swept
            for (std::size_t k = 0; k < mine.size(); ++k)
                starts.push_back({q0s[mine[k]], v0s[mine[k]], rows.empty() ? nullptr : &(rows[k] = trajectory_header),
                                  parameters_swept ? &systems[mine[k]] : nullptr});
            run_many(base, starts, cmd.settings, mine_results, write);
            for (std::size_t k = 0; k < mine.size(); ++k) results[mine[k]] = std::move(mine_results[k]);
        };
        executor.fork_join(threads, task);
        for (const std::string& path : trajectory_failed)
            if (!path.empty()) { // this rank's own failure: it speaks, and the sweep ends
                std::fprintf(stderr, "%s: --trajectories: cannot write %s\n", program, path.c_str());
                if (ranks > 1) processes->abort(1);
                return std::optional<std::string>();
            }
        std::string rows;
        for (std::size_t j = 0; j < count; ++j) {
            const RunSummary& r = results[j];
            rows += std::to_string(first + j);
            for (double v : batch_values[j]) rows += ',', append_number(rows, v);
            rows += r.status == RunSummary::Status::finished ? ",finished," : r.status == RunSummary::Status::stopped ? ",stopped," : ",failed,";
            append_number(rows, r.t);
            for (double v : r.q) rows += ',', append_number(rows, v);
            for (double v : r.qdot) rows += ',', append_number(rows, v);
            for (double v : r.first_event) {
                rows += ',';
                if (!std::isnan(v)) append_number(rows, v);
            }
            rows += ',';
            append_number(rows, r.max_energy_error);
            rows += ',' + csv_field(r.reason) + '\n';
        }
        return std::optional<std::string>(std::move(rows));
    };

    if (rank != 0) { // a worker: its batches, round robin, to rank 0
        for (std::size_t b = rank; b < batches; b += ranks) {
            auto rows = run_batch(b);
            processes->send(b, std::move(*rows));
        }
        processes->flush();
        return 0;
    }

    // Rank 0: its own batches, and the others' as they arrive, written in run order.
    std::map<std::size_t, std::string> pending;
    std::size_t next = 0; // the first batch not written
    const bool progress = ::isatty(STDERR_FILENO) != 0;
    const auto start = std::chrono::steady_clock::now();
    auto last_report = start;
    auto write_ready = [&] {
        for (auto it = pending.begin(); it != pending.end() && it->first == next; it = pending.erase(it), ++next) {
            const std::string& rows = it->second;
            if (std::fwrite(rows.data(), 1, rows.size(), out) != rows.size() || std::fflush(out) != 0) {
                std::fprintf(stderr, "%s: cannot write %s\n", program, cmd.summary.c_str());
                if (ranks > 1) processes->abort(1);
                return false;
            }
            const std::size_t written = std::min(total, done + (next + 1) * batch);
            const auto now = std::chrono::steady_clock::now();
            if (progress && (now - last_report > std::chrono::milliseconds(500) || written == total)) {
                last_report = now;
                const double sec = std::chrono::duration<double>(now - start).count();
                const double rate = static_cast<double>(written - done) / std::max(sec, 1e-9);
                std::fprintf(stderr, "\r%s: %zu of %zu runs, %.1f runs/s, about %.0f s left   ", program, written, total, rate,
                             static_cast<double>(total - written) / std::max(rate, 1e-9));
                if (written == total) std::fprintf(stderr, "\n");
            }
        }
        return true;
    };
    bool ok = true;
    for (std::size_t b = 0; ok && b < batches; b += ranks) {
        auto rows = run_batch(b);
        if (!rows) {
            ok = false;
            break;
        }
        pending.emplace(b, std::move(*rows));
        if (ranks > 1)
            while (auto got = processes->receive(false)) pending.emplace(got->first, std::move(got->second));
        ok = write_ready();
    }
    while (ok && next < batches) {
        auto got = processes->receive(true);
        pending.emplace(got->first, std::move(got->second));
        ok = write_ready();
    }
    std::fclose(out);
    if (processes) processes->flush();
    return ok ? 0 : 1;
}

} // namespace phynjo::runtime
