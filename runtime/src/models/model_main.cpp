// The command-line driver every generated simulator links (model_main.hpp).
#include "phynjo/runtime/models/model_main.hpp"

#include "phynjo/runtime/integrators/dormand_prince.hpp"
#include "phynjo/runtime/integrators/lagrangian_midpoint.hpp"
#include "phynjo/runtime/integrators/lagrangian_rk4.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace phynjo::runtime {

int model_main(int argc, char** argv, const ModelCommandLine& model) {
    double t_end = 10, dt = 1e-3;
    std::string integrator = "rk4", output;
    long every = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&](const char* opt) -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s: %s needs a value\n", argv[0], opt);
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--t-end") t_end = std::atof(value("--t-end").c_str());
        else if (a == "--dt") dt = std::atof(value("--dt").c_str());
        else if (a == "--integrator") integrator = value("--integrator");
        else if (a == "--every") every = std::atol(value("--every").c_str());
        else if (a == "--output" || a == "-o") output = value("--output");
        else if (a == "--param") {
            const std::string kv = value("--param");
            const auto eq = kv.find('=');
            const std::string name = kv.substr(0, eq);
            const double v = eq == std::string::npos ? 0 : std::atof(kv.c_str() + eq + 1);
            bool found = false;
            for (const auto& [pname, set] : model.parameters)
                if (name == pname) {
                    set(v);
                    found = true;
                }
            if (!found || eq == std::string::npos) {
                std::fprintf(stderr, "%s: unknown parameter in '%s'\n", argv[0], kv.c_str());
                return 2;
            }
        } else if (a == "--help" || a == "-h") {
            std::printf("usage: %s [--t-end T] [--dt DT] [--integrator rk4|dopri|midpoint] [--every K]\n"
                        "          [--param NAME=VALUE]... [--output FILE]\n"
                        "Simulates the model from its initial state and writes CSV: t, q..., q'..., E.\n",
                        argv[0]);
            return 0;
        } else {
            std::fprintf(stderr, "%s: unknown option '%s' (try --help)\n", argv[0], a.c_str());
            return 2;
        }
    }
    if (!(dt > 0) || !(t_end >= 0) || (integrator != "rk4" && integrator != "dopri" && integrator != "midpoint")) {
        std::fprintf(stderr, "%s: need --dt > 0, --t-end >= 0 and --integrator rk4, dopri or midpoint\n", argv[0]);
        return 2;
    }
    const long steps = static_cast<long>(std::llround(t_end / dt));
    if (every <= 0) every = std::max(1L, steps / 5000);
    std::FILE* out = output.empty() ? stdout : std::fopen(output.c_str(), "w");
    if (!out) {
        std::fprintf(stderr, "%s: cannot write %s\n", argv[0], output.c_str());
        return 1;
    }
    const LagrangianSystem sys = model.system();
    World w = make_lagrangian_world(sys);
    const std::size_t dof = sys.dof;
    std::fprintf(out, "t");
    for (const auto& n : sys.coordinate_names) std::fprintf(out, ",%s", n.c_str());
    for (const auto& n : sys.coordinate_names) std::fprintf(out, ",%s'", n.c_str());
    std::fprintf(out, ",E\n");
    auto row = [&] {
        std::fprintf(out, "%.17g", w.time);
        for (std::size_t i = 0; i < dof; ++i) std::fprintf(out, ",%.17g", w.at(kGQ, static_cast<Index>(i)));
        for (std::size_t i = 0; i < dof; ++i) std::fprintf(out, ",%.17g", w.at(kGV, static_cast<Index>(i)));
        std::fprintf(out, ",%.17g\n", sys.energy(w.time, w.field(kGQ), w.field(kGV)));
    };
    int status = 0;
    try {
        row();
        if (integrator == "dopri") {
            DormandPrince45 dp(sys, {});
            double h = dt;
            for (long k = 1; k <= steps; ++k) {
                const double target = static_cast<double>(k) * dt;
                while (w.time < target - 1e-12 * dt)
                    h = dp.step(w, std::min(dp.next_dt() > 0 ? dp.next_dt() : h, target - w.time), target);
                w.time = target;
                if (k % every == 0) row();
            }
        } else {
            Stepper stepper(integrator == "rk4" ? lagrangian_rk4(sys, w.layout_ptr()) : lagrangian_midpoint(sys, w.layout_ptr()));
            for (long k = 1; k <= steps; ++k) {
                stepper.step(w, dt);
                if (k % every == 0) row();
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: simulation stopped at t = %.17g: %s\n", argv[0], w.time, e.what());
        status = 1;
    }
    if (out != stdout) std::fclose(out);
    return status;
}

} // namespace phynjo::runtime
