// Events of generated models between integrator steps (simulate/events.hpp: the rules).
#include "phynjo/runtime/simulate/events.hpp"

#include "phynjo/runtime/simulate/detail/crossing.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace phynjo::runtime {

namespace {
std::string time_text(double t) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", t);
    return buf;
}
} // namespace

EventMonitor::EventMonitor(LagrangianSystem system, EventOptions options) : sys_(std::move(system)), opt_(options) {
    n_ = sys_.dof;
    ne_ = sys_.n_events;
    if (ne_ > 0 && (!sys_.event_guards || !sys_.apply_event || sys_.event_directions.size() != ne_ ||
                    sys_.event_stops.size() != ne_ || sys_.event_names.size() != ne_))
        throw std::invalid_argument("EventMonitor: the system declares " + std::to_string(ne_) +
                                    " events but not their guards, actions, directions, stops and names");
    if (!(opt_.time_tolerance > 0)) throw std::invalid_argument("EventMonitor: time_tolerance must be positive");
    if (opt_.max_events_per_step == 0) throw std::invalid_argument("EventMonitor: max_events_per_step must be positive");
    if (opt_.zeno_run < 3) throw std::invalid_argument("EventMonitor: zeno_run must be at least 3");
    if (!(opt_.rest_speed >= 0)) throw std::invalid_argument("EventMonitor: rest_speed must not be negative");
    for (auto* v : {&q0_, &v0_, &a0_, &a1_, &qe_, &ve_, &qk_, &vk_, &qp_, &vp_, &ap_, &held_q_}) v->assign(n_, 0.0);
    for (auto* v : {&g_, &g_end_, &g_left_, &arm_time_}) v->assign(ne_, 0.0);
    for (auto* v : {&armed_, &resting_, &fired_}) v->assign(ne_, 0);
    held_by_.assign(n_, ne_);
    for (std::size_t k = 0; k < ne_; ++k) side_sign_.push_back(sys_.event_directions[k] < 0 ? 1.0 : -1.0);
    recent_.resize(ne_);
}

void EventMonitor::arm_first() {
    started_ = true;
    sys_.event_guards(t0_, q0_, v0_, g_);
    for (std::size_t k = 0; k < ne_; ++k) {
        armed_[k] = armed_side(k, g_[k]) ? 1 : 0;
        arm_time_[k] = t0_;
    }
}

EventStep EventMonitor::end_step(World& w, const Extension* extension) { return end_step_impl(w, extension, {}, {}, {}); }

void EventMonitor::wrong_sizes(std::size_t g, std::size_t a0, std::size_t a1) const {
    throw std::invalid_argument("EventMonitor::end_step: " + std::to_string(g) + " guards and " + std::to_string(a0) +
                                ", " + std::to_string(a1) + " accelerations given for a system of " +
                                std::to_string(ne_) + " events and " + std::to_string(n_) +
                                " coordinates (accelerations may be empty)");
}

