#include "phynjo/cas/transform.hpp"
#include "number_ops.hpp"
#include "phynjo/cas/node_map.hpp"

#include "phynjo/cas/diff.hpp"
#include "phynjo/cas/errors.hpp"

#include <boost/container/small_vector.hpp>

#include <algorithm>
#include <string>

namespace phynjo::cas {

Expr rebuild(Expr e, std::span<const Expr> a) {
    switch (e.kind()) {
    case Kind::Number:
    case Kind::Constant:
    case Kind::Symbol: return e;
    case Kind::TimeDerivative: {
        Expr x = a[0];
        if (x == e.args()[0]) return e;
        for (int k = 0; k < e->sub; ++k) x = time_derivative(x);
        return x;
    }
    case Kind::Function: return function(static_cast<Function>(e->sub), a);
    case Kind::Pow: return pow(a[0], a[1]);
    case Kind::Mul: {
        std::vector<Expr> fs(a.begin(), a.end());
        fs.push_back(e->number);
        return mul(fs);
    }
    case Kind::Add: {
        std::vector<Expr> ts;
        ts.reserve(a.size() + 1);
        for (std::size_t i = 0; i < a.size(); ++i) ts.push_back(detail::times(e->coefs[i], a[i]));
        ts.push_back(e->number);
        return add(ts);
    }
    }
    return e;
}

namespace {

/// Bottom-up map with a memo: f(node, rebuilt-children-node).
template <typename F>
Expr map_bottom_up(Expr e, NodeMap<Expr>& memo, F&& f) {
    auto rec = [&](auto&& self, Expr x) -> Expr {
        if (const Expr* m = memo.find(x)) return *m;
        const Expr r = x->nargs == 0 ? f(x) : f(with_children(x, [&](Expr c) { return self(self, c); }));
        memo.try_emplace(x, r);
        return r;
    };
    return rec(rec, e);
}

// ---- expand -----------------------------------------------------------------------------

/// The terms of an expanded expression (a sum becomes its terms, anything else one term).
void terms_of(Expr e, std::vector<Expr>& out) {
    if (e.kind() == Kind::Add) {
        for (std::uint32_t i = 0; i < e->nargs; ++i) out.push_back(detail::times(e->coefs[i], e.args()[i]));
        if (!e->number.is_zero()) out.push_back(e->number);
    } else out.push_back(e);
}

void check_terms(std::size_t n) {
    if (n > limits::max_expand_terms)
        throw LimitError("expansion would have more than " + std::to_string(limits::max_expand_terms) + " terms");
}

/// Product of two expanded expressions, expanded.
Expr expand_product(Expr a, Expr b) {
    std::vector<Expr> ta, tb;
    terms_of(a, ta);
    terms_of(b, tb);
    if (ta.size() == 1 && tb.size() == 1) return mul({a, b});
    check_terms(ta.size() * tb.size());
    std::vector<Expr> out;
    out.reserve(ta.size() * tb.size());
    for (Expr x : ta)
        for (Expr y : tb) out.push_back(mul({x, y}));
    return add(out);
}

Expr expand_node(Expr x) {
    switch (x.kind()) {
    case Kind::Mul: {
        Expr acc = x->number;
        for (Expr f : x.args()) acc = expand_product(acc, f);
        return acc;
    }
    case Kind::Pow: {
        const Expr b = x.args()[0], e = x.args()[1];
        if (b.kind() != Kind::Add || !e.is_integer() || e.value() <= 1) return x;
        const mpz_class n = e.value().get_num();
        if (n > 10'000) throw LimitError("expansion of a power above 10000");
        if (b->nargs >= 2 || !b->number.is_zero()) check_terms(static_cast<std::size_t>(n.get_ui()) + 1);
        // square-and-multiply keeps the number of large products at O(log n)
        Expr result = Expr(1), base = b;
        for (unsigned long k = n.get_ui(); k; k >>= 1) {
            if (k & 1) result = expand_product(result, base);
            if (k > 1) base = expand_product(base, base);
        }
        return result;
    }
    case Kind::Number:
    case Kind::Constant:
    case Kind::Symbol:
    case Kind::TimeDerivative:
    case Kind::Function:
    case Kind::Add: return x;
    }
    return x;
}

// ---- simplify -----------------------------------------------------------------------------

bool is_fn(Expr x, Function f) { return x.kind() == Kind::Function && static_cast<Function>(x->sub) == f; }

/// sin(u)^2·R + cos(u)^2·R → R inside one sum (equal coefficients), repeated to a fixed point.
Expr pythagoras(Expr s) {
    if (s.kind() != Kind::Add) return s;
    // rest → coefficient; the constant term has rest 1.
    std::vector<std::pair<Expr, Expr>> terms;
    for (std::uint32_t i = 0; i < s->nargs; ++i) terms.emplace_back(s.args()[i], s->coefs[i]);
    if (!s->number.is_zero()) terms.emplace_back(Expr(1), s->number);
    bool changed = false;
    for (bool again = true; again;) {
        again = false;
        for (std::size_t i = 0; i < terms.size() && !again; ++i) {
            const Expr t = terms[i].first;
            std::span<const Expr> fs = t.kind() == Kind::Mul ? t.args() : std::span<const Expr>(&terms[i].first, 1);
            for (Expr f : fs) {
                if (f.kind() != Kind::Pow || !is_fn(f.args()[0], Function::Sin) || !f.args()[1].is_integer() ||
                    f.args()[1].value() < 2)
                    continue;
                const Expr u = f.args()[0].args()[0];
                const Expr r = mul({t, pow(sin(u), Expr(-2))});
                const Expr partner = mul({r, pow(cos(u), Expr(2))});
                auto it = std::find_if(terms.begin(), terms.end(), [&](auto& p) { return p.first == partner; });
                if (it == terms.end() || it->second != terms[i].second) continue;
                const Expr c = terms[i].second;
                const std::size_t j = static_cast<std::size_t>(it - terms.begin());
                terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(std::max(i, j)));
                terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(std::min(i, j)));
                // c·r may itself be a sum or merge with an existing term: rebuild through add.
                std::vector<Expr> all;
                for (auto& [rest, coef] : terms) all.push_back(mul({coef, rest}));
                all.push_back(mul({c, r}));
                const Expr merged = add(all);
                terms.clear();
                if (merged.kind() == Kind::Add) {
                    for (std::uint32_t k = 0; k < merged->nargs; ++k) terms.emplace_back(merged.args()[k], merged->coefs[k]);
                    if (!merged->number.is_zero()) terms.emplace_back(Expr(1), merged->number);
                } else terms.emplace_back(merged, Expr(1));
                again = changed = true;
                break;
            }
        }
    }
    if (!changed) return s;
    std::vector<Expr> all;
    for (auto& [rest, coef] : terms) all.push_back(mul({coef, rest}));
    return add(all);
}

/// The angle-difference identities inside one sum, repeated to a fixed point:
///   c·R·cos(a)·cos(b) + c·R·sin(a)·sin(b) → c·R·cos(a − b),
///   c·R·sin(a)·cos(b) − c·R·cos(a)·sin(b) → c·R·sin(a − b)
/// (the double pendulum's M₁₂ = m₂l₁l₂ cos(θ₁ − θ₂)); every factor named has exponent 1.
Expr angle_difference(Expr s) {
    if (s.kind() != Kind::Add) return s;
    std::vector<std::pair<Expr, Expr>> terms; // rest → coefficient
    for (std::uint32_t i = 0; i < s->nargs; ++i) terms.emplace_back(s.args()[i], s->coefs[i]);
    const Expr constant = s->number;
    bool changed = false;
    for (bool again = true; again;) {
        again = false;
        for (std::size_t i = 0; i < terms.size() && !again; ++i) {
            const Expr t = terms[i].first;
            if (t.kind() != Kind::Mul) continue;
            for (Expr f : t.args()) {
                const bool f_cos = is_fn(f, Function::Cos), f_sin = is_fn(f, Function::Sin);
                if (!f_cos && !f_sin) continue;
                for (Expr g : t.args()) {
                    if (g == f || !is_fn(g, Function::Cos)) continue;
                    const Expr a = f.args()[0], b = g.args()[0];
                    // r = t / (f·g); the partner term and the result
                    const Expr r = mul({t, pow(f, Expr(-1)), pow(g, Expr(-1))});
                    const Expr partner = f_cos ? mul({r, sin(a), sin(b)}) : mul({r, cos(a), sin(b)});
                    const Expr want = f_cos ? terms[i].second : mul({Expr(-1), terms[i].second});
                    auto it = std::find_if(terms.begin(), terms.end(), [&](auto& p) { return p.first == partner; });
                    if (it == terms.end() || it->second != want || it == terms.begin() + static_cast<std::ptrdiff_t>(i))
                        continue;
                    const Expr c = terms[i].second;
                    const Expr diff = add({a, mul({Expr(-1), b})});
                    const Expr replacement = mul({c, r, f_cos ? cos(diff) : sin(diff)});
                    const std::size_t j = static_cast<std::size_t>(it - terms.begin());
                    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(std::max(i, j)));
                    terms.erase(terms.begin() + static_cast<std::ptrdiff_t>(std::min(i, j)));
                    std::vector<Expr> all{constant, replacement};
                    for (auto& [rest, coef] : terms) all.push_back(mul({coef, rest}));
                    const Expr merged = add(all);
                    terms.clear();
                    if (merged.kind() != Kind::Add) return merged;
                    for (std::uint32_t k = 0; k < merged->nargs; ++k) terms.emplace_back(merged.args()[k], merged->coefs[k]);
                    again = changed = true;
                    break;
                }
                if (again) break;
            }
        }
        if (!again) break;
    }
    if (!changed) return s;
    std::vector<Expr> all{constant};
    for (auto& [rest, coef] : terms) all.push_back(mul({coef, rest}));
    return add(all);
}

