#pragma once
/// \file
/// The generic Process — act | seq | par — and its one interpreter, shared by the numeric
/// layer (NumericWorkflow) and the Boolean event layer (EventWorkflow).
///
/// Semantics. `act(a)` applies action a and takes one tick. `seq(p1, …, pn)` runs p1, then
/// p2 on its result, and so on: its ticks add up. `par(p1, …, pn)` runs every branch on the
/// same input and merges their results in one sub-step: its ticks are the longest branch's.
/// `par` is only built when no branch writes an entry that another branch writes or reads
/// (checked once, at construction, by DomainOverlapError); hence reading the shared input
/// and reading the partly updated world are the same, every branch may run on its own
/// thread, and the result is bit-identical to running the branches in order.
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/executor.hpp"
#include "phynjo/runtime/core/world.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// A time-stamped event emitted by an event rule.
struct Event {
    std::uint64_t tick = 0;
    Index component = 0;
    std::string what;
    friend bool operator==(const Event&, const Event&) = default;
};
/// The events of a run, in order.
using Phenomenon = std::vector<Event>;

/// What an action sees besides the world.
struct StepContext {
    double dt = 0;                    ///< the step, s
    std::uint64_t tick = 0;           ///< the tick at which this action runs
    Phenomenon* events = nullptr;     ///< where emitted events go
};

/// The atom of a process: a named in-place update of a world with declared domains.
template <typename W>
struct Action {
    std::string name;
    Domain writes; ///< the entries it may change (its domain)
    Domain reads;  ///< the entries it may read besides its writes
    std::function<void(W&, const StepContext&)> run;
    std::shared_ptr<const Layout> layout; ///< for naming entries in messages
};

template <typename W>
class Process {
public:
    enum class Kind { Act, Seq, Par };

    static Process act(Action<W> a) {
        auto n = std::make_shared<Node>();
        n->kind = Kind::Act;
        n->writes = a.writes;
        n->reads = a.reads;
        n->names = {a.name};
        n->layout = a.layout;
        n->action = std::make_shared<Action<W>>(std::move(a));
        return Process(std::move(n));
    }
    static Process seq(std::vector<Process> parts) { return compose(Kind::Seq, std::move(parts)); }
    /// Throws DomainOverlapError when two branches share a written entry, or one writes
    /// what another reads.
    static Process par(std::vector<Process> parts) {
        for (std::size_t i = 0; i < parts.size(); ++i)
            for (std::size_t j = i + 1; j < parts.size(); ++j) check_disjoint(parts[i], parts[j]);
        return compose(Kind::Par, std::move(parts));
    }

    [[nodiscard]] Kind kind() const noexcept { return node_->kind; }
    [[nodiscard]] const Domain& writes() const noexcept { return node_->writes; }
    [[nodiscard]] const Domain& reads() const noexcept { return node_->reads; }
    [[nodiscard]] const std::vector<Process>& parts() const noexcept { return node_->parts; }
    [[nodiscard]] const Action<W>& action() const noexcept { return *node_->action; }
    /// The names of the actions inside, in order.
    [[nodiscard]] const std::vector<std::string>& names() const noexcept { return node_->names; }

private:
    struct Node {
        Kind kind = Kind::Act;
        Domain writes, reads;
        std::vector<Process> parts;
        std::shared_ptr<const Action<W>> action;
        std::vector<std::string> names;
        std::shared_ptr<const Layout> layout;
    };
    explicit Process(std::shared_ptr<const Node> n) : node_(std::move(n)) {}

    static Process compose(Kind k, std::vector<Process> parts) {
        if (parts.empty()) throw Error(k == Kind::Seq ? "seq of nothing" : "par of nothing");
        if (parts.size() == 1) return parts[0];
        auto n = std::make_shared<Node>();
        n->kind = k;
        for (const Process& p : parts) {
            n->writes = n->writes | p.writes();
            n->reads = n->reads | p.reads();
            n->names.insert(n->names.end(), p.names().begin(), p.names().end());
            if (!n->layout) n->layout = p.node_->layout;
        }
        n->parts = std::move(parts);
        return Process(std::move(n));
    }

    static std::string joined(const std::vector<std::string>& names) {
        std::string s;
        for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
        return s.empty() ? "(unnamed)" : s;
    }

    static void check_disjoint(const Process& a, const Process& b) {
        const Layout* layout = a.node_->layout ? a.node_->layout.get() : b.node_->layout.get();
        auto describe = [&](const std::vector<std::pair<FieldId, Index>>& entries, std::vector<std::string>& out) {
            std::string s;
            for (const auto& [f, c] : entries) {
                out.push_back(layout ? layout->describe(f, c) : std::to_string(f) + ":" + std::to_string(c));
                if (out.size() <= 8) s += (s.empty() ? "" : ", ") + out.back();
            }
            if (out.size() > 8) s += ", … (" + std::to_string(out.size()) + " in all)";
            return s;
        };
        std::vector<std::string> shared;
        if (auto ww = overlap(a.writes(), b.writes()); !ww.empty()) {
            const std::string s = describe(ww, shared);
            throw DomainOverlapError("par: branches [" + joined(a.names()) + "] and [" + joined(b.names()) +
                                         "] both write " + s,
                                     shared);
        }
        for (const auto& [x, y] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
            if (auto wr = overlap(x->writes(), y->reads()); !wr.empty()) {
                const std::string s = describe(wr, shared);
                throw DomainOverlapError("par: branch [" + joined(x->names()) + "] writes " + s + ", which branch [" +
                                             joined(y->names()) + "] reads",
                                         shared);
            }
        }
    }