EventStep EventMonitor::end_step_impl(World& w, const Extension* extension, std::span<const double> g1,
                                      std::span<const double> a0, std::span<const double> a1) {
    EventStep out;
    if (ne_ == 0 || stopped_) return out;
    const double t1 = w.time;
    auto q1 = w.field(kGQ), v1 = w.field(kGV);
    if (g1.empty()) sys_.event_guards(t1, q1, v1, g_);
    else std::copy(g1.begin(), g1.end(), g_.begin());
    // resting events: released when the free step left the guard on its armed side, else held
    bool restored = false;
    for (std::size_t k = 0; k < ne_; ++k) {
        if (!resting_[k]) continue;
        if (armed_side(k, g_[k])) {
            resting_[k] = 0;
            --resting_count_;
            armed_[k] = 1;
            arm_time_[k] = t1;
            for (std::size_t i = 0; i < n_; ++i)
                if (held_by_[i] == k) held_by_[i] = ne_;
        } else {
            for (std::size_t i = 0; i < n_; ++i)
                if (held_by_[i] == k) {
                    q1[i] = held_q_[i];
                    v1[i] = 0;
                    restored = true;
                }
        }
    }
    if (restored) {
        sys_.event_guards(t1, q1, v1, g_);
        out.moved = true;
        a1 = {}; // at the state before the hold
    }
    if (!rearm(g_.data(), t1)) return out;

    // the crossings, on the integrator's extension of the step or its Hermite arc
    std::optional<HermiteStep> hermite;
    if (!extension) {
        if (a0.empty()) sys_.accelerations(t0_, q0_, v0_, a0_);
        else std::copy(a0.begin(), a0.end(), a0_.begin());
        if (a1.empty()) sys_.accelerations(t1, q1, v1, a1_);
        else std::copy(a1.begin(), a1.end(), a1_.begin());
        hermite.emplace(t0_, t1, q0_, v0_, a0_, q1, v1, a1_);
    }
    auto arc_at = [&](double t, std::span<double> q, std::span<double> v) {
        if (extension) (*extension)(t, q, v);
        else hermite->at(t, q, v);
    };
    // the guards at t1 (g_ is reused at the event times)
    std::copy(g_.begin(), g_.end(), g_end_.begin());
    double from = t0_; // crossings are looked for after this: t0_, or the last event that changed nothing
    for (;;) {
        double te = t1, bracket = opt_.time_tolerance;
        for (std::size_t k = 0; k < ne_; ++k) {
            if (!armed_[k] || resting_[k] || armed_side(k, g_end_[k])) continue;
            auto guard = [&](double t) {
                arc_at(t, qe_, ve_);
                sys_.event_guards(t, qe_, ve_, g_left_);
                return g_left_[k];
            };
            const double left = std::min(std::max(arm_time_[k], from), t1);
            double gl = guard(left);
            if (!armed_side(k, gl) || left >= t1) {
                // the arc disagrees with what armed it (within its error): the crossing is at left
                if (left < te) te = left;
                continue;
            }
            const Crossing c = locate_crossing(guard, left, t1, gl, g_end_[k], opt_.time_tolerance);
            if (c.time < te) {
                te = c.time;
                bracket = std::max(c.hi - c.lo, opt_.time_tolerance);
            }
        }
        // the state at t_e, and who fires: every armed event across there
        arc_at(te, qe_, ve_);
        sys_.event_guards(te, qe_, ve_, g_);
        bool stop = false, fired_any = false;
        for (std::size_t k = 0; k < ne_; ++k) {
            fired_[k] = armed_[k] && !resting_[k] && !armed_side(k, g_[k]);
            fired_any = fired_any || fired_[k];
            if (fired_[k] && sys_.event_stops[k]) stop = true;
        }
        if (!fired_any) return out; // cannot happen: the earliest crossing is across at its own time
        std::copy(qe_.begin(), qe_.end(), qp_.begin());
        std::copy(ve_.begin(), ve_.end(), vp_.begin());
        bool changed = stop;
        if (!stop) {
            for (std::size_t k = 0; k < ne_; ++k) {
                if (!fired_[k]) continue;
                std::copy(qe_.begin(), qe_.end(), qk_.begin());
                std::copy(ve_.begin(), ve_.end(), vk_.begin());
                sys_.apply_event(k, te, qk_, vk_);
                for (std::size_t i = 0; i < n_; ++i) {
                    if (qk_[i] != qe_[i]) qp_[i] = qk_[i];
                    if (vk_[i] != ve_[i]) {
                        vp_[i] = vk_[i];
                        if (opt_.rest_speed > 0 && std::fabs(vp_[i]) < opt_.rest_speed) {
                            vp_[i] = 0;
                            resting_count_ += resting_[k] ? 0 : 1;
                            resting_[k] = 1;
                            held_by_[i] = k;
                            changed = true;
                        }
                    }
                }
            }
            for (std::size_t i = 0; i < n_ && !changed; ++i)
                changed = std::bit_cast<std::uint64_t>(qp_[i]) != std::bit_cast<std::uint64_t>(qe_[i]) ||
                          std::bit_cast<std::uint64_t>(vp_[i]) != std::bit_cast<std::uint64_t>(ve_[i]);
            for (std::size_t i = 0; i < n_; ++i)
                if (held_by_[i] < ne_) held_q_[i] = qp_[i];
        }
        for (std::size_t k = 0; k < ne_; ++k)
            if (fired_[k]) log_.push_back({te, k, qp_, vp_});
        if (!changed) {
            // Actions that change nothing (an observing event, `x' = x'`): logged at t_e, the
            // world left where the integrator put it — the run is the one without the event,
            // bit for bit — and the rest of the step searched again from t_e.
            out.observed = true;
            rearm_after(te, bracket, t1, arc_at);
            std::copy(g_end_.begin(), g_end_.end(), g_.begin());
            from = te;
            if (!rearm(g_.data(), t1)) return out;
            continue;
        }
        out.fired = true;
        out.moved = true;
        w.time = te;
        std::copy(qp_.begin(), qp_.end(), q1.begin());
        std::copy(vp_.begin(), vp_.end(), v1.begin());
        if (stop) {
            stopped_ = true;
            out.stopped = true;
            return out;
        }
        // a fired event re-arms just after t_e on the Taylor arc of the new state
        bool accelerations = false;
        rearm_after(te, bracket, t1, [&](double t, std::span<double> q, std::span<double> v) {
            if (!accelerations) sys_.accelerations(te, qp_, vp_, ap_);
            accelerations = true;
            const double d = t - te;
            for (std::size_t i = 0; i < n_; ++i) {
                q[i] = qp_[i] + d * (vp_[i] + 0.5 * d * ap_[i]);
                v[i] = vp_[i] + d * ap_[i];
            }
        });
        return out;
    }
}

