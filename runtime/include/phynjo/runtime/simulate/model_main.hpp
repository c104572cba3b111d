#pragma once
/// \file
/// The command-line simulator of a generated model (`phynjo-lagc --main`, `phynjo_add_model(…
/// MAIN)`): the generated main() only names the model's parameters and hands over; the
/// options, the integrators and the CSV output are this one tested driver.
///
///   MODEL [--t-end T] [--dt DT] [--integrator NAME] [--every K]
///         [--param NAME=VALUE]... [--output FILE]
/// simulates from the model's initial state and writes CSV: t, q…, q'…, E. The integrators
/// are those of integrator_registry.hpp; --help lists every option.
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <functional>
#include <string_view>
#include <utility>
#include <vector>

namespace phynjo::runtime {

/// What the driver needs of a generated model.
struct ModelCommandLine {
    std::string_view model_name;
    /// Every parameter by name, with how to set it (--param, before the run). Setting a
    /// parameter defined from others fixes it; the others follow what they are defined from.
    std::vector<std::pair<std::string_view, std::function<void(double)>>> parameters;
    /// The model at the current parameter values.
    std::function<LagrangianSystem()> system;
};

class SweepProcesses; // ensemble.hpp

/// Runs the simulator: exit status 0 on success, 1 when the run stops on an error (the
/// message names the time), 2 for a usage error.
int model_main(int argc, char** argv, const ModelCommandLine& model);
/// The same, one of several processes (MPI ranks: phynjo/mpi/mpi_sweep.hpp) that every one
/// call this with the same arguments: a sweep is shared among them (run_sweep); only rank 0
/// prints; anything but a sweep on more than one process is a usage error.
int model_main(int argc, char** argv, const ModelCommandLine& model, SweepProcesses* processes);

} // namespace phynjo::runtime
