// phynjo-lagc: the Lagrangian compiler.
//   phynjo-lagc MODEL.lag -o OUT.cpp [--main]     writes OUT.cpp and OUT.hpp
//   phynjo-lagc MODEL.lag --emit=eom [-o FILE]    M and f in the input syntax
//   phynjo-lagc MODEL.lag --emit=latex [-o FILE]  a LaTeX document of L and the equations
//   phynjo-lagc MODEL.lag --emit=linear --at x=EXPR,…,x'=EXPR [--format=latex]   A and B
// Exit status: 0 ok, 1 the model has errors (reported as FILE:LINE:COL: error: …), 2 usage.
#include "phynjo/cas/pool.hpp"
#include "phynjo/codegen/emit.hpp"
#include "phynjo/codegen/equations.hpp"
#include "phynjo/codegen/frontend.hpp"
#include "phynjo/codegen/linearize.hpp"
#include "phynjo/grammar/expression.hpp"

#if defined(__GLIBC__) && defined(__linux__)
#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>
#endif

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#ifndef PHYNJO_VERSION
#define PHYNJO_VERSION "unknown"
#endif

namespace {

constexpr const char* usage_text = R"(usage: phynjo-lagc MODEL.lag -o OUT.cpp [--main] [--parts K]
       phynjo-lagc MODEL.lag --emit=eom|latex|cpp [-o FILE]
       phynjo-lagc MODEL.lag --emit=linear --at x=EXPR,...,x'=EXPR [--format=latex] [-o FILE]
       phynjo-lagc MODEL.lag --emit=kernel -o OUT.cpp

Compiles a Lagrangian model (.lag, see docs/language.md) to C++: OUT.cpp and, beside it, OUT.hpp
declaring the model's namespace (dof, Parameters, mass_matrix, forcing, accelerations,
momenta, energy, initial_state, and the runtime integration: system, make_world, workflow).

options:
  -o FILE        output file (for cpp: the .cpp; the .hpp is written beside it)
  --emit=KIND    cpp (default), eom (M and f in the input syntax), latex (a LaTeX document),
                 linear (A = dy'/dy and B = dy'/du about --at, exact, with the eigenvalues of A),
                 kernel (one .cpp with the model's functions and a C table, to build as a
                 shared object the runtime loads: what phynjo-run does; docs/command-line.md)
  --at STATE     with --emit=linear: the state, NAME=EXPR separated by commas; NAME a
                 coordinate x, a velocity x', t, or an input u; EXPR numbers, pi, functions
                 and parameters (exact: th=pi gives A and B in closed form); a coordinate,
                 velocity or t not given is 0, an input not given is at its default
  --format=latex with --emit=linear: A and B as LaTeX matrices
  --main         add a main() that simulates from the initial state and writes CSV
                 (t, q..., q'..., E); run it with --help for its options
  --parts K      also write OUT.part2.cpp ... OUT.partK.cpp (K from 1 to 16, default 1): a big
                 model's largest functions go there, so a build compiles them in parallel;
                 a small model's part files hold a comment only (phynjo_add_model uses 4)
  --split-above BYTES  with --parts: spread the functions only when they are at least this
                 big (default 262144)
  --pieces-above N  compute a function body of N statements or more (default 1500) in
                 pieces the C++ compiler optimizes one at a time: same results, bit for bit,
                 and a compile time that grows linearly with the model (nlink_cart(40)'s
                 rhs_jacobian: 51 s and 1.5 GB in g++ -O3 as one piece, 15 s and 0.44 GB)
  --max-nodes=N  limit on the size of the derived equations, in distinct subexpressions
                 (default 5000000)
  --max-output=N limit on the size of the generated code, in bytes (default 268435456)
  --help, --version

Other limits, fixed: files up to 16 MiB, nesting depth 200, numbers up to 100000 bits
(literals: 31000 digits, exponents within +-31000), time derivatives up to order 16.

exit status: 0 ok, 1 the model has errors, 2 usage error
)";

