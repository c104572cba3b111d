#include "pool_impl.hpp"

#include <atomic>
#include <bit>
#include <cstring>
#include <string>

namespace phynjo::cas {
namespace detail {

namespace {
std::atomic<std::uint32_t> next_pool_id{1};

bool equal(const NodeKey& k, const Node& n) noexcept {
    if (n.hash != k.hash || n.kind != k.kind || n.sub != k.sub || n.nargs != k.args.size()) return false;
    switch (k.kind) {
    case Kind::Number:
        if (n.small != k.small) return false;
        return k.small ? n.small_value == k.small_value : *n.value == *k.value;
    case Kind::Symbol: return n.name == k.name;
    case Kind::Constant: return true;
    case Kind::TimeDerivative:
    case Kind::Function:
    case Kind::Pow:
    case Kind::Mul:
    case Kind::Add:
        if (n.number != k.number) return false;
        for (std::size_t i = 0; i < k.args.size(); ++i)
            if (n.args[i] != k.args[i]) return false;
        if (k.kind == Kind::Add)
            for (std::size_t i = 0; i < k.coefs.size(); ++i)
                if (n.coefs[i] != k.coefs[i]) return false;
        return true;
    }
    return false;
}
} // namespace

std::uint64_t hash_of(const NodeKey& k) noexcept {
    std::uint64_t h = mix(0x5851F42D4C957F2DULL, static_cast<std::uint64_t>(k.kind) * 131 + k.sub);
    switch (k.kind) {
    case Kind::Number:
        if (k.small) return mix(h, static_cast<std::uint64_t>(k.small_value));
        {
            const mpz_srcptr num = k.value->get_num_mpz_t();
            const mpz_srcptr den = k.value->get_den_mpz_t();
            h = mix(h, static_cast<std::uint64_t>(mpz_sgn(num) + 7));
            for (std::size_t i = 0, n = mpz_size(num); i < n; ++i) h = mix(h, mpz_getlimbn(num, i));
            h = mix(h, 0xABCDEF);
            for (std::size_t i = 0, n = mpz_size(den); i < n; ++i) h = mix(h, mpz_getlimbn(den, i));
            return h;
        }
    case Kind::Symbol: return mix(h, hash_bytes(k.name));
    case Kind::Constant: return h;
    case Kind::TimeDerivative:
    case Kind::Function:
    case Kind::Pow:
    case Kind::Mul:
    case Kind::Add:
        if (!k.number.is_null()) h = mix(h, k.number.hash());
        for (Expr a : k.args) h = mix(h, a.hash());
        for (Expr c : k.coefs) h = mix(h, c.hash());
        return h;
    }
    return h;
}

PoolImpl::PoolImpl(std::uint32_t id_) : id(id_) { table.assign(1 << 14, Slot{}); }

PoolImpl::~PoolImpl() {
    for (mpq_class* q : big_numbers) q->~mpq_class();
}

void PoolImpl::grow() {
    std::vector<Slot> bigger(table.size() * 2, Slot{});
    const std::size_t mask = bigger.size() - 1;
    for (const Slot& s : table) {
        if (!s.node) continue;
        std::size_t i = s.hash & mask;
        while (bigger[i].node) i = (i + 1) & mask;
        bigger[i] = s;
    }
    table.swap(bigger);
}

const Node* PoolImpl::make(const NodeKey& k) {
    void* mem = arena.allocate(sizeof(Node), alignof(Node));
    Node* n = new (mem) Node{};
    n->kind = k.kind;
    n->sub = k.sub;
    n->small = k.small;
    n->small_value = k.small_value;
    n->nargs = static_cast<std::uint32_t>(k.args.size());
    n->pool_id = id;
    n->hash = k.hash;
    n->number = k.number;
    if (k.kind == Kind::Number) {
        auto* q = new (arena.allocate(sizeof(mpq_class), alignof(mpq_class)))
            mpq_class(k.small ? mpq_class(static_cast<long>(k.small_value)) : *k.value);
        big_numbers.push_back(q);
        n->value = q;
    }
    if (!k.name.empty()) {
        char* s = static_cast<char*>(arena.allocate(k.name.size(), 1));
        std::memcpy(s, k.name.data(), k.name.size());
        n->name = std::string_view(s, k.name.size());
    }
    auto copy = [&](std::span<const Expr> src) -> const Expr* {
        if (src.empty()) return nullptr;
        Expr* dst = static_cast<Expr*>(arena.allocate(sizeof(Expr) * src.size(), alignof(Expr)));
        for (std::size_t i = 0; i < src.size(); ++i) {
            assert(src[i]->pool_id == id && "expression built from nodes of another pool");
            new (dst + i) Expr(src[i]);
        }
        return dst;
    };
    n->args = copy(k.args);
    n->coefs = copy(k.coefs);
    std::uint64_t mask = 0;
    if (k.kind == Kind::Symbol || k.kind == Kind::TimeDerivative) mask = std::uint64_t{1} << (k.hash & 63);
    else
        for (Expr a : k.args) mask |= a->atom_mask;
    n->atom_mask = mask;
    return n;
}

const Node* PoolImpl::intern(NodeKey& k) {
    k.hash = hash_of(k);
    std::size_t mask = table.size() - 1;
    std::size_t i = k.hash & mask;
    while (const Node* n = table[i].node) {
        if (table[i].hash == k.hash && equal(k, *n)) return n;
        i = (i + 1) & mask;
    }
    if (count >= node_limit)
        throw LimitError("expression too large: more than " + std::to_string(node_limit) +
                         " distinct subexpressions");
    const Node* n = make(k);
    table[i] = Slot{k.hash, n};
    if (++count * 2 > table.size()) grow();
    return n;
}

} // namespace detail

using detail::current_pool;

Pool::Pool() : impl_(std::make_unique<detail::PoolImpl>(detail::next_pool_id.fetch_add(1))) {}
Pool::~Pool() = default;

Pool& Pool::current() {
    if (Pool* p = current_pool()) return *p;
    thread_local Pool default_pool;
    return default_pool;
}
std::size_t Pool::size() const noexcept { return impl_->count; }
std::size_t Pool::bytes() const noexcept {
    // monotonic_buffer_resource does not report usage; approximate by node count.
    return impl_->count * (sizeof(Node) + 2 * sizeof(Expr)) + impl_->table.size() * sizeof(detail::PoolImpl::Slot);
}
std::uint32_t Pool::id() const noexcept { return impl_->id; }
void Pool::set_node_limit(std::size_t n) noexcept { impl_->node_limit = n; }
std::size_t Pool::node_limit() const noexcept { return impl_->node_limit; }
void Pool::set_work_limit(std::uint64_t n) noexcept { impl_->work_limit = n; }
std::uint64_t Pool::work() const noexcept { return impl_->work; }
void Pool::clear_memo() noexcept {
    impl_->diff_memo.clear();
    impl_->dt_memo.clear();
    impl_->trig_memo.clear();
    impl_->expand_memo.clear();
    impl_->horner_memo.clear();
    impl_->print_keys.clear();
    impl_->cpp_abs_literals.clear();
}

PoolScope::PoolScope(Pool& pool) noexcept : previous_(current_pool()) { current_pool() = &pool; }
PoolScope::~PoolScope() { current_pool() = previous_; }

} // namespace phynjo::cas
