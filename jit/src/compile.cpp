// Models compiled at run time (jit/compile.hpp): the key, the cache, the compiler.
#include "phynjo/jit/compile.hpp"

#include "phynjo/codegen/emit.hpp"
#include "phynjo/codegen/optimize.hpp"
#include "phynjo/runtime/system/kernel.hpp"

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <random>
#include <sstream>
#include <thread>

#include "derived_model.hpp"

#ifndef PHYNJO_VERSION
#define PHYNJO_VERSION "unknown"
#endif
#ifndef PHYNJO_JIT_CXX
#define PHYNJO_JIT_CXX "c++"
#endif
#ifndef PHYNJO_JIT_SOURCE_INCLUDE
#define PHYNJO_JIT_SOURCE_INCLUDE ""
#endif
#ifndef PHYNJO_JIT_INSTALLED_INCLUDE
#define PHYNJO_JIT_INSTALLED_INCLUDE ""
#endif
#ifndef PHYNJO_JIT_BINARY_DIR
#define PHYNJO_JIT_BINARY_DIR ""
#endif
#ifndef PHYNJO_JIT_LIBMVEC
#define PHYNJO_JIT_LIBMVEC 0
#endif
#ifndef PHYNJO_JIT_NATIVE
#define PHYNJO_JIT_NATIVE 0
#endif

namespace fs = std::filesystem;

namespace phynjo::jit {

namespace {

/// Two FNV-1a hashes of 64 bits from different bases: a 128-bit key. Not a defence against
/// an attacker who writes the cache, only against collisions of honest inputs.
struct Hash {
    std::uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull;
    Hash& add(std::string_view s) {
        for (const unsigned char c : s) {
            a = (a ^ c) * 0x100000001b3ull;
            b = (b ^ c) * 0x100000001b3ull + 0x9e3779b97f4a7c15ull;
        }
        a = (a ^ 0xff) * 0x100000001b3ull; // a separator: ("ab", "c") and ("a", "bc") differ
        return *this;
    }
    [[nodiscard]] std::string hex() const {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(a), static_cast<unsigned long long>(b));
        return buf;
    }
};

std::string read_text(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) return {};
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

bool write_text(const fs::path& p, std::string_view text) {
    std::ofstream out(p, std::ios::binary);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    return static_cast<bool>(out.flush());
}

/// A unique name beside `p` for a file to be renamed over it.
fs::path temporary_beside(const fs::path& p) {
    static std::mt19937_64 rng(std::random_device{}() ^ static_cast<std::uint64_t>(::getpid()));
    static std::mutex m;
    std::lock_guard lock(m);
    return p.string() + "." + std::to_string(::getpid()) + "." + std::to_string(rng() % 1000000000) + ".tmp";
}

/// The runtime headers a kernel includes: $PHYNJO_INCLUDE_DIR, else the source tree's when
/// this program (or the library holding this code: the Python module) is in phynjo's build
/// tree, else the nearest include/ above that file that holds them (PREFIX/include beside
/// PREFIX/bin/phynjo-run or PREFIX/lib/python3.X/dist-packages/phynjo), else the configured
/// install folder's (then the source tree's, for a program outside all).
fs::path include_dir() {
    const auto has_abi = [](const fs::path& d) { return !d.empty() && fs::exists(d / "phynjo/runtime/system/kernel_abi.h"); };
    if (const char* e = std::getenv("PHYNJO_INCLUDE_DIR"); e && *e) return e;
    std::error_code ec;
    const std::string self = fs::read_symlink("/proc/self/exe", ec).string();
    std::string library;
    if (Dl_info info{}; ::dladdr(reinterpret_cast<const void*>(&include_dir), &info) != 0 && info.dli_fname)
        library = fs::weakly_canonical(fs::absolute(info.dli_fname, ec), ec).string();
    const std::string build = PHYNJO_JIT_BINARY_DIR;
    const auto in_build = [&](const std::string& f) { return !build.empty() && f.rfind(build + "/", 0) == 0; };
    if ((in_build(self) || in_build(library)) && has_abi(PHYNJO_JIT_SOURCE_INCLUDE)) return PHYNJO_JIT_SOURCE_INCLUDE;
    for (const std::string& file : {library, self}) {
        if (file.empty()) continue;
        for (fs::path d = fs::path(file).parent_path(); !d.empty() && d != d.root_path(); d = d.parent_path())
            if (has_abi(d / "include")) return d / "include";
    }
    if (has_abi(PHYNJO_JIT_INSTALLED_INCLUDE)) return PHYNJO_JIT_INSTALLED_INCLUDE;
    if (has_abi(PHYNJO_JIT_SOURCE_INCLUDE)) return PHYNJO_JIT_SOURCE_INCLUDE;
    throw BuildError("phynjo's runtime headers are not found (set PHYNJO_INCLUDE_DIR to the folder holding "
                     "phynjo/runtime/system/kernel_abi.h)");
}

std::string compiler_of(const JitOptions& o) {
    if (!o.compiler.empty()) return o.compiler;
    if (const char* e = std::getenv("CXX"); e && *e) return e;
    return PHYNJO_JIT_CXX;
}

std::string shell_quoted(const std::string& s) {
    std::string out = "'";
    for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

/// The first line `compiler --version` prints ("g++ (Debian 12.2.0-14) 12.2.0"), or empty
/// when it does not run.
std::string compiler_identity(const std::string& compiler) {
    static std::mutex m;
    static std::string last_compiler, last_identity;
    std::lock_guard lock(m);
    if (compiler == last_compiler) return last_identity;
    std::string line;
    if (std::FILE* p = ::popen((shell_quoted(compiler) + " --version 2>/dev/null").c_str(), "r")) {
        char buf[512];
        if (std::fgets(buf, sizeof buf, p)) line = buf;
        ::pclose(p);
    }
    while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
    last_compiler = compiler;
    last_identity = line;
    return line;
}

/// This phynjo's build: the file holding this code (an executable, or the Python module),
/// its size and time. A rebuilt phynjo may emit other kernels for the same text, even at the
/// same version: it does not reuse the kernels of the build before.
std::string build_identity() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<const void*>(&build_identity), &info) == 0 || !info.dli_fname) return "unknown build";
    struct stat st {};
    if (::stat(info.dli_fname, &st) != 0) return info.dli_fname;
    return std::string(info.dli_fname) + ":" + std::to_string(st.st_size) + ":" + std::to_string(st.st_mtim.tv_sec) + "." +
           std::to_string(st.st_mtim.tv_nsec);
}