    std::shared_ptr<const Node> node_;
};

/// Compiles a Process once into a flat program and runs it: `step` allocates nothing
/// (beyond events that rules emit), and runs `par` branches on the executor's threads.
template <typename W>
class Interpreter {
public:
    explicit Interpreter(const Process<W>& process, Executor* executor = nullptr) : executor_(executor) {
        root_ = compile(process);
        branch_events_.resize(instrs_.size());
    }

    /// One application of the process: world ← process(dt, world). Advances world.tick by
    /// the process's ticks and world.time by dt (when W has them).
    void step(W& world, double dt, Phenomenon* events = nullptr) {
        StepContext ctx{dt, world.tick, events};
        const std::uint64_t ticks = run(root_, world, ctx);
        world.tick += ticks;
        if constexpr (requires { world.time; }) world.time += dt;
    }

    /// Checked mode (for tests and debugging; slow, allocates): after every action, verifies
    /// that nothing outside its write domain changed, else throws DomainViolation.
    void set_checked(bool on) noexcept { checked_ = on; }

private:
    struct Instr {
        typename Process<W>::Kind kind;
        std::shared_ptr<const Action<W>> action;
        std::vector<std::uint32_t> children;
    };

    std::uint32_t compile(const Process<W>& p) {
        Instr in{p.kind(), nullptr, {}};
        if (p.kind() == Process<W>::Kind::Act) in.action = std::make_shared<Action<W>>(p.action());
        std::vector<std::uint32_t> kids;
        for (const auto& c : p.parts()) kids.push_back(compile(c));
        in.children = std::move(kids);
        instrs_.push_back(std::move(in));
        return static_cast<std::uint32_t>(instrs_.size() - 1);
    }

    std::uint64_t run(std::uint32_t at, W& world, const StepContext& ctx) {
        const Instr& in = instrs_[at];
        switch (in.kind) {
        case Process<W>::Kind::Act:
            if (checked_) run_checked(*in.action, world, ctx);
            else in.action->run(world, ctx);
            return 1;
        case Process<W>::Kind::Seq: {
            std::uint64_t ticks = 0;
            for (std::uint32_t c : in.children) {
                StepContext sub = ctx;
                sub.tick = ctx.tick + ticks;
                ticks += run(c, world, sub);
            }
            return ticks;
        }
        case Process<W>::Kind::Par: {
            // Every branch starts at the same tick; events of branch i go to its own buffer
            // and are appended in branch order, so the log does not depend on threads.
            auto& buffers = branch_events_[at];
            if (ctx.events && buffers.size() < in.children.size()) buffers.resize(in.children.size());
            std::uint64_t ticks[64];
            const std::size_t n = in.children.size();
            std::vector<std::uint64_t> many;
            std::uint64_t* t = ticks;
            if (n > 64) { // rare: wide par nodes allocate their tick slots
                many.resize(n);
                t = many.data();
            }
            auto branch = [&](unsigned i) {
                StepContext sub = ctx;
                if (ctx.events) {
                    buffers[i].clear();
                    sub.events = &buffers[i];
                }
                t[i] = run(in.children[i], world, sub);
            };
            if (executor_ && !checked_) executor_->fork_join(static_cast<unsigned>(n), branch);
            else
                for (unsigned i = 0; i < n; ++i) branch(i);
            std::uint64_t longest = 0;
            for (std::size_t i = 0; i < n; ++i) {
                longest = std::max(longest, t[i]);
                if (ctx.events) ctx.events->insert(ctx.events->end(), buffers[i].begin(), buffers[i].end());
            }
            return longest;
        }
        }
        return 0;
    }

    /// first_change_outside(before, after, writes) is declared beside each world kind
    /// (world.hpp, event.hpp) and found by argument-dependent lookup.
    void run_checked(const Action<W>& a, W& world, const StepContext& ctx) {
        const W before = world;
        a.run(world, ctx);
        if (auto where = first_change_outside(before, world, a.writes))
            throw DomainViolation("rule '" + a.name + "' changed " + *where + ", outside its declared domain");
    }

    std::vector<Instr> instrs_;
    std::uint32_t root_ = 0;
    Executor* executor_ = nullptr;
    bool checked_ = false;
    std::vector<std::vector<Phenomenon>> branch_events_;
};

} // namespace phynjo::runtime
