#pragma once
// Internal: the pool's storage and intern table, and the helpers every factory uses.
#include "phynjo/cas/errors.hpp"
#include "phynjo/cas/expr.hpp"
#include "phynjo/cas/node_map.hpp"
#include "phynjo/cas/pool.hpp"

#include <cassert>
#include <string>
#include <memory_resource>
#include <utility>
#include <vector>

namespace phynjo::cas::detail {

// ---- structural hashing: fixed constants, so hashes (and hence the canonical order) are
// identical across runs, compilers and platforms.
inline constexpr std::uint64_t mix(std::uint64_t h, std::uint64_t v) noexcept {
    h ^= v + 0x9E3779B97F4A7C15ULL + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ULL;
    return h ^ (h >> 31);
}
inline std::uint64_t hash_bytes(std::string_view s) noexcept {
    std::uint64_t h = 0xCBF29CE484222325ULL; // FNV-1a
    for (unsigned char c : s) h = (h ^ c) * 0x100000001B3ULL;
    return h;
}

/// What identifies a node: the fields the intern table compares.
struct NodeKey {
    Kind kind;
    std::uint8_t sub = 0;
    std::span<const Expr> args{};
    std::span<const Expr> coefs{};
    Expr number{};
    std::string_view name{};
    const mpq_class* value = nullptr; // Number, not small
    bool small = false;
    std::int64_t small_value = 0;
    std::uint64_t hash = 0;
};

std::uint64_t hash_of(const NodeKey& k) noexcept;

struct PoolImpl {
    explicit PoolImpl(std::uint32_t id);
    ~PoolImpl();

    /// The unique node with this structure, made if new. Children must belong to this pool.
    const Node* intern(NodeKey& key);

    std::uint32_t id;
    std::pmr::monotonic_buffer_resource arena{1 << 16};
    /// A slot of the intern table: the node's hash beside it, so that a probe past another
    /// node compares two integers instead of loading that node (a cache miss).
    struct Slot {
        std::uint64_t hash = 0;
        const Node* node = nullptr;
    };
    std::vector<Slot> table; // open addressing, power-of-two capacity, linear probing
    std::size_t count = 0;
    std::size_t node_limit = limits::max_nodes;
    std::uint64_t work = 0; ///< terms and factors processed by add and mul
    std::uint64_t work_limit = limits::max_work;

    /// Counts `n` units of work; throws LimitError past the budget.
    void charge(std::size_t n) {
        work += n;
        if (work > work_limit)
            throw LimitError("computation too large: more than " + std::to_string(work_limit) +
                             " terms and factors processed");
    }
    std::vector<mpq_class*> big_numbers; // destroyed with the pool

    static constexpr int small_cache = 64;
    Expr small_ints[2 * small_cache + 1]{};
    Expr pi, time;

    FlatTable<std::pair<const Node*, const Node*>, Expr, NodePairHash> diff_memo{1 << 12};
    NodeMap<Expr> dt_memo{1 << 8};
    /// Memos of the bottom-up rewrites, each a function of the node alone (transform.cpp):
    /// kept across calls, so that simplify's second look, and every expression sharing
    /// subexpressions with one done before, costs a lookup.
    NodeMap<Expr> trig_memo{1 << 10}, expand_memo{1 << 10}, horner_memo{1 << 10};
    /// The printers' memos: a node's display-order key, a Number's C++ literal of |value|.
    NodeMap<std::string> print_keys{1 << 10};
    NodeMap<std::string> cpp_abs_literals{1 << 6};

private:
    void grow();
    const Node* make(const NodeKey& key);
};

/// The base of a product's factor: b for b^e, the factor itself otherwise (the key by which a
/// canonical Mul sorts its factors).
inline Expr base_of(Expr f) noexcept { return f.kind() == Kind::Pow ? f.args()[0] : f; }

/// The calling thread's current pool, if a PoolScope set one. A function-local thread_local
/// with a constant initializer: no guard and no TLS wrapper call (an `extern thread_local`
/// goes through one, which UBSan reads as a null load in GCC 12).
inline Pool*& current_pool() noexcept {
    static thread_local Pool* p = nullptr;
    return p;
}

/// The current pool's storage: inline, since every factory asks for it (a thread-local load
/// and a branch; the thread's default pool out of line).
inline PoolImpl& pool() {
    if (Pool* p = current_pool()) return p->impl();
    return Pool::current().impl();
}

} // namespace phynjo::cas::detail