/// The flags of every kernel (at -O0 for the quick tier, JitOptions::quick): those of
/// phynjo_add_model's model code
/// (cmake/PhynjoAddModel.cmake) — every operation rounded once (-ffp-contract=off), so a kernel
/// gives the bits of the CMake-built model — and its own functions hidden (only the table's
/// entry point is exported: nothing of one kernel can stand in for another's). A build
/// configured with PHYNJO_NATIVE compiles both for the machine (-march=native: four runs a
/// register in a sweep's lanes where the CPU has AVX2, against two).
std::vector<std::string> kernel_flags(bool quick = false) {
    std::vector<std::string> f{"-std=c++20", quick ? "-O0" : "-O2", "-fPIC", "-fvisibility=hidden", "-fno-tree-slp-vectorize", "-ffp-contract=off", "-w"};
    if (PHYNJO_JIT_NATIVE) f.push_back("-march=native");
    if (PHYNJO_JIT_LIBMVEC) f.push_back("-DPHYNJO_LIBMVEC=1");
    return f;
}

/// -fuse-ld=gold where Debian's binutils installed gold: it links a kernel in half the time
/// of ld.bfd (0.06 s against 0.13 s on the bench machine), the same bytes of code.
std::string fast_linker() {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "/usr/bin:/bin";
    for (std::size_t at = 0; at <= dirs.size();) {
        const std::size_t end = std::min(dirs.find(':', at), dirs.size());
        const std::string dir = dirs.substr(at, end - at);
        if (!dir.empty() && ::access((fs::path(dir) / "ld.gold").c_str(), X_OK) == 0) return "-fuse-ld=gold";
        at = end + 1;
    }
    return {};
}

/// What -march=native means on this machine, for the cache keys of a native build: a cache
/// folder shared by machines of other CPUs (a home on NFS) must not hand one the other's
/// kernels. The CPU's model and feature flags as Linux reports them; empty in a portable build.
std::string cpu_identity() {
    if (!PHYNJO_JIT_NATIVE) return {};
    std::ifstream in("/proc/cpuinfo");
    std::string line, model, flags;
    while (std::getline(in, line) && (model.empty() || flags.empty())) {
        if (model.empty() && line.rfind("model name", 0) == 0) model = line;
        if (flags.empty() && line.rfind("flags", 0) == 0) flags = line;
    }
    return model + "\n" + flags;
}

/// Runs `command` (a shell line), its output into `log`: the exit status.
int run(const std::string& command, const fs::path& log) {
    const int rc = std::system((command + " >" + shell_quoted(log.string()) + " 2>&1").c_str());
    return rc == -1 ? -1 : WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
}

/// The checksum a kernel's bytes had when it was written (its `.sum` beside it).
std::string checksum(const fs::path& p) { return Hash().add(read_text(p)).hex(); }

/// True when the cached kernel loads and its bytes are those written.
bool usable(const fs::path& so, const fs::path& sum) {
    if (!fs::exists(so) || !fs::exists(sum)) return false;
    if (read_text(sum) != checksum(so)) return false;
    try {
        (void)runtime::ModelKernel::load(so.string());
        return true;
    } catch (const runtime::KernelError&) {
        return false;
    }
}

