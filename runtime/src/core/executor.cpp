#include "phynjo/runtime/core/executor.hpp"

#include <exception>

namespace phynjo::runtime {

namespace {
thread_local bool inside_task = false;
}

Executor::Executor(unsigned threads) {
    for (unsigned i = 1; i < threads; ++i) {
        workers_.push_back(std::make_unique<Worker>());
        Worker& w = *workers_.back();
        w.thread = std::thread([this, &w] { run_worker(w); });
    }
}

Executor::~Executor() {
    stop_.store(true);
    for (auto& w : workers_) {
        w->go.fetch_add(1);
        w->go.notify_one();
    }
    for (auto& w : workers_) w->thread.join();
}

void Executor::run_worker(Worker& w) {
    inside_task = true;
    std::uint32_t seen = 0;
    for (;;) {
        w.go.wait(seen);
        seen = w.go.load();
        if (stop_.load()) return;
        try {
            (*w.task)(w.index);
        } catch (...) {
            w.error = std::current_exception();
        }
        w.done.store(seen);
        w.done.notify_one();
    }
}

void Executor::fork_join(unsigned n, TaskRef task) {
    // Nested, concurrent or oversubscribed calls run in order on the calling thread: the
    // branches are disjoint, so the result is the same.
    bool expected = false;
    if (n <= 1 || inside_task || workers_.empty() || !busy_.compare_exchange_strong(expected, true)) {
        for (unsigned i = 0; i < n; ++i) task(i);
        return;
    }
    const unsigned k = std::min<unsigned>(n - 1, static_cast<unsigned>(workers_.size()));
    for (unsigned j = 0; j < k; ++j) {
        Worker& w = *workers_[j];
        w.task = &task;
        w.index = j + 1;
        w.error = nullptr;
        w.go.fetch_add(1);
        w.go.notify_one();
    }
    std::exception_ptr error;
    inside_task = true;
    try {
        task(0);
        for (unsigned i = k + 1; i < n; ++i) task(i); // more branches than workers
    } catch (...) {
        error = std::current_exception();
    }
    inside_task = false;
    for (unsigned j = 0; j < k; ++j) {
        Worker& w = *workers_[j];
        const std::uint32_t target = w.go.load();
        for (std::uint32_t d = w.done.load(); d != target; d = w.done.load()) w.done.wait(d);
        if (w.error && !error) error = w.error;
    }
    busy_.store(false);
    if (error) std::rethrow_exception(error);
}

} // namespace phynjo::runtime
