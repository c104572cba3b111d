#pragma once
/// \file
/// Everything of phynjo::runtime.
#include "phynjo/runtime/component.hpp"
#include "phynjo/runtime/errors.hpp"
#include "phynjo/runtime/event.hpp"
#include "phynjo/runtime/executor.hpp"
#include "phynjo/runtime/forces.hpp"
#include "phynjo/runtime/integrators.hpp"
#include "phynjo/runtime/lagrangian.hpp"
#include "phynjo/runtime/literal.hpp"
#include "phynjo/runtime/nbody.hpp"
#include "phynjo/runtime/numeric.hpp"
#include "phynjo/runtime/process.hpp"
#include "phynjo/runtime/quaternion.hpp"
#include "phynjo/runtime/rigid_body.hpp"
#include "phynjo/runtime/world.hpp"
