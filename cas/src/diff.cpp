// Differentiation by a variable and by time: one derivation core, two leaf rules.
#include "phynjo/cas/diff.hpp"

#include "number_ops.hpp"

#include <boost/container/small_vector.hpp>

#include <string>

namespace phynjo::cas {

using detail::as_span;


namespace {

/// d atan2(y, x) = (x·dy − y·dx)/(x² + y²).
Expr atan2_derivative(Expr y, Expr x, Expr dy, Expr dx) {
    if (dy.is_zero() && dx.is_zero()) return dy;
    return mul({add({mul({x, dy}), mul({Expr(-1), y, dx})}), pow(add({pow(x, Expr(2)), pow(y, Expr(2))}), Expr(-1))});
}

/// The derivative of a compound node, given `rec` for the derivative of its children:
/// sum rule, flattened product rule, power rule, chain rule.
template <typename Rec>
Expr derive_compound(Expr e, Rec&& rec) {
    switch (e.kind()) {
    case Kind::Add: {
        boost::container::small_vector<Expr, 16> terms;
        terms.reserve(e->nargs);
        for (std::uint32_t i = 0; i < e->nargs; ++i) {
            Expr d = rec(e.args()[i]);
            if (!d.is_zero()) terms.push_back(detail::times(e->coefs[i], d));
        }
        return terms.empty() ? Expr(0) : add(as_span(terms));
    }
    case Kind::Mul: {
        // d(c·u1·…·un) = Σ_i c·u1…u_{i-1}·u_i'·u_{i+1}…un
        const auto fs = e.args();
        boost::container::small_vector<Expr, 16> terms, factors(fs.size() + 1);
        terms.reserve(fs.size());
        for (std::size_t i = 0; i < fs.size(); ++i) {
            Expr d = rec(fs[i]);
            if (d.is_zero()) continue;
            // c, the other factors in order, u_i' (filled in place: GCC 12 warns, wrongly, on
            // push_back into the small vector here)
            std::size_t k = 0;
            factors[k++] = e->number;
            for (std::size_t j = 0; j < fs.size(); ++j)
                if (j != i) factors[k++] = fs[j];
            factors[k] = d;
            terms.push_back(mul(as_span(factors)));
        }
        return terms.empty() ? Expr(0) : add(as_span(terms));
    }
    case Kind::Pow: {
        const Expr b = e.args()[0], x = e.args()[1];
        const Expr db = rec(b), dx = rec(x);
        if (dx.is_zero()) {
            if (db.is_zero()) return Expr(0);
            return mul({x, pow(b, add({x, Expr(-1)})), db}); // x·b^(x−1)·b'
        }
        // d(b^x) = b^x·(x'·log b + x·b'/b)
        return mul({e, add({mul({dx, log(b)}), mul({x, db, pow(b, Expr(-1))})})});
    }
    case Kind::Function: {
        if (static_cast<Function>(e->sub) == Function::Atan2)
            return atan2_derivative(e.args()[0], e.args()[1], rec(e.args()[0]), rec(e.args()[1]));
        const Expr u = e.args()[0];
        const Expr du = rec(u);
        if (du.is_zero()) return du;
        switch (static_cast<Function>(e->sub)) {
        case Function::Sin: return mul({cos(u), du});
        case Function::Cos: return mul({Expr(-1), sin(u), du});
        case Function::Tan: return mul({add({Expr(1), pow(e, Expr(2))}), du}); // 1 + tan²
        case Function::Exp: return mul({e, du});
        case Function::Log: return mul({du, pow(u, Expr(-1))});
        case Function::Asin: return mul({du, pow(add({Expr(1), mul({Expr(-1), pow(u, Expr(2))})}), rational(-1, 2))});
        case Function::Acos:
            return mul({Expr(-1), du, pow(add({Expr(1), mul({Expr(-1), pow(u, Expr(2))})}), rational(-1, 2))});
        case Function::Atan: return mul({du, pow(add({Expr(1), pow(u, Expr(2))}), Expr(-1))});
        case Function::Sinh: return mul({cosh(u), du});
        case Function::Cosh: return mul({sinh(u), du});
        case Function::Tanh: return mul({add({Expr(1), mul({Expr(-1), pow(e, Expr(2))})}), du}); // 1 − tanh²
        case Function::Abs: return mul({sign(u), du});
        case Function::Sign: return Expr(0); // docs/language.md: sign' = 0
        case Function::Atan2: break;      // above
        }
        return Expr(0);
    }
    case Kind::Number:
    case Kind::Constant:
    case Kind::Symbol:
    case Kind::TimeDerivative: break; // leaves: handled by the callers
    }
    return Expr(0);
}

Expr make_derivative_node(Expr sym, int order) {
    if (order > limits::max_derivative_order)
        throw LimitError("time derivative of order above " + std::to_string(limits::max_derivative_order));
    const Expr args[1] = {sym};
    detail::NodeKey k{Kind::TimeDerivative};
    k.sub = static_cast<std::uint8_t>(order);
    k.args = args;
    return Expr(detail::pool().intern(k));
}

} // namespace

Expr diff(Expr e, Expr var) {
    if (!var.is_atom_variable())
        throw Error("can only differentiate with respect to a symbol or a time derivative of one");
    auto& memo = detail::pool().diff_memo;
    const std::uint64_t mask = var->atom_mask;
    auto rec = [&](auto&& self, Expr x) -> Expr {
        if ((x->atom_mask & mask) == 0) return Expr(0);
        switch (x.kind()) {
        case Kind::Number:
        case Kind::Constant: return Expr(0);
        case Kind::Symbol:
        case Kind::TimeDerivative: return x == var ? Expr(1) : Expr(0);
        case Kind::Function:
        case Kind::Pow:
        case Kind::Mul:
        case Kind::Add: break;
        }
        const auto key = std::make_pair(x.get(), var.get());
        if (const Expr* m = memo.find(key)) return *m;
        Expr d = derive_compound(x, [&](Expr c) { return self(self, c); });
        memo.try_emplace(key, d);
        return d;
    };
    return rec(rec, e);
}

Expr velocity(Expr x) {
    if (x.kind() == Kind::Symbol) return make_derivative_node(x, 1);
    if (x.kind() == Kind::TimeDerivative) return make_derivative_node(x.args()[0], x->sub + 1);
    throw Error("velocity() needs a symbol");
}

Expr time_derivative(Expr e) {
    auto& memo = detail::pool().dt_memo;
    auto rec = [&](auto&& self, Expr x) -> Expr {
        switch (x.kind()) {
        case Kind::Number:
        case Kind::Constant: return Expr(0);
        case Kind::Symbol: return x == time_symbol() ? Expr(1) : make_derivative_node(x, 1);
        case Kind::TimeDerivative: return make_derivative_node(x.args()[0], x->sub + 1);
        case Kind::Function:
        case Kind::Pow:
        case Kind::Mul:
        case Kind::Add: break;
        }
        if (const Expr* m = memo.find(x)) return *m;
        Expr d = derive_compound(x, [&](Expr c) { return self(self, c); });
        memo.try_emplace(x, d);
        return d;
    };
    return rec(rec, e);
}

Expr total_time_derivative(Expr e, std::span<const Expr> coordinates) {
    std::vector<Expr> terms;
    for (Expr q : coordinates) {
        // e may contain q, q' and q'' (an acceleration, once differentiated already).
        Expr x = q;
        for (int order = 0; order < 3; ++order, x = velocity(x)) {
            if ((e->atom_mask & x->atom_mask) == 0) continue;
            Expr d = diff(e, x);
            if (!d.is_zero()) terms.push_back(mul({d, velocity(x)}));
        }
    }
    Expr dt = diff(e, time_symbol());
    if (!dt.is_zero()) terms.push_back(dt);
    return terms.empty() ? Expr(0) : add(as_span(terms));
}

} // namespace phynjo::cas
