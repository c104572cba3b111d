#pragma once
// Property-based tests: RapidCheck (with shrinking to a minimal counterexample) run from
// Catch2 with a fixed seed and an explicit number of cases, so every run checks the same
// inputs. Set PHYNJO_RC_SEED to explore other seeds.
#include <catch2/catch.hpp>
#include <rapidcheck.h>

#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

namespace phynjo::test {

struct PropertyConfig {
    int cases = 200;
    std::uint64_t seed = 20261123;
    int max_size = 100;
};

template <typename Testable>
void check_property(const std::string& description, Testable&& testable, PropertyConfig cfg = {}) {
    rc::detail::TestParams params;
    params.seed = cfg.seed;
    if (const char* s = std::getenv("PHYNJO_RC_SEED")) params.seed = std::strtoull(s, nullptr, 10);
    params.maxSuccess = cfg.cases;
    params.maxSize = cfg.max_size;
    params.maxDiscardRatio = 50;
    rc::detail::TestMetadata metadata;
    metadata.id = description;
    metadata.description = description;
    const auto result = rc::detail::checkTestable(std::forward<Testable>(testable), metadata, params);
    if (result.template is<rc::detail::SuccessResult>()) {
        const auto& success = result.template get<rc::detail::SuccessResult>();
        INFO(description << ": " << success.numSuccess << " cases");
        CHECK(success.numSuccess == cfg.cases);
    } else {
        std::ostringstream ss;
        rc::detail::printResultMessage(result, ss);
        FAIL(description << " (seed " << params.seed << ")\n" << ss.str());
    }
}

} // namespace phynjo::test
