#include "phynjo/cas/cse.hpp"
#include "number_ops.hpp"

#include "phynjo/cas/node_map.hpp"
#include "phynjo/cas/transform.hpp"

#include <algorithm>
#include <unordered_set>

namespace phynjo::cas {

namespace {
bool trivial(Expr x) {
    switch (x.kind()) {
    case Kind::Number:
    case Kind::Constant:
    case Kind::Symbol:
    case Kind::TimeDerivative: return true;
    case Kind::Mul: // a negated or scaled variable costs one multiplication at the use
        return x->nargs == 1 && x.args()[0].is_atom_variable();
    case Kind::Function:
    case Kind::Pow:
    case Kind::Add: return false;
    }
    return false;
}
} // namespace

namespace {

/// x = y + (the rest of x's terms), y an Add of the same DAG whose terms are some of x's.
struct PartialSum {
    const Node* y = nullptr;
    std::vector<std::uint32_t> rest; ///< indices of x's terms not in y
    bool constant = false;           ///< x's constant term is not in y
};

std::uint64_t term_hash(Expr coef, Expr arg) noexcept {
    std::uint64_t h = coef.hash() * 0x9E3779B97F4A7C15ULL ^ (arg.is_null() ? 0x51ED270B27A2F5C3ULL : arg.hash());
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ULL;
    return h ^ (h >> 32);
}

/// The partial sums to share: for each Add x of `nodes` with three terms or more, an Add y
/// among `nodes` with all but one or two of x's terms (the largest such y), so that x is
/// computed as y plus one or two terms. A chain's sums (the velocity of link k of a
/// pendulum: q0' − Σ_{j≤k} l_j q_j' cos q_j) then cost O(1) each instead of O(k). Term
/// sets are compared by an additive hash of their terms, so dropping a term is a
/// subtraction; a hit is verified term by term. Deterministic: structural hashes only.
NodeMap<PartialSum> partial_sums(const std::vector<Expr>& nodes) {
    NodeMap<PartialSum> out;
    auto terms = [](Expr x) { return x->nargs + (x->number.is_zero() ? 0u : 1u); };
    // term k of an Add: (coef, arg) for k < nargs, (constant, null) for k == nargs
    auto term = [](Expr x, std::uint32_t k) -> std::uint64_t {
        return k < x->nargs ? term_hash(x->coefs[k], x.args()[k]) : term_hash(x->number, Expr());
    };
    // (set hash, sum) of every sum, by hash; sums of one hash in the order of `nodes`
    std::vector<std::pair<std::uint64_t, const Node*>> by_hash;
    NodeMap<std::uint64_t> set_hash(nodes.size());
    for (Expr x : nodes) {
        if (x.kind() != Kind::Add) continue;
        std::uint64_t h = 0;
        for (std::uint32_t k = 0, m = terms(x); k < m; ++k) h += term(x, k);
        set_hash.try_emplace(x, h);
        by_hash.emplace_back(h, x.get());
    }
    std::stable_sort(by_hash.begin(), by_hash.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    // Does y have exactly x's terms but those at `drop` (sorted; x = y + the dropped terms)?
    // Both lists are in the canonical order, so the comparison is one pass.
    auto matches = [&](Expr x, Expr y, const std::uint32_t* drop, std::size_t nd) {
        if (terms(y) + nd != terms(x)) return false;
        bool drops_constant = false;
        std::uint32_t j = 0;
        std::size_t d = 0;
        for (std::uint32_t k = 0; k < x->nargs; ++k) {
            if (d < nd && drop[d] == k) {
                ++d;
                continue;
            }
            if (j >= y->nargs || y->coefs[j] != x->coefs[k] || y.args()[j] != x.args()[k]) return false;
            ++j;
        }
        if (d < nd && drop[d] == x->nargs) drops_constant = true;
        return j == y->nargs && (drops_constant ? y->number.is_zero() : y->number == x->number);
    };
    for (Expr x : nodes) {
        if (x.kind() != Kind::Add) continue;
        const std::uint32_t m = terms(x);
        if (m < 3) continue;
        const std::uint64_t h = *set_hash.find(x);
        auto find = [&](std::uint64_t key, const std::uint32_t* drop, std::size_t nd) -> bool {
            auto it = std::lower_bound(by_hash.begin(), by_hash.end(), key,
                                       [](const auto& e, std::uint64_t k) { return e.first < k; });
            for (; it != by_hash.end() && it->first == key; ++it)
                if (const Node* y = it->second; matches(x, Expr(y), drop, nd)) {
                    PartialSum& p = out[x];
                    p.y = y;
                    for (std::uint32_t k = 0; k < x->nargs; ++k)
                        if (std::find(drop, drop + nd, k) != drop + nd) p.rest.push_back(k);
                    p.constant = std::find(drop, drop + nd, x->nargs) != drop + nd;
                    return true;
                }
            return false;
        };
        bool found = false;
        for (std::uint32_t i = 0; i < m && !found; ++i) found = find(h - term(x, i), &i, 1);
        for (std::uint32_t i = 0; i < m && !found && m <= 48; ++i)
            for (std::uint32_t j = i + 1; j < m && !found && m > 3; ++j) {
                const std::uint32_t drop[2] = {i, j};
                found = find(h - term(x, i) - term(x, j), drop, 2);
            }
    }
    return out;
}

} // namespace

CseResult cse(std::span<const Expr> outputs, const CseOptions& options) {
    // 0. Partial sums: which sums are computed from others (extra edges x → y of the DAG).
    NodeMap<PartialSum> sums;
    if (options.share_partial_sums) {
        std::vector<Expr> nodes;
        NodeSet seen;
        auto visit = [&](auto&& self, Expr x) -> void {
            if (!seen.insert(x)) return;
            for (Expr c : x.args()) self(self, c);
            nodes.push_back(x);
        };
        for (Expr o : outputs) visit(visit, o);
        sums = partial_sums(nodes);
    }
    // the children of x in the computation: a shared partial sum's y and its other terms' args
    auto for_children = [&](Expr x, auto&& f) {
        if (x.kind() == Kind::Add) {
            if (const PartialSum* p = sums.find(x)) {
                f(Expr(p->y));
                for (std::uint32_t k : p->rest) f(x.args()[k]);
                return;
            }
        }
        for (Expr c : x.args()) f(c);
    };
    // 1. Post-order of the DAG and the number of parents of each node.
    // (a node is visited when first counted: its entry in `uses` is the visited mark)
    NodeMap<int> uses(1024);
    std::vector<Expr> post;
    NodeSet hoist;
    {
        auto count = [&](Expr c) {
            auto [n, first] = uses.try_emplace(c, 0);
            ++*n;
            return first;
        };
        auto visit = [&](auto&& self, Expr x) -> void {
            for_children(x, [&](Expr c) {
                if (count(c)) self(self, c);
            });
            if (options.hoist_power_bases && x.kind() == Kind::Pow && x.args()[1].is_integer() &&
                !trivial(x.args()[0]))
                hoist.insert(x.args()[0]);
            post.push_back(x);
        };
        for (Expr o : outputs)
            if (count(o)) visit(visit, o);
    }
    // 2. Names that cannot clash with the input's symbols.
    std::string prefix = options.prefix;
    {
        std::unordered_set<std::string_view> names;
        for (Expr x : post)
            if (x.kind() == Kind::Symbol) names.insert(x->name);
        auto clashes = [&] {
            for (std::string_view n : names)
                if (n.size() > prefix.size() && n.substr(0, prefix.size()) == prefix &&
                    n.find_first_not_of("0123456789", prefix.size()) == std::string_view::npos)
                    return true;
            return false;
        };
        while (clashes()) prefix += "_";
    }
    // 3. Rewrite bottom-up, replacing shared nodes by temporaries.
    CseResult result;
    NodeMap<Expr> rewritten(post.size()); // node → expression in temporaries
    NodeMap<Expr> temp;                   // node → its temporary
    auto ref = [&](Expr c) {
        if (const Expr* t = temp.find(c)) return *t;
        return *rewritten.find(c);
    };
    for (Expr x : post) {
        Expr r = x;
        if (const PartialSum* p = sums.find(x)) {
            std::vector<Expr> ts{ref(Expr(p->y))};
            for (std::uint32_t k : p->rest) ts.push_back(detail::times(x->coefs[k], ref(x.args()[k])));
            if (p->constant) ts.push_back(x->number);
            r = add(ts);
        } else if (x->nargs) {
            r = with_children(x, ref);
        }
        rewritten.try_emplace(x, r);
        if (!trivial(x) && (*uses.find(x) >= 2 || hoist.contains(x))) {
            const Expr t = symbol(prefix + std::to_string(result.assignments.size()));
            result.assignments.emplace_back(t, r);
            temp.try_emplace(x, t);
        }
    }
    for (Expr o : outputs) result.outputs.push_back(ref(o));
    return result;
}

} // namespace phynjo::cas