Expr trig_simplify(Expr e) {
    return map_bottom_up(e, detail::pool().trig_memo, [](Expr x) { return angle_difference(pythagoras(x)); });
}

} // namespace

Expr expand(Expr e) {
    return map_bottom_up(e, detail::pool().expand_memo, [](Expr x) { return expand_node(x); });
}

Expr trig_simplify_only(Expr e) { return trig_simplify(e); }

Expr simplify(Expr e) {
    for (int iteration = 0; iteration < 64; ++iteration) {
        Expr best = trig_simplify(e);
        try {
            const Expr expanded = trig_simplify(expand(e));
            if (tree_size(expanded) < tree_size(best)) best = expanded;
        } catch (const LimitError&) {
            // expansion too large: keep the unexpanded form
        }
        if (best == e) return e;
        e = best;
    }
    return e;
}

namespace {

/// A term of a sum as coefficient × Π atom^multiplicity (atoms: bases of positive integer
/// powers; any other factor is an atom of multiplicity 1).
struct HTerm {
    Expr coef;
    boost::container::small_vector<std::pair<Expr, long>, 6> atoms; // sorted by canonical order of the atom
};

HTerm to_hterm(Expr coef, Expr rest) {
    HTerm t{coef, {}};
    auto add_factor = [&](Expr f) {
        if (f.kind() == Kind::Pow && f.args()[1].is_integer() && f.args()[1].value() > 0 &&
            f.args()[1].value() < 1000)
            t.atoms.emplace_back(f.args()[0], f.args()[1].value().get_num().get_si());
        else t.atoms.emplace_back(f, 1);
    };
    if (rest.is_null()) return t;
    if (rest.kind() == Kind::Mul) {
        t.coef = detail::num_mul(t.coef, rest->number);
        for (Expr f : rest.args()) add_factor(f);
    } else add_factor(rest);
    std::sort(t.atoms.begin(), t.atoms.end(), [](auto& a, auto& b) { return compare(a.first, b.first) < 0; });
    return t;
}

Expr from_hterm(const HTerm& t) {
    boost::container::small_vector<Expr, 8> fs;
    bool sorted = true; // factors by base in canonical order (an atom that is a fractional power sorts by itself)
    for (const auto& [a, m] : t.atoms) {
        fs.push_back(m == 1 ? a : pow(a, Expr(m)));
        if (fs.size() > 1 && compare(detail::base_of(fs[fs.size() - 2]), detail::base_of(fs.back())) >= 0) sorted = false;
    }
    if (sorted) return detail::mul_sorted(t.coef, detail::as_span(fs));
    fs.insert(fs.begin(), t.coef);
    return mul(detail::as_span(fs));
}

Expr horner_terms(std::vector<HTerm> terms) {
    if (terms.size() <= 1) {
        if (terms.empty()) return Expr(0);
        return from_hterm(terms[0]);
    }
    // the atom in the most terms (ties: canonical order): sort the atoms of all terms by
    // node address, count runs
    boost::container::small_vector<const Node*, 64> atoms;
    for (const HTerm& t : terms)
        for (const auto& [a, m] : t.atoms) atoms.push_back(a.get());
    std::sort(atoms.begin(), atoms.end());
    Expr best_atom;
    int best_count = 1;
    for (std::size_t i = 0; i < atoms.size();) {
        std::size_t j = i + 1;
        while (j < atoms.size() && atoms[j] == atoms[i]) ++j;
        const int c = static_cast<int>(j - i);
        const Expr a(atoms[i]);
        if (c > best_count || (c == best_count && c >= 2 && compare(a, best_atom) < 0)) {
            best_count = c;
            best_atom = a;
        }
        i = j;
    }
    const Expr* best = best_atom.is_null() ? nullptr : &best_atom;
    if (!best) {
        std::vector<Expr> all;
        all.reserve(terms.size());
        for (const HTerm& t : terms) all.push_back(from_hterm(t));
        return add(all);
    }
    const Expr atom = *best;
    std::vector<HTerm> with, without;
    with.reserve(static_cast<std::size_t>(best_count));
    without.reserve(terms.size() - static_cast<std::size_t>(best_count));
    for (HTerm& t : terms) {
        auto it = std::find_if(t.atoms.begin(), t.atoms.end(), [&](auto& p) { return p.first == atom; });
        if (it == t.atoms.end()) {
            without.push_back(std::move(t));
            continue;
        }
        if (--it->second == 0) t.atoms.erase(it);
        with.push_back(std::move(t));
    }
    const Expr factored = mul({atom, horner_terms(std::move(with))});
    return without.empty() ? factored : add({factored, horner_terms(std::move(without))});
}

} // namespace

