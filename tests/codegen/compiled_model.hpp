#pragma once
// A .lag text read and derived, for the codegen tests (test_derive, test_linearize): fails the
// test with the diagnostics when the model has errors.
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"

#include <catch2/catch.hpp>

#include <string_view>

namespace phynjo::test {

struct Compiled {
    codegen::Model model;
    codegen::EquationsOfMotion eom;
};

inline Compiled compile_model(std::string_view text) {
    grammar::DiagnosticSink sink("m.lag", text);
    auto model = codegen::read_model(text, "m.lag", sink);
    INFO(sink.format_all());
    REQUIRE(model);
    auto eom = codegen::derive(*model, sink);
    REQUIRE(eom);
    return {*model, *eom};
}

} // namespace phynjo::test
