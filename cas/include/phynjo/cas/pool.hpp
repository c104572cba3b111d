#pragma once
/// \file
/// The arena that owns interned expression nodes.
#include <cstddef>
#include <cstdint>
#include <memory>

namespace phynjo::cas {

namespace detail {
struct PoolImpl;
}

/// Owns every node made while it is the current pool of a thread, the intern table that
/// makes equal structure one node, and the memo tables of derivatives. Nodes live as long
/// as their pool. Each thread has a default pool; `PoolScope` makes another one current,
/// for example to free a whole compilation at once or to measure without warm caches.
///
/// A pool is not synchronized: build expressions of one pool on one thread at a time.
/// Finished expressions are immutable and may be read from any thread.
class Pool {
public:
    Pool();
    ~Pool();
    Pool(const Pool&) = delete;
    Pool& operator=(const Pool&) = delete;

    /// The current pool of the calling thread.
    static Pool& current();
    /// Number of interned nodes.
    [[nodiscard]] std::size_t size() const noexcept;
    /// Bytes held by the arena.
    [[nodiscard]] std::size_t bytes() const noexcept;
    [[nodiscard]] std::uint32_t id() const noexcept;
    /// Forgets memoized derivatives and rewrites (expand, trig, Horner, print keys; the nodes stay).
    void clear_memo() noexcept;
    /// The most distinct nodes this pool may hold (default limits::max_nodes); making one
    /// more throws LimitError, so that no input can run a computation without bound.
    void set_node_limit(std::size_t n) noexcept;
    [[nodiscard]] std::size_t node_limit() const noexcept;
    /// The budget on work (limits::max_work by default) and the work done so far.
    void set_work_limit(std::uint64_t n) noexcept;
    [[nodiscard]] std::uint64_t work() const noexcept;

    detail::PoolImpl& impl() noexcept { return *impl_; }

private:
    std::unique_ptr<detail::PoolImpl> impl_;
};

/// Makes `pool` the calling thread's current pool until the scope ends.
class PoolScope {
public:
    explicit PoolScope(Pool& pool) noexcept;
    ~PoolScope();
    PoolScope(const PoolScope&) = delete;
    PoolScope& operator=(const PoolScope&) = delete;

private:
    Pool* previous_;
};

} // namespace phynjo::cas
