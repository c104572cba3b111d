#pragma once
/// \file
/// `NodeMap<V>` and `NodeSet`: flat hash tables keyed by interned nodes, for the memos and
/// visited sets of the passes (diff, CSE, Horner, printing, …).
///
/// A node's structural hash is stored in it and well mixed, so a lookup is one load of the
/// hash, a mask and a linear probe over pointer-sized keys: no hashing, no allocation per
/// entry (std::unordered_map allocated a node for each, and the passes of phynjo-lagc spent
/// a fifth of their instructions in malloc and free). Insert-only: there is no erase, and a
/// pointer returned by `find` or `try_emplace` is valid until the next insertion.
#include "phynjo/cas/expr.hpp"

#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace phynjo::cas {

namespace detail {

/// Open addressing, power-of-two capacity, linear probing, at most half full. `Key` is a
/// pointer-like value whose default (null) marks an empty slot; `hash(k)` is well mixed.
template <class Key, class V, class Hash>
class FlatTable {
public:
    explicit FlatTable(std::size_t expected = 8) {
        const std::size_t cap = std::bit_ceil(expected < 8 ? std::size_t{16} : 2 * expected);
        slots_.resize(cap);
        mask_ = cap - 1;
    }
    /// The value stored for `k`, or null.
    [[nodiscard]] V* find(const Key& k) noexcept {
        for (std::size_t i = Hash{}(k) & mask_;; i = (i + 1) & mask_) {
            Slot& s = slots_[i];
            if (s.key == k) return &s.value;
            if (s.key == Key{}) return nullptr;
        }
    }
    [[nodiscard]] const V* find(const Key& k) const noexcept { return const_cast<FlatTable*>(this)->find(k); }
    /// Inserts (k, v) if k is absent; the value stored for k and whether it was inserted.
    std::pair<V*, bool> try_emplace(const Key& k, V v = V{}) {
        if (2 * (count_ + 1) > slots_.size()) grow();
        std::size_t i = Hash{}(k) & mask_;
        for (; slots_[i].key != Key{}; i = (i + 1) & mask_)
            if (slots_[i].key == k) return {&slots_[i].value, false};
        slots_[i].key = k;
        slots_[i].value = std::move(v);
        ++count_;
        return {&slots_[i].value, true};
    }
    V& operator[](const Key& k) { return *try_emplace(k).first; }
    [[nodiscard]] std::size_t size() const noexcept { return count_; }
    [[nodiscard]] bool empty() const noexcept { return count_ == 0; }
    void clear() {
        for (Slot& s : slots_) s = Slot{};
        count_ = 0;
    }

private:
    struct Slot {
        Key key{};
        V value{};
    };
    void grow() {
        std::vector<Slot> old(slots_.size() * 2);
        old.swap(slots_);
        mask_ = slots_.size() - 1;
        for (Slot& s : old) {
            if (s.key == Key{}) continue;
            std::size_t i = Hash{}(s.key) & mask_;
            while (slots_[i].key != Key{}) i = (i + 1) & mask_;
            slots_[i] = std::move(s);
        }
    }
    std::vector<Slot> slots_;
    std::size_t mask_ = 0;
    std::size_t count_ = 0;
};

struct NodeHash {
    std::size_t operator()(const Node* n) const noexcept { return static_cast<std::size_t>(Expr(n).hash()); }
};
struct NodePairHash {
    std::size_t operator()(const std::pair<const Node*, const Node*>& p) const noexcept {
        std::uint64_t h = Expr(p.first).hash() ^ (Expr(p.second).hash() * 0x9E3779B97F4A7C15ULL);
        h ^= h >> 32;
        return static_cast<std::size_t>(h);
    }
};
struct Empty {};

} // namespace detail

/// A map from nodes to values (see the file comment).
template <class V>
class NodeMap : public detail::FlatTable<const Node*, V, detail::NodeHash> {
public:
    using detail::FlatTable<const Node*, V, detail::NodeHash>::FlatTable;
    [[nodiscard]] V* find(Expr e) noexcept { return Base::find(e.get()); }
    [[nodiscard]] const V* find(Expr e) const noexcept { return Base::find(e.get()); }
    std::pair<V*, bool> try_emplace(Expr e, V v = V{}) { return Base::try_emplace(e.get(), std::move(v)); }
    V& operator[](Expr e) { return Base::operator[](e.get()); }
    [[nodiscard]] bool contains(Expr e) const noexcept { return find(e) != nullptr; }

private:
    using Base = detail::FlatTable<const Node*, V, detail::NodeHash>;
};

/// A set of nodes (see the file comment).
class NodeSet {
public:
    explicit NodeSet(std::size_t expected = 8) : table_(expected) {}
    /// Adds `e`; true if it was not there.
    bool insert(Expr e) { return table_.try_emplace(e.get()).second; }
    [[nodiscard]] bool contains(Expr e) const noexcept { return table_.find(e.get()) != nullptr; }
    [[nodiscard]] std::size_t size() const noexcept { return table_.size(); }

private:
    detail::FlatTable<const Node*, detail::Empty, detail::NodeHash> table_;
};

} // namespace phynjo::cas
