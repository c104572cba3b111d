#include "phynjo/grammar/builtins.hpp"

#include "phynjo/cas/cas.hpp"

namespace phynjo::grammar {

const BuiltinFunction* find_builtin_function(std::string_view name) {
    for (const BuiltinFunction& b : builtin_functions)
        if (b.name == name) return &b;
    return nullptr;
}

bool is_builtin(std::string_view name) {
    for (auto c : builtin_constants)
        if (c == name) return true;
    return find_builtin_function(name) != nullptr;
}

std::string builtin_function_list() {
    std::string s;
    for (const BuiltinFunction& b : builtin_functions) s += (s.empty() ? "" : ", ") + std::string(b.name);
    return s;
}

} // namespace phynjo::grammar
