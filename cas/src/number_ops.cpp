#include "number_ops.hpp"

#include "phynjo/cas/errors.hpp"

#include <limits>
#include <string>

namespace phynjo::cas::detail {

namespace {
bool fits_small(const mpq_class& v) noexcept {
    return v.get_den() == 1 && mpz_sizeinbase(v.get_num_mpz_t(), 2) <= 62;
}
void check_size(const mpq_class& v) {
    if (mpz_sizeinbase(v.get_num_mpz_t(), 2) > limits::max_number_bits ||
        mpz_sizeinbase(v.get_den_mpz_t(), 2) > limits::max_number_bits)
        throw LimitError("exact number too large (more than " + std::to_string(limits::max_number_bits) + " bits)");
}
Expr intern_small(std::int64_t v) {
    NodeKey k{Kind::Number};
    k.small = true;
    k.small_value = v;
    return Expr(pool().intern(k));
}
constexpr std::int64_t small_limit = std::int64_t{1} << 61; // |v| < 2^61: sums and products checked
} // namespace

Expr make_int_slow(std::int64_t v) {
    if (v >= -PoolImpl::small_cache && v <= PoolImpl::small_cache) {
        PoolImpl& p = pool();
        Expr& slot = p.small_ints[v + PoolImpl::small_cache];
        if (slot.is_null()) slot = intern_small(v);
        return slot;
    }
    if (v > -small_limit && v < small_limit) return intern_small(v);
    return make_number(mpq_class(mpz_class(std::to_string(v))));
}

Expr make_number(const mpq_class& v) {
    if (fits_small(v)) {
        const long s = v.get_num().get_si();
        if (s > -small_limit && s < small_limit) return make_int(s);
    }
    check_size(v);
    NodeKey k{Kind::Number};
    k.value = &v;
    return Expr(pool().intern(k));
}

Expr num_add(Expr a, Expr b) {
    if (a.is_zero()) return b;
    if (b.is_zero()) return a;
    if (a->small && b->small) return make_int(a->small_value + b->small_value); // |each| < 2^61
    return make_number(a.value() + b.value());
}
Expr num_mul(Expr a, Expr b) {
    if (a.is_one()) return b; // the common case in mul and add: a coefficient of 1
    if (b.is_one()) return a;
    if (a->small && b->small) {
        std::int64_t r;
        if (!__builtin_mul_overflow(a->small_value, b->small_value, &r)) return make_int(r);
    }
    return make_number(a.value() * b.value());
}
Expr num_neg(Expr a) {
    if (a->small) return make_int(-a->small_value);
    return make_number(-a.value());
}
Expr num_inv(Expr a) {
    if (a.is_zero()) throw DomainError("division by zero");
    if (a->small && (a->small_value == 1 || a->small_value == -1)) return a;
    return make_number(1 / a.value());
}
int num_sign(Expr a) noexcept {
    if (a->small) return (a->small_value > 0) - (a->small_value < 0);
    return sgn(a.value());
}
int num_cmp(Expr a, Expr b) noexcept {
    if (a->small && b->small) return (a->small_value > b->small_value) - (a->small_value < b->small_value);
    return cmp(a.value(), b.value());
}
bool num_is_integer(Expr a) noexcept { return a->small || a.value().get_den() == 1; }

namespace {
mpz_class ipow(const mpz_class& b, unsigned long n) {
    mpz_class r;
    mpz_pow_ui(r.get_mpz_t(), b.get_mpz_t(), n);
    return r;
}
Expr pow_node(Expr b, Expr e) {
    const Expr args[2] = {b, e};
    NodeKey k{Kind::Pow};
    k.args = args;
    return Expr(pool().intern(k));
}
} // namespace

Expr num_pow(Expr b, Expr e) {
    if (e.is_zero()) return make_int(1);
    if (e.is_one()) return b;
    if (b.is_one()) return b;
    if (b.is_zero()) {
        if (num_sign(e) < 0) throw DomainError("division by zero (0 raised to a negative power)");
        return b;
    }
    const mpq_class& bv = b.value();
    const mpq_class& ev = e.value();
    if (num_is_integer(e)) {
        if (b->small && (b->small_value == -1)) return make_int(mpz_odd_p(ev.get_num_mpz_t()) ? -1 : 1);
        const std::size_t bits = std::max(mpz_sizeinbase(bv.get_num_mpz_t(), 2), mpz_sizeinbase(bv.get_den_mpz_t(), 2));
        const mpz_class n = abs(ev.get_num());
        if (n > mpz_class(static_cast<unsigned long>(limits::max_number_bits)) ||
            (bits > 1 && (bits - 1) * n.get_ui() > limits::max_number_bits))
            throw LimitError("exact power too large (more than " + std::to_string(limits::max_number_bits) + " bits)");
        const unsigned long un = n.get_ui();
        mpq_class r(ipow(bv.get_num(), un), ipow(bv.get_den(), un));
        r.canonicalize();
        if (sgn(ev) < 0) {
            r = 1 / r;
        }
        return make_number(r);
    }
    // Non-integer exponent p/q (q > 1).
    if (sgn(bv) > 0) {
        const mpz_class& p = ev.get_num();
        const mpz_class& q = ev.get_den();
        if (q.fits_ulong_p()) {
            mpz_class rn, rd;
            const int exact_n = mpz_root(rn.get_mpz_t(), bv.get_num_mpz_t(), q.get_ui());
            const int exact_d = mpz_root(rd.get_mpz_t(), bv.get_den_mpz_t(), q.get_ui());
            if (exact_n && exact_d) {
                mpq_class root(rn, rd);
                root.canonicalize();
                return num_pow(make_number(root), make_number(mpq_class(p)));
            }
        }
        // b^(k + r) = b^k · b^r with k = floor(e), 0 < r < 1; and for b = n/d,
        // b^r = n^r · d^(−r) = (1/d) · n^r · d^(1−r), so every Pow has an integer base.
        mpz_class k;
        mpz_fdiv_q(k.get_mpz_t(), p.get_mpz_t(), q.get_mpz_t());
        const mpq_class r = ev - mpq_class(k);
        if (k == 0 && bv.get_den() == 1) return pow_node(b, e); // already canonical
        const Expr kpart = k == 0 ? make_int(1) : num_pow(b, make_number(mpq_class(k)));
        const Expr num_base = make_number(mpq_class(bv.get_num()));
        const Expr den_base = make_number(mpq_class(bv.get_den()));
        std::vector<Expr> factors{kpart};
        // integer bases: each either has an exact root or becomes a canonical Pow
        if (!num_base.is_one()) factors.push_back(num_pow(num_base, make_number(r)));
        if (!den_base.is_one()) {
            factors.push_back(num_inv(den_base));
            factors.push_back(num_pow(den_base, make_number(1 - r)));
        }
        return mul(factors);
    }
    // Negative base, non-integer exponent: not real; kept unevaluated.
    return pow_node(b, e);
}

} // namespace phynjo::cas::detail
