#pragma once
/// \file
/// Everything of phynjo::runtime, folder by folder (docs/architecture.md): core (components,
/// worlds, rules, workflows, the Process interpreter, events), particles (NState, 3-D
/// particles, forces, N-body), rigid bodies, collision, contacts, integrators, and models
/// (what generated code binds to).
#include "phynjo/runtime/core/archive.hpp"
#include "phynjo/runtime/core/component.hpp"
#include "phynjo/runtime/core/errors.hpp"
#include "phynjo/runtime/core/event.hpp"
#include "phynjo/runtime/core/executor.hpp"
#include "phynjo/runtime/core/literal.hpp"
#include "phynjo/runtime/core/unit_literal.hpp"
#include "phynjo/runtime/core/process.hpp"
#include "phynjo/runtime/core/splitting.hpp"
#include "phynjo/runtime/core/workflow.hpp"
#include "phynjo/runtime/core/world.hpp"

#include "phynjo/runtime/particles/force1d.hpp"
#include "phynjo/runtime/particles/force3d.hpp"
#include "phynjo/runtime/particles/nbody.hpp"
#include "phynjo/runtime/particles/nstate.hpp"
#include "phynjo/runtime/particles/particles3d.hpp"

#include "phynjo/runtime/rigid/quaternion.hpp"
#include "phynjo/runtime/rigid/rigid_body.hpp"
#include "phynjo/runtime/rigid/rigid_rules.hpp"
#include "phynjo/runtime/rigid/rigid_world.hpp"

#include "phynjo/runtime/collision/bounding_volume.hpp"
#include "phynjo/runtime/collision/broad_phase.hpp"
#include "phynjo/runtime/collision/collision_manager.hpp"
#include "phynjo/runtime/collision/narrow_phase.hpp"
#include "phynjo/runtime/collision/manifold.hpp"

#include "phynjo/runtime/contact/contact_solver.hpp"
#include "phynjo/runtime/contact/scene.hpp"

#include "phynjo/runtime/integrators/adaptive_verlet.hpp"
#include "phynjo/runtime/integrators/dormand_prince.hpp"
#include "phynjo/runtime/integrators/forest_ruth.hpp"
#include "phynjo/runtime/integrators/lagrangian_midpoint.hpp"
#include "phynjo/runtime/integrators/lagrangian_rattle.hpp"
#include "phynjo/runtime/integrators/lagrangian_rk4.hpp"
#include "phynjo/runtime/integrators/leapfrog.hpp"
#include "phynjo/runtime/integrators/nbody_leapfrog.hpp"
#include "phynjo/runtime/integrators/rigid_leapfrog.hpp"
#include "phynjo/runtime/integrators/rk4.hpp"
#include "phynjo/runtime/integrators/symplectic_euler.hpp"

#include "phynjo/runtime/system/constraint_projection.hpp"
#include "phynjo/runtime/simulate/archived_run.hpp"
#include "phynjo/runtime/simulate/generated.hpp"
#include "phynjo/runtime/view/recorder.hpp"
#include "phynjo/runtime/system/detail/kkt_solve.hpp"
#include "phynjo/runtime/system/detail/symmetric_solve.hpp"