/// A kernel in the cache and its checksum.
struct Tier {
    fs::path so, sum;
    /// KEY.so.new, KEY.building, KEY.O2-failed: the files of its background build.
    [[nodiscard]] fs::path fresh() const { return fs::path(so).concat(".new"); }
    [[nodiscard]] fs::path building() const { return fs::path(so).replace_extension(".building"); }
    [[nodiscard]] fs::path failed() const { return fs::path(so).replace_extension(".O2-failed"); }
};

/// `built` (a kernel just written) into place as `tier`: the checksum first, then the kernel,
/// so a reader finding the kernel finds its checksum.
void install(const fs::path& built, const Tier& tier) {
    std::error_code ec;
    const fs::path sum_tmp = temporary_beside(tier.sum);
    if (!write_text(sum_tmp, checksum(built))) throw std::runtime_error("cannot write " + sum_tmp.string());
    fs::rename(sum_tmp, tier.sum, ec);
    fs::rename(built, tier.so, ec);
    if (ec) throw std::runtime_error("cannot write " + tier.so.string() + ": " + ec.message());
}

/// The optimized kernel a background build left (KEY.so.new: written whole, then renamed)
/// checked and installed; false when there is none or it does not load.
bool adopt(const Tier& full) {
    const fs::path fresh = full.fresh();
    std::error_code ec;
    if (!fs::exists(fresh, ec)) return false;
    const fs::path mine = temporary_beside(full.so);
    fs::rename(fresh, mine, ec); // one process adopts it; the others find it installed
    if (ec) return usable(full.so, full.sum);
    try {
        (void)runtime::ModelKernel::load(mine.string());
        install(mine, full);
        return true;
    } catch (const std::exception&) {
        fs::remove(mine, ec);
        return false;
    }
}

/// Starts `command` (building KEY.so at -O2 into `target`, a temporary name) in the background, the
/// result renamed to KEY.so.new for adopt(); KEY.building says it runs (one build at a time
/// per cache and key, a stale one retried after ten minutes), KEY.O2-failed that it failed
/// (never retried: the log is beside it). The process may exit meanwhile: the next compile
/// of the model adopts the kernel.
void optimize_in_background(const Tier& full, const std::string& command, const fs::path& target, const fs::path& log) {
    const fs::path building = full.building(), failed = full.failed();
    std::error_code ec;
    if (fs::exists(failed, ec)) return;
    if (fs::exists(building, ec)) {
        const auto age = fs::file_time_type::clock::now() - fs::last_write_time(building, ec);
        if (!ec && age < std::chrono::minutes(10)) return;
    }
    if (!write_text(building, std::to_string(::getpid()))) return;
    const std::string built = shell_quoted(target.string());
    const std::string script = "(" + command + " >" + shell_quoted(log.string()) + " 2>&1 && mv -f " + built + " " +
                               shell_quoted(full.fresh().string()) + " || { rm -f " + built +
                               "; touch " + shell_quoted(failed.string()) + "; }; rm -f " + shell_quoted(building.string()) +
                               ") </dev/null >/dev/null 2>&1 &";
    if (std::system(script.c_str()) != 0) fs::remove(building, ec);
}

} // namespace

std::string cache_directory(const JitOptions& o) {
    fs::path dir;
    if (!o.cache_dir.empty()) dir = o.cache_dir;
    else if (const char* e = std::getenv("PHYNJO_CACHE_DIR"); e && *e) dir = e;
    else if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) dir = fs::path(x) / "phynjo";
    else if (const char* h = std::getenv("HOME"); h && *h) dir = fs::path(h) / ".cache" / "phynjo";
    else dir = fs::temp_directory_path() / "phynjo-cache";
    std::error_code ec;
    fs::create_directories(dir / "kernels", ec);
    if (ec || !fs::is_directory(dir / "kernels"))
        throw std::runtime_error("cannot make the kernel cache " + (dir / "kernels").string() + ": " + ec.message());
    return dir.string();
}

