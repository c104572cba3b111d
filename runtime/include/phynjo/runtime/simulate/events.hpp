#pragma once
/// \file
/// Events of generated models (docs/language.md, *Events*) between the steps of any integrator:
/// crossings located on the step's continuous extension, resets applied at the crossing,
/// the log of what fired as a value, and the rules for simultaneous events, re-arming and
/// Zeno behaviour. (source: simulate/events.cpp)
///
/// The rules, in the order they act:
/// - **Crossing.** Event k fires when its guard g_k passes from its *armed side* (g > 0 for
///   `A < B`, g < 0 for `A > B`) to the other side (or onto 0). After each step the guards
///   are evaluated at its end; an armed guard that is no longer on its armed side has
///   crossed. Where: on the integrator's continuous extension of the step — Dormand–Prince's
///   dense output; CVODE's, IDA's and Bdf's interpolating polynomials of their own internal
///   steps (the run then advances them one internal step at a time: Cvode::step, Ida::step,
///   Bdf::step); for the fixed-step integrators the cubic Hermite arc of the step
///   (HermiteStep, from the states and accelerations at both ends: O(h⁴), the order of
///   RK4) — by the Illinois root finder (locate_crossing) to `time_tolerance`. The event
///   time is the first time known to be across (so the guard is across after the event),
///   never the end of the step. A guard that crosses and crosses back within one step is
///   not seen (as in every integrator that checks signs at steps).
/// - **Simultaneous events.** The earliest crossing sets the event time t_e; every armed
///   event whose guard is across at t_e fires with it. Each one's right sides are evaluated
///   on the state before the event (as the spec says of one event's actions); a coordinate or
///   velocity reset by two of them takes the value of the later one in file order. If one of
///   them is `stop`, nothing is reset: the run ends at t_e with the state there.
/// - **Actions that change nothing** (an observing event, `x' = x'`): the event is logged
///   at t_e with the state there, but the world stays where the integrator left it and the
///   rest of the step is searched again from t_e: the run is the run without the event, bit
///   for bit (a multistep solver keeps its history).
/// - **Re-arming.** After its actions an event is disarmed until its guard is back on its
///   armed side; the monitor looks for that just after t_e — on the Taylor arc
///   q + v·δ + a·δ²/2 for δ from a few times the crossing bracket up to the rest of the step
///   (a ball bounced upwards re-arms at once, even when its next flight is shorter than a
///   step) — and then at the end of every step. A reset never fires another event: an
///   event whose guard a reset throws across is disarmed, not fired.
/// - **Zeno.** More than `max_events_per_step` events within one step of the run, or one
///   event firing `zeno_run` times in a row with each interval at most 0.99 of the one before
///   and the last shorter than a tenth of the step (a geometric accumulation), stops the run
///   with ZenoError naming the event, the time, and the estimated accumulation point.
/// - **The remedy** (`rest_speed` > 0): a velocity an event resets to a magnitude below
///   rest_speed becomes 0 and the event *rests*: its reset coordinates and velocities are
///   held (at their values then, velocities 0) after every step, while a free step would
///   leave its guard across; a step that ends with the guard on the armed side releases it
///   (lift-off). The bouncing ball comes to rest on the floor instead of chattering. With
///   the remedy on, the geometric Zeno test is off (a chattering sequence is expected to
///   end in rest); the per-step limit still applies.
#include "phynjo/runtime/core/archive.hpp"
#include "phynjo/runtime/core/event.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <cstddef>
#include <vector>

namespace phynjo::runtime {

/// One event that fired: the time, which event (file order), and the state just after its
/// actions (for `stop`, the state at the event).
struct EventRecord {
    double time = 0;
    std::size_t event = 0;
    std::vector<double> q, qdot;
};

struct EventOptions {
    /// The crossing time is located to this, s (docs/language.md: 1e-10 or better).
    double time_tolerance = 1e-12;
    /// Zeno: more events than this within one step of the run is an error.
    std::size_t max_events_per_step = 100;
    /// Zeno: this many firings of one event in a row at geometrically shrinking intervals,
    /// the last below a tenth of the run's step, is an error.
    std::size_t zeno_run = 6;
    /// The Zeno remedy: velocity resets below this speed (in the velocity's units) become 0
    /// and hold. 0 turns it off.
    double rest_speed = 0;
};

/// What end_step found.
struct EventStep {
    bool fired = false;   ///< the world was moved back to the event time, after the actions
    bool stopped = false; ///< a `stop` event fired: the run ends here
    bool moved = false;   ///< w's state is no longer the one the integrator left (an event, or a resting event's hold)
    bool observed = false; ///< an event fired whose actions changed nothing: logged, w left where it was
};

/// Watches the events of one run. Use: for each step of the run, `begin_run_step(dt)`; then
/// until the world has reached the step's end: `begin_step(w)`, let the integrator advance
/// w (w.time at the step's end), `end_step(w)` — after an event, w is at the event time and
/// the integrator continues from there (a multistep solver restarts: the state jumped).
/// Allocates nothing in a step without events.
class EventMonitor {
public:
    explicit EventMonitor(LagrangianSystem system, EventOptions options = {});

