#pragma once
/// \file
/// Ensembles of runs of a generated model: parameter and initial-condition sweeps (a grid, or
/// Monte Carlo samples, or both), every run from its own values to the same end, spread over
/// threads, summarized one CSV row per run in a fixed order — byte-identical whatever the
/// thread count, and resumable. The simulators' `--grid`, `--samples`, `--uniform`, `--summary`
/// (model_main.hpp) are this module.
#include "phynjo/runtime/simulate/runs.hpp"
#include "phynjo/runtime/simulate/sweep.hpp"
#include "phynjo/runtime/simulate/sweep_plan.hpp"