CompiledModel compile_model(std::string_view text, const std::string& source_name, const JitOptions& o) {
    const fs::path cache = cache_directory(o);
    const std::string compiler = compiler_of(o);
    const std::string identity = compiler_identity(compiler);
    if (identity.empty())
        throw BuildError("no C++ compiler: '" + compiler + "' does not run (install Debian's g++, or set CXX)");
    const fs::path include = include_dir();

    // the key: what decides the kernel's bits
    std::string flags;
    for (const std::string& f : kernel_flags()) flags += f + " ";
    Hash h;
    const std::string cpu = cpu_identity();
    h.add("phynjo kernel").add(std::to_string(PHYNJO_KERNEL_ABI_VERSION)).add(PHYNJO_VERSION).add(build_identity()).add(text).add(compiler).add(identity).add(flags).add(cpu);
    const std::string linker = fast_linker();
    h.add(linker);
    for (const char* header : {"system/kernel_support.hpp", "system/kernel_abi.h", "system/detail/derived.hpp",
                               "system/detail/factor_core.hpp", "system/detail/lanes.hpp"})
        h.add(read_text(include / "phynjo/runtime" / header));
    CompiledModel out;
    out.key = h.hex();
    const fs::path dir = cache / "kernels";
    const Tier full{dir / (out.key + ".so"), dir / (out.key + ".sum")},
        quick{dir / (out.key + ".quick.so"), dir / (out.key + ".quick.sum")};
    out.kernel_path = out.optimized_path = full.so.string();
    if (usable(full.so, full.sum) || adopt(full)) {
        out.cache_hit = true;
        if (o.verbose) std::fprintf(stderr, "phynjo: %s: the kernel is in the cache (%s)\n", source_name.c_str(), full.so.c_str());
        return out;
    }
    const fs::path cpp = dir / (out.key + ".cpp");
    auto command = [&](const fs::path& target, bool at_o0) {
        std::string cmd = shell_quoted(compiler);
        for (const std::string& f : kernel_flags(at_o0)) cmd += " " + f;
        if (!linker.empty()) cmd += " " + linker;
        cmd += " -I" + shell_quoted(include.string()) + " -shared -o " + shell_quoted(target.string()) + " " + shell_quoted(cpp.string());
        if (PHYNJO_JIT_LIBMVEC) cmd += " -lmvec";
        return cmd;
    };
    auto optimize = [&] {
        const fs::path target = temporary_beside(full.so);
        optimize_in_background(full, command(target, false), target, dir / (out.key + ".O2.log"));
    };
    if (o.quick && usable(quick.so, quick.sum)) {
        out.cache_hit = out.quick = true;
        out.kernel_path = quick.so.string();
        if (fs::exists(cpp)) optimize();
        if (o.verbose) std::fprintf(stderr, "phynjo: %s: the quick kernel is in the cache (%s)\n", source_name.c_str(), quick.so.c_str());
        return out;
    }

    // the model: parsed, derived, optimized, emitted (its own pool of expressions)
    const std::string kernel = detail::with_derived_model(text, source_name, [](const auto& model, const auto& eom) {
        return codegen::emit_kernel(model, codegen::optimize(model, eom), {}, PHYNJO_VERSION);
    });
    const fs::path log = dir / (out.key + ".log");
    const fs::path cpp_tmp = temporary_beside(cpp);
    if (!write_text(cpp_tmp, kernel)) throw std::runtime_error("cannot write " + cpp_tmp.string());
    std::error_code ec;
    fs::rename(cpp_tmp, cpp, ec);

    const Tier& tier = o.quick ? quick : full;
    const fs::path so_tmp = temporary_beside(tier.so);
    const std::string cmd = command(so_tmp, o.quick);
    const auto t0 = std::chrono::steady_clock::now();
    const int rc = run(cmd, log);
    out.compile_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (rc != 0) {
        fs::remove(so_tmp, ec);
        std::string output = read_text(log);
        if (output.size() > 4000) output = output.substr(0, 4000) + "\n…";
        throw BuildError("the C++ compiler failed on the kernel of " + source_name + " (" + cpp.string() + "):\n" + cmd + "\n" +
                         output);
    }
    install(so_tmp, tier);
    out.kernel_path = tier.so.string();
    out.quick = o.quick;
    if (o.quick) optimize();
    if (o.verbose)
        std::fprintf(stderr, "phynjo: %s: compiled its %skernel in %.2f s (%s, with the headers in %s)\n", source_name.c_str(),
                     o.quick ? "quick " : "", out.compile_seconds, tier.so.c_str(), include.c_str());
    return out;
}

std::optional<std::string> optimized_kernel(const CompiledModel& c, double wait_seconds) {
    const fs::path so = c.optimized_path;
    if (so.empty()) return std::nullopt;
    const Tier full{so, fs::path(so).replace_extension(".sum")};
    const fs::path building = full.building();
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(wait_seconds);
    for (;;) {
        if (usable(full.so, full.sum) || adopt(full)) return full.so.string();
        std::error_code ec;
        if (!fs::exists(building, ec) || std::chrono::steady_clock::now() >= until) return std::nullopt;
        // a build left unfinished (its process killed): nothing to wait for
        if (fs::file_time_type::clock::now() - fs::last_write_time(building, ec) > std::chrono::minutes(10) || ec)
            return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
}

CompiledModel compile_model_file(const std::string& path, const JitOptions& o) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read '" + path + "'");
    std::ostringstream s;
    s << in.rdbuf();
    return compile_model(s.str(), path, o);
}

} // namespace phynjo::jit
