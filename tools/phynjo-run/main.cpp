// phynjo-run MODEL.lag [the options of a simulator]: the model compiled into a kernel unless
// the cache holds it (phynjo/jit/compile.hpp), loaded (phynjo/runtime/system/kernel.hpp) and
// run by the simulators' driver — every option a generated simulator has, no CMake project
// (docs/command-line.md).
#include "phynjo/jit/compile.hpp"
#include "phynjo/runtime/simulate/model_main.hpp"
#include "phynjo/runtime/system/kernel.hpp"
#ifdef PHYNJO_MPI
#include "phynjo/mpi/mpi_sweep.hpp"
#endif

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr const char* usage_text =
    R"(usage: phynjo-run [--verbose] [--cache-dir DIR] MODEL.lag [the simulator's options]
       phynjo-run MODEL.lag --help      (the simulator's options for this model)

Compiles a model (.lag, docs/language.md) into a kernel — once: a second run of the same
model finds it in the cache — and runs it as the simulator phynjo_add_model(... MAIN) would
build: the same options (--t-end, --dt, --integrator, --param, --init, --output, --events,
--shapes, --html, sweeps with --grid/--summary, --threads, ...), the same output, bit for bit.

  --verbose        say whether the kernel was compiled or found in the cache, and how long
                   compiling took
  --cache-dir DIR  the kernel cache (default: $PHYNJO_CACHE_DIR, else $XDG_CACHE_HOME/phynjo,
                   else ~/.cache/phynjo)
The C++ compiler is $CXX, else the one phynjo was built with. docs/command-line.md.

exit status: 0 done, 1 the model has errors or the run failed, 2 usage error, 3 energy drift
(--fail-on-drift)
)";

} // namespace

int main(int argc, char** argv) {
    using namespace phynjo;
    jit::JitOptions options;
    int i = 1;
    for (; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--verbose") options.verbose = true;
        else if (a == "--cache-dir") {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "phynjo-run: --cache-dir needs a folder\n");
                return 2;
            }
            options.cache_dir = argv[++i];
        } else if (a == "--help" || a == "-h") {
            std::fputs(usage_text, stdout);
            return 0;
        } else if (a == "--version") {
            std::printf("phynjo-run %s\n", PHYNJO_VERSION);
            return 0;
        } else break;
    }
    if (i >= argc) {
        std::fprintf(stderr, "phynjo-run: no model file (try --help)\n");
        return 2;
    }
    const std::string model_file = argv[i];
    if (!model_file.empty() && model_file[0] == '-') {
        std::fprintf(stderr, "phynjo-run: unknown option '%s' before the model file (try --help)\n", model_file.c_str());
        return 2;
    }
    std::shared_ptr<const runtime::ModelKernel> kernel;
    try {
        const jit::CompiledModel compiled = jit::compile_model_file(model_file, options);
        kernel = runtime::ModelKernel::load(compiled.kernel_path);
    } catch (const jit::ModelError& e) {
        std::fputs(e.what(), stderr);
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "phynjo-run: %s\n", e.what());
        return 1;
    }
    runtime::KernelParameters P(kernel);
    const phynjo_kernel& t = kernel->table();
    runtime::ModelCommandLine model{t.model_name, {}, [&P] { return runtime::kernel_system(P); }};
    for (std::size_t k = 0; k < t.n_parameters; ++k)
        model.parameters.emplace_back(t.parameter_names[k], [&P, k](double v) { P.set(k, v); });
    // the driver sees "phynjo-run MODEL.lag" as its program, then the options after the model
    std::string program = std::string("phynjo-run ") + model_file;
    std::vector<char*> args{program.data()};
    for (int k = i + 1; k < argc; ++k) args.push_back(argv[k]);
    args.push_back(nullptr);
    const int n = static_cast<int>(args.size()) - 1;
#ifdef PHYNJO_MPI
    return mpi::model_main(n, args.data(), model);
#else
    return runtime::model_main(n, args.data(), model);
#endif
}