std::vector<Expr> horner(std::span<const Expr> es) {
    auto& memo = detail::pool().horner_memo;
    auto step = [](Expr x) {
        if (x.kind() != Kind::Add) return x;
        std::vector<HTerm> terms;
        terms.reserve(x->nargs + 1);
        for (std::uint32_t i = 0; i < x->nargs; ++i) terms.push_back(to_hterm(x->coefs[i], x.args()[i]));
        if (!x->number.is_zero()) terms.push_back(HTerm{x->number, {}});
        return horner_terms(std::move(terms));
    };
    std::vector<Expr> out;
    for (Expr e : es) out.push_back(map_bottom_up(e, memo, step));
    return out;
}

Expr horner(Expr e) { return horner(std::span<const Expr>(&e, 1))[0]; }

Expr subs(Expr e, const std::unordered_map<Expr, Expr>& replacements) {
    if (replacements.empty()) return e;
    NodeMap<Expr> memo;
    auto rec = [&](auto&& self, Expr x) -> Expr {
        if (auto r = replacements.find(x); r != replacements.end()) return r->second;
        if (x->nargs == 0) return x;
        if (const Expr* m = memo.find(x)) return *m;
        const Expr r = with_children(x, [&](Expr c) { return self(self, c); });
        memo.try_emplace(x, r);
        return r;
    };
    return rec(rec, e);
}