    /// A step of the run of length `dt` begins: the Zeno count starts again.
    void begin_run_step(double dt) noexcept {
        run_dt_ = dt;
        events_this_run_step_ = 0;
    }
    /// Before the integrator advances `w`: remembers its time and state. The first call arms
    /// the events whose guards are on their armed side.
    void begin_step(const World& w) {
        if (ne_ == 0) return; // nothing to watch: no copy in the step
        t0_ = w.time;
        const double *q = w.field(kGQ).data(), *v = w.field(kGV).data();
        double *q0 = q0_.data(), *v0 = v0_.data();
        for (std::size_t i = 0; i < n_; ++i) {
            q0[i] = q[i];
            v0[i] = v[i];
        }
        if (!started_) arm_first();
        // (an event armed before this step is armed since its start: end_step_impl brackets a
        // crossing from max(arm_time_, t0_))
    }
    /// An integrator's own continuous extension of the step just taken: (q, q') at t.
    using Extension = std::function<void(double t, std::span<double> q, std::span<double> qdot)>;
    /// After the integrator advanced `w` (w.time its new time): locates, applies, logs.
    /// Crossings are located on `extension` when given (DormandPrince45::dense), else on
    /// the cubic Hermite arc of the step. Throws ZenoError (see the rules above); the world
    /// is then at the last event.
    EventStep end_step(World& w, const Extension* extension = nullptr);
    /// end_step on the Hermite arc with what the caller has already computed: `g1` the guards
    /// at w's state, `a0` and `a1` the accelerations at the step's start and end (empty when
    /// not known, or when accelerations_energy_guards returned false there: then computed, and
    /// thrown, as end_step does). The same result, bit for bit, as end_step(w) when they are
    /// what the system's functions give (run_one with generated code's fused kernels).
    EventStep end_step(World& w, std::span<const double> g1, std::span<const double> a0, std::span<const double> a1) {
        if (g1.size() != ne_ || (!a0.empty() && a0.size() != n_) || (!a1.empty() && a1.size() != n_))
            wrong_sizes(g1.size(), a0.size(), a1.size());
        if (ne_ == 0 || stopped_) return {};
        // the common step: none resting, none crossed — only events back on their armed side
        // re-armed (what end_step_impl does first, without its copies)
        if (resting_count_ == 0 && !rearm(g1.data(), w.time)) return {};
        return end_step_impl(w, nullptr, g1, a0, a1);
    }

    [[nodiscard]] const std::vector<EventRecord>& log() const noexcept { return log_; }
    [[nodiscard]] bool stopped() const noexcept { return stopped_; }
    [[nodiscard]] bool armed(std::size_t k) const { return armed_.at(k) != 0; }
    [[nodiscard]] bool resting(std::size_t k) const { return resting_.at(k) != 0; }
    [[nodiscard]] const LagrangianSystem& system() const noexcept { return sys_; }

