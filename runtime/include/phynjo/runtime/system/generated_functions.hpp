#pragma once
/// \file
/// What the model functions of generated code need (Parameters' Derived, the solves of
/// M q'' = f and of the saddle-point system, the typed errors): the part files of a big
/// model (phynjo-lagc --parts) include only this, not the runtime integration of
/// generated.hpp, which saves about a second of g++ per file.
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/system/detail/derived.hpp"
#include "phynjo/runtime/system/detail/kkt_solve.hpp"
#include "phynjo/runtime/system/detail/lanes.hpp"
#include "phynjo/runtime/system/detail/symmetric_solve.hpp"