template <typename Arc>
void EventMonitor::rearm_after(double te, double bracket, double t1, Arc&& arc) {
    // every guard at the state after the event (qp_, vp_); a fired one is also looked at just
    // after t_e, on `arc`, from a few times the crossing bracket up to the step's end
    sys_.event_guards(te, qp_, vp_, g_);
    bool probe = false;
    for (std::size_t k = 0; k < ne_; ++k) {
        if (resting_[k]) {
            armed_[k] = 0;
            continue;
        }
        armed_[k] = armed_side(k, g_[k]) ? 1 : 0;
        arm_time_[k] = te;
        probe = probe || (fired_[k] && !armed_[k]);
    }
    if (probe && t1 > te) {
        for (double d = 4 * bracket; d <= t1 - te; d *= 2) {
            arc(te + d, qk_, vk_);
            sys_.event_guards(te + d, qk_, vk_, g_left_);
            bool pending = false;
            for (std::size_t k = 0; k < ne_; ++k) {
                if (!fired_[k] || armed_[k] || resting_[k]) continue;
                if (armed_side(k, g_left_[k])) {
                    armed_[k] = 1;
                    arm_time_[k] = te + d;
                } else pending = true;
            }
            if (!pending) break;
        }
    }
    for (std::size_t k = 0; k < ne_; ++k)
        if (fired_[k]) {
            ++events_this_run_step_;
            check_zeno(k, te);
        }
}

std::vector<Index> add_event_flags(Registry& flags, const LagrangianSystem& system, std::string_view prefix) {
    std::vector<Index> out;
    for (const std::string& name : system.event_names) out.push_back(flags.add(std::string(prefix) + name));
    return out;
}

std::size_t signal_events(const EventMonitor& monitor, std::size_t since, std::span<const Index> flags, FlagWorld& world) {
    const auto& log = monitor.log();
    if (flags.size() != monitor.system().n_events)
        throw std::invalid_argument("signal_events: " + std::to_string(flags.size()) + " flags for " +
                                    std::to_string(monitor.system().n_events) + " events");
    for (std::size_t i = since; i < log.size(); ++i) world.flags.set(flags[log[i].event], true);
    return log.size();
}

EventRule model_events_rule(std::string name, const LagrangianSystem& system, std::span<const Index> flags) {
    if (flags.size() != system.n_events)
        throw std::invalid_argument("model_events_rule: " + std::to_string(flags.size()) + " flags for " +
                                    std::to_string(system.n_events) + " events");
    const ComponentSet domain{std::vector<Index>(flags.begin(), flags.end())};
    if (domain.indices().size() != flags.size()) throw std::invalid_argument("model_events_rule: a flag given for two events");
    // the slice is in the order of domain.indices() (ascending): each position's flag and event
    std::vector<std::pair<Index, std::string>> by_slot;
    for (std::size_t k = 0; k < flags.size(); ++k) by_slot.emplace_back(flags[k], system.event_names[k]);
    std::sort(by_slot.begin(), by_slot.end());
    return EventRule{std::move(name), domain, {},
                     [](const FlagLit&, std::span<std::uint8_t> out) { std::fill(out.begin(), out.end(), 0); },
                     [by_slot](std::uint64_t tick, std::span<const std::uint8_t> slice, Phenomenon& events) {
                         for (std::size_t j = 0; j < slice.size(); ++j)
                             if (slice[j]) events.push_back(epsilon(by_slot[j].first, tick, by_slot[j].second + " fired"));
                     }};
}