    /// What the monitor carries from one step of the run to the next — which events are
    /// armed and since when, which rest and what they hold, the recent firing times (Zeno),
    /// the log, whether the run was stopped — for an archive's snapshot (core/archive.hpp).
    void save(ArchiveBytes& out) const;
    /// Continues as the monitor that saved `in` (of the same model: ArchiveError otherwise).
    void restore(ArchiveReader& in);

private:
    /// Is guard value g on event k's armed side (g > 0 for a falling event, g < 0 for a rising one)?
    [[nodiscard]] bool armed_side(std::size_t k, double g) const noexcept { return side_sign_[k] * g > 0; }
    /// Re-arms each event not resting whose guard `g` (at time t) is back on its armed side;
    /// true when an armed one is off it (a crossing to locate).
    bool rearm(const double* g, double t) noexcept {
        bool any = false;
        for (std::size_t k = 0; k < ne_; ++k) {
            if (resting_[k]) continue;
            const bool side = armed_side(k, g[k]);
            if (armed_[k]) any = any || !side;
            else if (side) {
                armed_[k] = 1; // back on its armed side: watch it from here
                arm_time_[k] = t;
            }
        }
        return any;
    }
    void check_zeno(std::size_t k, double t);
    void arm_first();
    [[noreturn]] void wrong_sizes(std::size_t g, std::size_t a0, std::size_t a1) const;
    /// After events fired at te (fired_) with the state qp_, vp_ after them: re-arms every
    /// event on its armed side there, probes a fired one on `arc` (t, q, v) just after te up
    /// to t1, and counts the firings for the Zeno tests.
    template <typename Arc>
    void rearm_after(double te, double bracket, double t1, Arc&& arc);
    EventStep end_step_impl(World& w, const Extension* extension, std::span<const double> g1, std::span<const double> a0,
                            std::span<const double> a1);

    LagrangianSystem sys_;
    EventOptions opt_;
    std::size_t n_ = 0, ne_ = 0;
    bool started_ = false, stopped_ = false;
    double run_dt_ = 0, t0_ = 0;
    std::size_t events_this_run_step_ = 0;
    std::size_t resting_count_ = 0; ///< events resting now
    std::vector<double> side_sign_;  ///< per event: +1 when its armed side is g > 0, else −1 (event_directions)
    std::vector<double> q0_, v0_, a0_, a1_, g_, g_end_, g_left_, qe_, ve_, qk_, vk_, qp_, vp_, ap_;
    std::vector<unsigned char> armed_, resting_, fired_;
    std::vector<std::size_t> held_by_; ///< per coordinate: the resting event holding it, or ne_
    std::vector<double> arm_time_, held_q_;
    std::vector<std::vector<double>> recent_; ///< per event: its last firing times (Zeno)
    std::vector<EventRecord> log_;
};

// ---- The model's events on the runtime's event layer (core/event.hpp) -------------------
// The physical layer signals, the Boolean layer reacts (sensors): after each step
// of the run, signal_events raises one flag per model event that fired; event rules of the
// user's read those flags in an EventWorkflow; model_events_rule turns them into the
// Phenomenon (the event layer's log) and lowers them again.

/// Registers one flag per event of `system`, labelled PREFIX + event name ("ball.bounce"),
/// in file order; returns their indices.
std::vector<Index> add_event_flags(Registry& flags, const LagrangianSystem& system, std::string_view prefix);

/// Raises the flag of every event that fired since log entry `since` of `monitor` (flags[k]
/// for event k; the others are left as they are); returns the new cursor, log().size().
std::size_t signal_events(const EventMonitor& monitor, std::size_t since, std::span<const Index> flags, FlagWorld& world);

/// An event rule over the flags of add_event_flags (its domain): each tick it emits one
/// Event per raised flag, "NAME fired" (the Phenomenon of the event layer), and lowers it: a
/// model event is a one-tick pulse. Rules that read those flags run before it in a `seq`.
EventRule model_events_rule(std::string name, const LagrangianSystem& system, std::span<const Index> flags);

/// One step of a run, `h` long, from w.time to `target` (= w.time + h), watched by `monitor`:
/// `step_to(target, dt)` takes one step of the integrator, dt long (h itself while no event
/// has fired in this step of the run, the rest of it after one), and leaves w.time where it
/// ended (an adaptive integrator may end short of target: it is called again). Ends with
/// w.time = target exactly and returns true, or returns false when a `stop` event ended the
/// run (w at the event). `extension`: the integrator's continuous extension, when it has
/// one (end_step). Throws what end_step throws (ZenoError).
template <typename StepTo>
bool advance_with_events(EventMonitor& monitor, World& w, double target, double h, StepTo&& step_to,
                         const EventMonitor::Extension* extension = nullptr) {
    monitor.begin_run_step(h);
    bool whole = true;
    while (w.time < target - 1e-12 * h) {
        monitor.begin_step(w);
        step_to(target, whole ? h : target - w.time);
        const EventStep e = monitor.end_step(w, extension);
        if (e.stopped) return false;
        whole = whole && !e.fired;
    }
    w.time = target;
    return true;
}

} // namespace phynjo::runtime