namespace {
template <typename Keep>
std::vector<Expr> collect_atoms(std::span<const Expr> es, Keep&& keep, bool into_derivatives) {
    NodeSet seen;
    std::vector<Expr> stack(es.begin(), es.end()), out;
    while (!stack.empty()) {
        Expr x = stack.back();
        stack.pop_back();
        if (!seen.insert(x)) continue;
        if (keep(x)) out.push_back(x);
        if (x.kind() == Kind::TimeDerivative && !into_derivatives) continue;
        for (Expr c : x.args()) stack.push_back(c);
    }
    std::sort(out.begin(), out.end(), [](Expr a, Expr b) {
        if (symbol_name(a) != symbol_name(b)) return symbol_name(a) < symbol_name(b);
        return derivative_order(a) < derivative_order(b);
    });
    return out;
}
} // namespace

std::vector<Expr> free_symbols(Expr e) {
    return collect_atoms(std::span<const Expr>(&e, 1), [](Expr x) { return x.kind() == Kind::Symbol; }, true);
}
std::vector<Expr> free_variables(std::span<const Expr> es) {
    return collect_atoms(es, [](Expr x) { return x.is_atom_variable(); }, false);
}
std::vector<Expr> free_variables(Expr e) { return free_variables(std::span<const Expr>(&e, 1)); }

bool contains(Expr e, Expr x) {
    if (x.is_atom_variable() && (e->atom_mask & x->atom_mask) == 0) return false;
    NodeSet seen;
    std::vector<Expr> stack{e};
    while (!stack.empty()) {
        Expr y = stack.back();
        stack.pop_back();
        if (y == x) return true;
        if (!seen.insert(y)) continue;
        for (Expr c : y.args()) stack.push_back(c);
    }
    return false;
}

bool contains_any(Expr e, const NodeSet& vars) {
    NodeSet seen;
    std::vector<Expr> stack{e};
    while (!stack.empty()) {
        const Expr x = stack.back();
        stack.pop_back();
        if (x.is_atom_variable()) {
            if (vars.contains(x)) return true;
            continue;
        }
        if (!seen.insert(x)) continue;
        for (Expr c : x.args()) stack.push_back(c);
    }
    return false;
}

} // namespace phynjo::cas