/// The whole of a file opened for reading (one read, not a character at a time).
std::string slurp(std::istream& in) {
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

int usage_error(const std::string& m) {
    std::cerr << "phynjo-lagc: " << m << "\ntry 'phynjo-lagc --help'\n";
    return 2;
}

/// Writes `text` to `path` unless it already holds exactly that (no needless rebuilds).
bool write_file(const std::string& path, const std::string& text) {
    {
        std::ifstream in(path, std::ios::binary);
        if (in) {
            if (in.seekg(0, std::ios::end).tellg() == static_cast<std::streamoff>(text.size()) &&
                slurp(in.seekg(0)) == text)
                return true;
        }
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
        std::cerr << "phynjo-lagc: cannot write " << path << "\n";
        return false;
    }
    return true;
}

/// The heap in large pages. A compile allocates a few megabytes and frees little; touched 4 KB
/// at a time, that was ~1940 page faults for nlink_cart(10), most of the quarter of its time
/// spent in the kernel (each fault zeroes and charges one page). So: the heap grows by PAD at a time, never shrinks, nothing
/// goes to separate mappings, and the kernel is asked for transparent huge pages on it (a
/// request, not a reservation: memory is still only taken when touched). glibc and Linux only.
void prepare_heap() {
#if defined(__GLIBC__) && defined(__linux__) && !defined(__SANITIZE_ADDRESS__) // (ASan has its own allocator)
    constexpr std::size_t pad = std::size_t{16} << 20, huge = std::size_t{2} << 20;
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    mallopt(M_TOP_PAD, static_cast<int>(pad));
    void* first = std::malloc(pad); // more than the heap has: it grows (by twice the pad)
    const auto begin = (reinterpret_cast<std::uintptr_t>(first) + huge - 1) & ~(huge - 1);
    const auto end = reinterpret_cast<std::uintptr_t>(sbrk(0)) & ~(huge - 1);
    if (first && end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
    std::free(first);
#endif
}

} // namespace

int main(int argc, char** argv) {
    using namespace phynjo;
    prepare_heap();
    // The expressions live as long as the process: their pool is never destroyed (the
    // system takes the memory back at once; freeing the nodes and numbers one by one was
    // about 4% of compiling nlink_cart(10)).
    static cas::Pool* const pool = new cas::Pool;
    static const cas::PoolScope scope(*pool);
    std::string input, output, emit = "cpp", at_text, format = "text";
    bool have_at = false;
    bool with_main = false;
    std::size_t parts = 1, piece_threshold = codegen::kPieceThreshold, split_threshold = codegen::kSplitThreshold;
    // the options that shape generated C++, each a count within bounds
    struct CountOption {
        const char* name;
        std::size_t* target;
        unsigned long long lo, hi;
        const char* what;
    };
    constexpr auto any = ~0ull;
    const CountOption count_options[] = {{"--parts", &parts, 1, 16, "a number from 1 to 16"},
                                         {"--pieces-above", &piece_threshold, 1, any, "a positive number of statements"},
                                         {"--split-above", &split_threshold, 0, any, "a number of bytes"}};
    auto count_option = [&](const std::string& a) -> const CountOption* {
        for (const CountOption& c : count_options) {
            const std::string name = c.name;
            if (a == name || a.rfind(name + "=", 0) == 0) return &c;
        }
        return nullptr;
    };
    codegen::DeriveLimits derive_limits;
    std::size_t max_output = 256u << 20;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            std::cout << usage_text;
            return 0;
        }
        if (a == "--version") {
            std::cout << "phynjo-lagc " << PHYNJO_VERSION << "\n";
            return 0;
        }
        if (a == "-o") {
            if (++i >= argc) return usage_error("-o needs a file name");
            output = argv[i];
        } else if (a.rfind("--emit=", 0) == 0) {
            emit = a.substr(7);
            if (emit != "cpp" && emit != "eom" && emit != "latex" && emit != "linear" && emit != "kernel")
                return usage_error("unknown --emit kind '" + emit + "'");
        } else if (a == "--at" || a.rfind("--at=", 0) == 0) {
            if (a == "--at" && ++i >= argc) return usage_error("--at needs a state, e.g. --at th=pi");
            at_text = a == "--at" ? argv[i] : a.substr(5);
            have_at = true;
        } else if (a.rfind("--format=", 0) == 0) {
            format = a.substr(9);
            if (format != "text" && format != "latex") return usage_error("unknown --format '" + format + "' (text or latex)");
        } else if (a == "--main") with_main = true;
        else if (const CountOption* c = count_option(a)) {
            // `--NAME N` or `--NAME=N`, N within the option's bounds
            const std::string name = c->name;
            if (a == name && ++i >= argc) return usage_error(name + " needs " + c->what);
            const std::string v = a == name ? argv[i] : a.substr(name.size() + 1);
            char* end = nullptr;
            const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
            if (v.empty() || *end != '\0' || n < c->lo || n > c->hi)
                return usage_error(name + " takes " + c->what + ", not '" + v + "'");
            *c->target = static_cast<std::size_t>(n);
        }
        else if (a.rfind("--max-nodes=", 0) == 0 || a.rfind("--max-output=", 0) == 0) {
            const std::string v = a.substr(a.find('=') + 1);
            char* end = nullptr;
            const unsigned long long n = std::strtoull(v.c_str(), &end, 10);
            if (v.empty() || *end != '\0' || n == 0) return usage_error("bad value in '" + a + "'");
            (a[6] == 'n' ? derive_limits.max_nodes : max_output) = static_cast<std::size_t>(n);
        }
        else if (!a.empty() && a[0] == '-' && a != "-") return usage_error("unknown option '" + a + "'");
        else if (input.empty()) input = a;
        else return usage_error("more than one model file");
    }
    if (input.empty()) return usage_error("missing model file");
    if ((emit == "cpp" || emit == "kernel") && output.empty()) return usage_error("-o OUT.cpp is needed to write C++");
    if ((parts != 1 || piece_threshold != codegen::kPieceThreshold || split_threshold != codegen::kSplitThreshold) &&
        emit != "cpp" && !(emit == "kernel" && parts == 1 && split_threshold == codegen::kSplitThreshold))
        return usage_error("--parts, --split-above and --pieces-above shape generated C++: they do not go with --emit=" + emit);
    if (with_main && emit != "cpp") return usage_error("--main adds a main() to generated C++: it does not go with --emit=" + emit);
    if (have_at && emit != "linear") return usage_error("--at gives the state of --emit=linear");
    if (format != "text" && emit != "linear") return usage_error("--format goes with --emit=linear");
    // --at: NAME=EXPR items, split at commas outside parentheses
    std::vector<std::pair<std::string, cas::Expr>> at;
    if (have_at) {
        std::vector<std::string> items;
        std::string item;
        int depth = 0;
        for (char ch : at_text) {
            if (ch == ',' && depth == 0) {
                items.push_back(item);
                item.clear();
                continue;
            }
            depth += ch == '(' ? 1 : ch == ')' ? -1 : 0;
            item += ch;
        }
        items.push_back(item);
        for (const std::string& it : items) {
            const auto eq = it.find('=');
            std::string name = it.substr(0, eq);
            name.erase(0, name.find_first_not_of(' '));
            name.erase(name.find_last_not_of(' ') + 1);
            if (eq == std::string::npos || name.empty())
                return usage_error("--at: '" + it + "' is not NAME=EXPR (e.g. th=pi or th'=0)");
            try {
                at.emplace_back(name, grammar::parse(it.substr(eq + 1), "--at " + name));
            } catch (const std::exception& e) {
                std::cerr << e.what();
                return usage_error("--at: cannot read the value of " + name);
            }
        }
    }

    std::ifstream in(input, std::ios::binary);
    if (!in) {
        std::cerr << "phynjo-lagc: cannot read '" << input << "'\n";
        return 1;
    }
    const std::string text = slurp(in);
    grammar::DiagnosticSink sink(input, text);
    try {
        auto model = codegen::read_model(text, input, sink);
        std::optional<codegen::EquationsOfMotion> eom;
        if (model) eom = codegen::derive(*model, sink, derive_limits);
        if (!model || !eom) {
            std::cerr << sink.format_all();
            return 1;
        }
        if (emit == "linear") {
            std::string doc;
            try {
                doc = codegen::emit_linear(*model, codegen::linearize(*model, *eom, at), format == "latex");
            } catch (const codegen::LinearizeError& e) {
                std::cerr << "phynjo-lagc: --emit=linear: " << e.what() << "\n";
                return 1;
            }
            if (output.empty()) std::cout << doc;
            else if (!write_file(output, doc)) return 1;
            return 0;
        }
        if (emit == "eom" || emit == "latex") {
            const std::string doc = emit == "eom" ? codegen::emit_eom(*model, *eom) : codegen::emit_latex(*model, *eom);
            if (output.empty()) std::cout << doc;
            else if (!write_file(output, doc)) return 1;
            return 0;
        }
        if (emit == "kernel") { // one translation unit, no header beside it
            const std::string kernel =
                codegen::emit_kernel(*model, codegen::optimize(*model, *eom), {.header_name = {}, .piece_threshold = piece_threshold}, PHYNJO_VERSION);
            if (kernel.size() > max_output) {
                sink.error(model->lagrangian_where.offset, model->lagrangian_where.length,
                           "the generated code would be " + std::to_string(kernel.size()) + " bytes (the limit is " +
                               std::to_string(max_output) + ")");
                std::cerr << sink.format_all();
                return 1;
            }
            return write_file(output, kernel) ? 0 : 1;
        }
        std::string header_path = output;
        if (const auto dot = header_path.rfind('.'); dot != std::string::npos && header_path.find('/', dot) == std::string::npos)
            header_path.erase(dot);
        header_path += ".hpp";
        const std::string header_name = header_path.substr(header_path.find_last_of('/') + 1);
        const auto code = codegen::emit_cpp(*model, codegen::optimize(*model, *eom), {.header_name = header_name, .main = with_main, .parts = parts, .split_threshold = split_threshold, .piece_threshold = piece_threshold});
        std::size_t bytes = code.header.size() + code.source.size();
        for (const auto& part : code.parts) bytes += part.size();
        if (bytes > max_output) {
            sink.error(model->lagrangian_where.offset, model->lagrangian_where.length,
                       "the generated code would be " + std::to_string(bytes) + " bytes (the limit is " +
                           std::to_string(max_output) + ")");
            std::cerr << sink.format_all();
            return 1;
        }
        if (!write_file(header_path, code.header) || !write_file(output, code.source)) return 1;
        // OUT.part2.cpp …: the source's name with .partK before its extension
        const auto dot = output.rfind('.');
        const bool has_ext = dot != std::string::npos && output.find('/', dot) == std::string::npos;
        for (std::size_t k = 0; k < code.parts.size(); ++k) {
            const std::string tag = ".part" + std::to_string(k + 2);
            const std::string path = has_ext ? output.substr(0, dot) + tag + output.substr(dot) : output + tag;
            if (!write_file(path, code.parts[k])) return 1;
        }
    } catch (const std::exception& e) {
        std::cerr << sink.format_all() << input << ": error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
