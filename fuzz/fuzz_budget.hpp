// The per-input budget shared by every fuzz target: a fresh CAS pool whose memory and work
// are bounded (well below the documented defaults, so that a slow input shows up as a
// LimitError rather than a libFuzzer timeout).
#pragma once
#include "phynjo/cas/pool.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace phynjo::fuzz {

/// A fresh pool, current for this scope, with the fuzzing budget.
class BoundedPool {
public:
    BoundedPool() : scope_(limited(pool_)) {}

private:
    static cas::Pool& limited(cas::Pool& p) {
        p.set_node_limit(200'000);
        p.set_work_limit(300'000);
        return p;
    }
    cas::Pool pool_;
    cas::PoolScope scope_;
};

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

} // namespace phynjo::fuzz
