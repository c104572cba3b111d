#pragma once
/// \file
/// A fork-join thread pool for the branches of `par`. Dispatch and join use C++20 atomic
/// wait/notify: no allocation, no locks on the hot path.
#include <atomic>
#include <cstddef>
#include <memory>
#include <thread>
#include <type_traits>
#include <vector>

namespace phynjo::runtime {

/// A non-owning reference to a callable `void(unsigned)`.
class TaskRef {
public:
    template <typename F>
    TaskRef(F& f) noexcept // NOLINT: implicit on purpose
        : object_(static_cast<void*>(std::addressof(f))), call_([](void* o, unsigned i) { (*static_cast<F*>(o))(i); }) {}
    void operator()(unsigned i) const { call_(object_, i); }

private:
    void* object_;
    void (*call_)(void*, unsigned);
};

class Executor {
public:
    /// `threads` in all, the calling thread included (so threads − 1 workers). 0 or 1: no workers.
    explicit Executor(unsigned threads);
    ~Executor();
    Executor(const Executor&) = delete;
    Executor& operator=(const Executor&) = delete;

    [[nodiscard]] unsigned threads() const noexcept { return static_cast<unsigned>(workers_.size()) + 1; }

    /// Runs task(0) … task(n − 1), task(0) on the calling thread and the others on workers
    /// when enough are free; returns when all are done. Nested calls from inside a task run
    /// their tasks on the calling thread. The first exception thrown by a task is rethrown.
    void fork_join(unsigned n, TaskRef task);

private:
    struct Worker {
        std::atomic<std::uint32_t> go{0};   // incremented to start a job
        std::atomic<std::uint32_t> done{0}; // set equal to go when finished
        const TaskRef* task = nullptr;
        unsigned index = 0;
        std::exception_ptr error;
        std::thread thread;
    };
    void run_worker(Worker& w);
    std::vector<std::unique_ptr<Worker>> workers_;
    std::atomic<bool> stop_{false};
    std::atomic<bool> busy_{false};
};

} // namespace phynjo::runtime