void EventMonitor::save(ArchiveBytes& out) const {
    out.u64(n_).u64(ne_).u64(started_ ? 1 : 0).u64(stopped_ ? 1 : 0).u64(resting_count_);
    for (std::size_t k = 0; k < ne_; ++k) {
        out.u64(armed_[k]).u64(resting_[k]).f64(arm_time_[k]).u64(recent_[k].size());
        out.f64s(recent_[k].data(), recent_[k].size());
    }
    for (std::size_t i = 0; i < n_; ++i) out.u64(held_by_[i]).f64(held_q_[i]);
    out.u64(log_.size());
    for (const EventRecord& r : log_) {
        out.f64(r.time).u64(r.event);
        out.f64s(r.q.data(), n_).f64s(r.qdot.data(), n_);
    }
}

void EventMonitor::restore(ArchiveReader& in) {
    if (in.u64() != n_ || in.u64() != ne_)
        throw ArchiveError("the event monitor's snapshot is of a model with other coordinates or events");
    started_ = in.u64() != 0;
    stopped_ = in.u64() != 0;
    resting_count_ = in.u64();
    for (std::size_t k = 0; k < ne_; ++k) {
        armed_[k] = in.u64() != 0;
        resting_[k] = in.u64() != 0;
        arm_time_[k] = in.f64();
        const std::uint64_t m = in.u64();
        if (m > opt_.zeno_run) throw ArchiveError("the event monitor's snapshot keeps more firing times than zeno_run");
        recent_[k].resize(m);
        in.f64s(recent_[k].data(), m);
    }
    for (std::size_t i = 0; i < n_; ++i) {
        held_by_[i] = in.u64();
        if (held_by_[i] > ne_) throw ArchiveError("the event monitor's snapshot holds a coordinate by no event");
        held_q_[i] = in.f64();
    }
    const std::uint64_t m = in.u64();
    log_.clear();
    for (std::uint64_t j = 0; j < m; ++j) {
        EventRecord r;
        r.time = in.f64();
        r.event = in.u64();
        if (r.event >= ne_) throw ArchiveError("the event monitor's snapshot logs an event the model does not have");
        r.q.resize(n_);
        r.qdot.resize(n_);
        in.f64s(r.q.data(), n_);
        in.f64s(r.qdot.data(), n_);
        log_.push_back(std::move(r));
    }
}

void EventMonitor::check_zeno(std::size_t k, double t) {
    const std::string name = "event '" + sys_.event_names[k] + "'";
    if (events_this_run_step_ > opt_.max_events_per_step)
        throw ZenoError(name + " at t = " + time_text(t) + ": more than " + std::to_string(opt_.max_events_per_step) +
                        " events within one step of the run (Zeno behaviour: events accumulating in finite time); "
                        "a rest speed (--rest-speed) lets velocity resets below it end in rest");
    auto& times = recent_[k];
    times.push_back(t);
    if (times.size() > opt_.zeno_run) times.erase(times.begin());
    // with the remedy on, a chattering sequence is expected to end in rest: only the
    // per-step limit above applies
    if (times.size() < opt_.zeno_run || run_dt_ <= 0 || opt_.rest_speed > 0) return;
    double ratio = 0;
    for (std::size_t j = 2; j < times.size(); ++j) {
        const double before = times[j - 1] - times[j - 2], now = times[j] - times[j - 1];
        if (!(now <= 0.99 * before)) return;
        ratio = before > 0 ? now / before : 0;
    }
    const double last = times.back() - times[times.size() - 2];
    if (!(last < 0.1 * run_dt_)) return;
    throw ZenoError(name + " at t = " + time_text(t) + ": fired " + std::to_string(opt_.zeno_run) +
                    " times at shrinking intervals, the last " + time_text(last) +
                    " s (Zeno behaviour: infinitely many events before t = " + time_text(t + last * ratio / (1 - ratio)) +
                    "); a rest speed (--rest-speed) lets velocity resets below it end in rest");
}

} // namespace phynjo::runtime
