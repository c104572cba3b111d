#pragma once
/// \file
/// Models compiled while a program runs (docs/command-line.md, *Kernels*): a `.lag` file or
/// text becomes a kernel — phynjo-lagc's `--emit=kernel`, then the C++ compiler into a shared
/// object — kept in a cache keyed by a hash of what decides its bits (the model text,
/// phynjo's version and the runtime headers the kernel includes, the compiler and its flags).
/// A second compile of the same model is a cache hit: no parse, no compiler.
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace phynjo::jit {

/// Where kernels are kept and how they are built.
struct JitOptions {
    /// The cache: empty means $PHYNJO_CACHE_DIR, else $XDG_CACHE_HOME/phynjo, else
    /// ~/.cache/phynjo.
    std::string cache_dir;
    /// The C++ compiler: empty means $CXX, else the one phynjo was built with.
    std::string compiler;
    /// Say on standard error what is compiled (or found in the cache) and how long it took.
    bool verbose = false;
    /// When the optimized kernel is not in the cache: build the quick one (-O0, about a third
    /// less compiler time; its code runs a few times slower) and return it, and build the
    /// optimized one in the background (optimized_kernel() finds it; the next compile of the
    /// model returns it). Both give the same bits: -O levels do not change what
    /// -ffp-contract=off arithmetic computes (tests/codegen/test_kernel_abi.cpp checks every
    /// function on every held model).
    bool quick = false;
};

/// The model has errors: what() is every diagnostic, `FILE:LINE:COL: error: …` with the line
/// and a caret.
class ModelError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// No C++ compiler, or it failed on a kernel: the message says what to install, or shows the
/// compiler's output and where the kernel's source is kept.
class BuildError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A compiled model.
struct CompiledModel {
    std::string kernel_path; ///< the shared object in the cache (load it with ModelKernel::load)
    std::string key;         ///< the cache key, 32 hex digits
    bool cache_hit = false;
    double compile_seconds = 0; ///< the C++ compiler's wall time (0 on a hit)
    bool quick = false;         ///< kernel_path is the quick kernel (JitOptions::quick)
    std::string optimized_path; ///< where the optimized kernel is (or will be) in the cache
};

/// Compiles `text` (its diagnostics naming `source_name`) to a kernel, or finds it in the
/// cache. A cached kernel that does not load, or whose bytes changed since it was written, is
/// rebuilt. Safe when several processes compile the same model at once (each writes its own
/// file and renames it into place). Throws ModelError, BuildError, std::runtime_error (the
/// cache cannot be written).
CompiledModel compile_model(std::string_view text, const std::string& source_name, const JitOptions& options = {});
/// The same for a file; std::runtime_error when it cannot be read.
CompiledModel compile_model_file(const std::string& path, const JitOptions& options = {});

/// The optimized kernel of a quick one (c.quick) once its background build has finished —
/// waiting for it up to `wait_seconds` while it runs — else nullopt (it failed, or is not
/// done yet). For c not quick: c's own kernel.
std::optional<std::string> optimized_kernel(const CompiledModel& c, double wait_seconds = 0);

/// The cache folder `options` name (made if missing).
std::string cache_directory(const JitOptions& options = {});

} // namespace phynjo::jit
