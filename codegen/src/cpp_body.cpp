// Straight-line bodies for generated functions: one CSE pass over all outputs of a function,
// locals declared only for the variables used.
#include "emit_detail.hpp"

#include "phynjo/cas/node_map.hpp"

#include <map>
#include <optional>
#include <unordered_map>
#include <unordered_set>

namespace phynjo::codegen::detail {

namespace {

/// The variables a CSE result uses (its temporaries among them), sorted by name.
std::vector<Expr> variables_of(const cas::CseResult& r) {
    std::vector<Expr> all = r.outputs;
    for (const auto& [t, v] : r.assignments) all.push_back(v);
    return cas::free_variables(all);
}

/// The loads of the user variables among `vars`, in a deterministic order.
std::string loads(const Names& names, const std::vector<Expr>& vars, bool& uses_t, bool& uses_params, bool generic) {
    std::map<std::string, Expr> used;
    for (Expr v : vars)
        if (names.is_user(v)) used.emplace(names.local(v), v);
    std::string s;
    uses_t = false;
    uses_params = false;
    for (const auto& [local, v] : used) {
        if (v == cas::time_symbol()) uses_t = true;
        else {
            if (local[0] == 'k') uses_params = true;
            s += names.load(v, generic);
        }
    }
    return s;
}

/// Statements a piece: smaller pieces compile faster (nlink_cart(40)'s canonical_jacobian:
/// 13.1 s of g++ in pieces of 250, 10.1 s in pieces of 64) and run within a few per cent.
constexpr std::size_t kChunkStatements = 64;
/// Arrays of fewer entries than this are written as one initializer or one statement each.
constexpr std::size_t kInlineEntries = 250;

/// Statements wrapped in pieces of kChunkStatements, each a lambda called at once that the
/// compiler may not inline: each piece is optimized (register allocation, SLP
/// vectorization) on its own, in time linear in the number of pieces.
class Pieces {
public:
    void add(std::string& out, const std::string& statement) {
        if (open_ == kChunkStatements) close(out);
        if (open_ == 0) out += "    [&]() __attribute__((noinline)) {\n";
        out += "    " + statement;
        ++open_;
    }
    void close(std::string& out) {
        if (open_ > 0) out += "    }();\n";
        open_ = 0;
    }

private:
    std::size_t open_ = 0;
};

/// When `entries` are the consecutive elements ARR[a], ARR[a+1], … of one array: "&ARR[a]".
std::optional<std::string> consecutive(const std::vector<std::string>& entries) {
    std::string array;
    std::size_t first = 0;
    for (std::size_t k = 0; k < entries.size(); ++k) {
        const std::string& e = entries[k];
        const auto open = e.find('[');
        if (open == std::string::npos || e.back() != ']') return std::nullopt;
        const std::string digits = e.substr(open + 1, e.size() - open - 2);
        if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
        const std::size_t index = std::stoul(digits);
        if (k == 0) {
            array = e.substr(0, open);
            first = index;
        } else if (e.compare(0, open, array) != 0 || open != array.size() || index != first + k)
            return std::nullopt;
    }
    if (entries.empty()) return std::nullopt;
    return "&" + array + "[" + std::to_string(first) + "]";
}

/// Statements of a body in one of two forms. Small bodies: `const double x7 = …;`. Large
/// ones (Names::piece_threshold statements and more): the temporaries and the outputs in one local
/// array, `xv[i] = …;`, computed in pieces of kChunkStatements, each piece a lambda the
/// compiler may not inline. GCC's register allocation grows much faster than linearly with
/// the size of a straight-line function (nlink_cart(40)'s rhs_jacobian: 51 s and 1.5 GB at
/// -O3 as one piece, 16 s and 0.44 GB in pieces); in pieces each is allocated on its own,
/// and the values pass between them through memory, at a few per cent of run time.
class Statements {
public:
    /// `vars`: the variables the body uses (variables_of), each spelt once for the printer.
    Statements(const Names& names, const cas::CseResult& r, const std::vector<Expr>& vars, bool generic = false)
        : names_(names), spelling_(2 * vars.size()) {
        generic_ = generic;
        cpp_.math_prefix = generic ? kLanes : names.math();
        chunked_ = r.assignments.size() + r.outputs.size() >= names.piece_threshold;
        if (chunked_) {
            array_ = names.temp_prefix() + "v"; // no temporary is PREFIX followed by a letter
            for (const auto& [t, v] : r.assignments) slot_.emplace(t, slot_.size());
        }
        cpp_.variable_name = [this](Expr v) {
            if (auto it = slot_.find(v); it != slot_.end()) return array_ + "[" + std::to_string(it->second) + "]";
            return names_.local(v);
        };
        for (Expr v : vars) spelling_.try_emplace(v, cpp_.variable_name(v));
        cpp_.variable_table = &spelling_;
        outputs_ = r.outputs.size();
        slots_ = slot_.size() + outputs_;
    }
    bool chunked() const noexcept { return chunked_; }
    /// `double xv[N];` for a chunked body (declared before any of its statements).
    std::string declaration() const {
        return chunked_ ? std::string(generic_ ? "    T " : "    double ") + array_ + "[" + std::to_string(slots_) + "];\n" : "";
    }
    /// The statement computing temporary `t` as `v`.
    void assign(std::string& out, Expr t, Expr v) {
        if (!chunked_) {
            out += std::string(generic_ ? "    const auto " : "    const double ") + names_.local(t) + " = " + cas::to_cpp(v, cpp_) + ";\n";
            return;
        }
        add(out, "    " + array_ + "[" + std::to_string(slot_.at(t)) + "] = " + typed(cas::to_cpp(v, cpp_)) + ";\n");
    }
    /// The C++ expression of output `j` (`e`); in a chunked body the output is stored in the
    /// array by a statement appended to `out`, and the expression is its element.
    std::string output(std::string& out, std::size_t j, Expr e) {
        std::string c = typed(cas::to_cpp(e, cpp_));
        if (!chunked_) return c;
        const std::string element = array_ + "[" + std::to_string(slot_.size() + j) + "]";
        add(out, "    " + element + " = " + c + ";\n");
        return element;
    }
    /// Ends the open piece (before code that is not part of the body: the late half of a split body).
    void close(std::string& out) { pieces_.close(out); }

private:
    void add(std::string& out, const std::string& statement) { pieces_.add(out, statement); }
    /// A value of type T in a generic body (a constant or a parameters' product is a double).
    std::string typed(const std::string& c) const { return generic_ ? std::string(kLanes) + "as<T>(" + c + ")" : c; }
    bool generic_ = false;
    Pieces pieces_;
    const Names& names_;
    cas::NodeMap<std::string> spelling_;
    cas::CppOptions cpp_;
    bool chunked_ = false;
    std::string array_;
    std::unordered_map<Expr, std::size_t> slot_;
    std::size_t outputs_ = 0, slots_ = 0;
};

} // namespace

std::string body(const Names& names, const std::vector<Expr>& outputs, std::vector<std::string>& results,
                 bool& uses_t, bool& uses_params, bool generic) {
    const cas::CseResult r = cas::cse(outputs, {.prefix = names.temp_prefix(), .hoist_power_bases = true});
    const std::vector<Expr> vars = variables_of(r);
    Statements st(names, r, vars, generic);
    std::string s = loads(names, vars, uses_t, uses_params, generic) + st.declaration();
    for (const auto& [t, v] : r.assignments) st.assign(s, t, v);
    results.clear();
    for (std::size_t j = 0; j < r.outputs.size(); ++j) results.push_back(st.output(s, j, r.outputs[j]));
    st.close(s);
    return s;
}

void body_split(const Names& names, const std::vector<Expr>& outputs, const std::vector<Expr>& late_variables,
                std::vector<std::string>& results, std::string& early, std::string& late, bool& uses_t, bool& uses_params) {
    const cas::CseResult r = cas::cse(outputs, {.prefix = names.temp_prefix(), .hoist_power_bases = true});
    const std::vector<Expr> vars = variables_of(r);
    Statements st(names, r, vars);
    early = loads(names, vars, uses_t, uses_params, false) + st.declaration();
    late.clear();
    cas::NodeSet is_late(late_variables.size() + r.assignments.size());
    for (Expr x : late_variables) is_late.insert(x);
    for (const auto& [t, v] : r.assignments) {
        if (cas::contains_any(v, is_late)) is_late.insert(t);
        else st.assign(early, t, v);
    }
    // the outputs that need no late variable are computed early (M, f, G, γ before the solve)
    std::vector<char> output_late(r.outputs.size());
    for (std::size_t j = 0; j < r.outputs.size(); ++j) output_late[j] = cas::contains_any(r.outputs[j], is_late);
    results.assign(r.outputs.size(), {});
    for (std::size_t j = 0; j < r.outputs.size(); ++j)
        if (!output_late[j]) results[j] = st.output(early, j, r.outputs[j]);
    st.close(early);
    for (const auto& [t, v] : r.assignments)
        if (is_late.contains(t)) st.assign(late, t, v);
    for (std::size_t j = 0; j < r.outputs.size(); ++j)
        if (output_late[j]) results[j] = st.output(late, j, r.outputs[j]);
    st.close(late);
}

std::string array_of(const Names& names, const std::string& name, const std::vector<std::string>& entries) {
    if (auto first = consecutive(entries)) return "    const double* " + name + " = " + *first + ";\n";
    std::string s;
    if (entries.size() < kInlineEntries) {
        s = "    const double " + name + "[" + std::to_string(entries.size()) + "] = {";
        for (std::size_t k = 0; k < entries.size(); ++k) s += (k ? ", " : "") + entries[k];
        return s + "};\n";
    }
    return "    double " + name + "[" + std::to_string(entries.size()) + "];\n" + store_all(names, name, entries, false);
}

std::string store_all(const Names& names, const std::string& target, const std::vector<std::string>& entries, bool span) {
    if (auto first = consecutive(entries)) {
        const std::string to = span ? names.data(target) : target, n = std::to_string(entries.size());
        return names.kernel() ? "    __builtin_memcpy(" + to + ", " + *first + ", " + n + " * sizeof(double));\n"
                              : "    std::copy_n(" + *first + ", " + n + ", " + to + ");\n";
    }
    std::string s;
    if (entries.size() < kInlineEntries) {
        for (std::size_t k = 0; k < entries.size(); ++k) s += "    " + target + "[" + std::to_string(k) + "] = " + entries[k] + ";\n";
        return s;
    }
    Pieces pieces;
    for (std::size_t k = 0; k < entries.size(); ++k)
        pieces.add(s, "    " + target + "[" + std::to_string(k) + "] = " + entries[k] + ";\n");
    pieces.close(s);
    return s;
}

const char* Names::math() const noexcept { return kernel() ? kLanes : "std::"; }

std::string Names::raise(Failure kind, const std::string& text, const std::string& value, const std::string& after) const {
    struct Spelling {
        const char* exception; ///< the source's
        const char* status;    ///< the kernel's (kernel_abi.h)
    };
    static constexpr Spelling spellings[] = {{"phynjo::runtime::SingularMassMatrix", "PHYNJO_SINGULAR_MASS_MATRIX"},
                                             {"phynjo::runtime::NonFiniteResult", "PHYNJO_NON_FINITE"},
                                             {"std::invalid_argument", "PHYNJO_INVALID_ARGUMENT"},
                                             {"std::out_of_range", "PHYNJO_OUT_OF_RANGE"}};
    const Spelling& sp = spellings[static_cast<std::size_t>(kind)];
    if (!kernel()) {
        std::string s = "throw " + std::string(sp.exception) + "(" + text;
        if (!value.empty()) s += " + std::to_string(" + value + ")";
        if (!after.empty()) s += " + " + after;
        return s + ");";
    }
    std::string s = std::string("throw phynjo::kernel::Failure(") + sp.status + ", " + text;
    if (!value.empty()) s += ", " + value;
    if (!after.empty()) s += ", " + after;
    return s + ");";
}

std::string unused(bool uses_t, bool uses_params, bool has_t) {
    std::string s;
    if (has_t && !uses_t) s += "    (void)t;\n";
    if (!uses_params) s += "    (void)P;\n";
    return s;
}

} // namespace phynjo::codegen::detail
