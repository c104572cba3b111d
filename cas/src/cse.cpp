#include "phynjo/cas/cse.hpp"

#include "phynjo/cas/transform.hpp"

#include <unordered_map>
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

CseResult cse(std::span<const Expr> outputs, const CseOptions& options) {
    // 1. Post-order of the DAG and the number of parents of each node.
    std::unordered_map<const Node*, int> uses;
    std::vector<Expr> post;
    std::unordered_set<const Node*> hoist;
    {
        std::unordered_set<const Node*> visited;
        auto visit = [&](auto&& self, Expr x) -> void {
            if (!visited.insert(x.get()).second) return;
            for (Expr c : x.args()) {
                ++uses[c.get()];
                self(self, c);
            }
            if (options.hoist_power_bases && x.kind() == Kind::Pow && x.args()[1].is_integer() &&
                !trivial(x.args()[0]))
                hoist.insert(x.args()[0].get());
            post.push_back(x);
        };
        for (Expr o : outputs) {
            ++uses[o.get()];
            visit(visit, o);
        }
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
    std::unordered_map<const Node*, Expr> rewritten; // node → expression in temporaries
    std::unordered_map<const Node*, Expr> temp;      // node → its temporary
    auto ref = [&](Expr c) {
        if (auto t = temp.find(c.get()); t != temp.end()) return t->second;
        return rewritten.at(c.get());
    };
    for (Expr x : post) {
        Expr r = x;
        if (x->nargs) {
            std::vector<Expr> a;
            a.reserve(x->nargs);
            bool same = true;
            for (Expr c : x.args()) {
                a.push_back(ref(c));
                same = same && a.back() == c;
            }
            if (!same) r = rebuild(x, a);
        }
        rewritten.emplace(x.get(), r);
        if (!trivial(x) && (uses[x.get()] >= 2 || hoist.count(x.get()))) {
            const Expr t = symbol(prefix + std::to_string(result.assignments.size()));
            result.assignments.emplace_back(t, r);
            temp.emplace(x.get(), t);
        }
    }
    for (Expr o : outputs) result.outputs.push_back(ref(o));
    return result;
}

} // namespace phynjo::cas
