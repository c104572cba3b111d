#pragma once
// Internal: exact arithmetic on Number nodes, with an int64 fast path.
#include "pool_impl.hpp"

namespace phynjo::cas::detail {

/// A span over a small_vector (Boost 1.74's iterators are not C++20 contiguous iterators).
template <typename V>
std::span<const Expr> as_span(const V& v) {
    return {v.data(), v.size()};
}

Expr make_number(const mpq_class& v);
Expr make_int_slow(std::int64_t v);
/// The integer v (from the pool's cache of small integers when |v| ≤ 64).
inline Expr make_int(std::int64_t v) {
    if (v >= -PoolImpl::small_cache && v <= PoolImpl::small_cache) {
        const Expr e = pool().small_ints[v + PoolImpl::small_cache];
        if (!e.is_null()) return e;
    }
    return make_int_slow(v);
}
Expr num_add(Expr a, Expr b);
Expr num_mul(Expr a, Expr b);
Expr num_neg(Expr a);
Expr num_inv(Expr a); // throws DomainError on 0
int num_sign(Expr a) noexcept;
int num_cmp(Expr a, Expr b) noexcept;
bool num_is_integer(Expr a) noexcept;
/// b^e for Numbers b, e: a Number when exact, otherwise a canonical Pow (or Mul of a
/// rational and a Pow). Throws DomainError (0^negative) or LimitError (too large).
Expr num_pow(Expr b, Expr e);
/// c·x for a Number c and any x: mul({c, x}) (the same node, the same work charged) without
/// sorting and merging factors — a canonical x needs neither.
Expr times(Expr c, Expr x);
/// coef · Π factors when the factors are already a canonical Mul's: none a Number or a Mul,
/// sums primitive, bases strictly increasing in `compare` order. mul({coef, factors…}) (the
/// same node, the same work charged) without sorting and merging.
Expr mul_sorted(Expr coef, std::span<const Expr> factors);

} // namespace phynjo::cas::detail
