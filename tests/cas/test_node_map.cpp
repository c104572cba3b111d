// NodeMap and NodeSet (flat tables keyed by nodes) against std::unordered_map as the oracle,
// and the pool's memos of whole rewrites (expand, trig_simplify, horner) against fresh pools.
#include "expr_gen.hpp"
#include "property.hpp"

#include "phynjo/cas/cas.hpp"
#include "phynjo/cas/node_map.hpp"
#include "phynjo/grammar/expression.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

using namespace phynjo::cas;
using phynjo::test::check_property;

// Catches: a lookup or an insertion that probes wrongly (an entry found under another key,
// or lost), a growth that rehashes with the old capacity or drops entries, try_emplace
// overwriting an existing value or reporting the wrong "inserted".
TEST_CASE("NodeMap and NodeSet agree with std::unordered_map through growth", "[cas][node_map]") {
    check_property("NodeMap = unordered_map", [] {
        // keys: distinct symbols, enough of them to grow the table from its smallest size
        const int universe = *rc::gen::inRange(1, 700);
        std::vector<Expr> keys;
        for (int k = 0; k < universe; ++k) keys.push_back(symbol("s" + std::to_string(k)));
        const auto ops = *rc::gen::container<std::vector<std::pair<int, int>>>(
            rc::gen::pair(rc::gen::inRange(0, universe), rc::gen::arbitrary<int>()));
        NodeMap<int> map(static_cast<std::size_t>(*rc::gen::inRange(0, 64)));
        NodeSet set;
        std::unordered_map<Expr, int> oracle;
        std::unordered_set<Expr> oracle_set;
        for (const auto& [k, v] : ops) {
            const auto [slot, inserted] = map.try_emplace(keys[static_cast<std::size_t>(k)], v);
            const auto [it, oracle_inserted] = oracle.try_emplace(keys[static_cast<std::size_t>(k)], v);
            RC_ASSERT(inserted == oracle_inserted);
            RC_ASSERT(*slot == it->second);
            RC_ASSERT(set.insert(keys[static_cast<std::size_t>(k)]) == oracle_set.insert(keys[static_cast<std::size_t>(k)]).second);
        }
        RC_ASSERT(map.size() == oracle.size());
        RC_ASSERT(set.size() == oracle_set.size());
        for (Expr key : keys) {
            const int* found = map.find(key);
            const auto it = oracle.find(key);
            RC_ASSERT((found != nullptr) == (it != oracle.end()));
            if (found) RC_ASSERT(*found == it->second);
            RC_ASSERT(set.contains(key) == (oracle_set.count(key) > 0));
        }
        // operator[] inserts a default value once, then finds it
        map[keys[0]] += 5;
        RC_ASSERT(*map.find(keys[0]) == (oracle.count(keys[0]) ? oracle[keys[0]] : 0) + 5);
        map.clear();
        RC_ASSERT(map.empty());
        RC_ASSERT(map.find(keys[0]) == nullptr);
    });
}

// Catches: a pool memo shared between two rewrites, keyed by something other than the node,
// or kept across clear_memo wrongly — each would make a later call return another rewrite's
// result. Every answer must equal the one a fresh pool gives (printed, since nodes of two
// pools are never the same pointer).
TEST_CASE("memoized rewrites give what a fresh pool gives, before and after clear_memo", "[cas][node_map]") {
    check_property("expand, trig_simplify_only, horner, simplify across calls", [] {
        const auto texts = *rc::gen::container<std::vector<std::string>>(
            3, rc::gen::map(phynjo::test::gen_expr(3), [](Expr e) { return to_string(e); }));
        // the reference: each rewrite of each text in a pool of its own (no memo of any other call)
        auto alone = [](const std::string& t, auto&& rewrite) {
            Pool fresh;
            PoolScope scope(fresh);
            return to_string(rewrite(phynjo::grammar::parse(t)));
        };
        std::vector<std::string> want;
        for (const std::string& t : texts)
            want.push_back(alone(t, [](Expr e) { return expand(e); }) + " | " +
                           alone(t, [](Expr e) { return trig_simplify_only(e); }) + " | " +
                           alone(t, [](Expr e) { return horner(e); }) + " | " +
                           alone(t, [](Expr e) { return simplify(e); }));
        // one pool for all, twice over (the second time from the memos), then after clear_memo
        Pool shared;
        PoolScope scope(shared);
        for (int round = 0; round < 3; ++round) {
            if (round == 2) shared.clear_memo();
            for (std::size_t i = 0; i < texts.size(); ++i) {
                const Expr e = phynjo::grammar::parse(texts[i]);
                const std::string got = to_string(expand(e)) + " | " + to_string(trig_simplify_only(e)) + " | " +
                                        to_string(horner(e)) + " | " + to_string(simplify(e));
                RC_ASSERT(got == want[i]);
            }
        }
    }, {.cases = 100});
}
