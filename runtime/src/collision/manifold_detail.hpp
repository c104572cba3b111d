#pragma once
// Shared by the manifold builders (runtime/src/collision): reducing a polygon of contact
// points to the four that hold the most.
#include "phynjo/runtime/collision/manifold.hpp"

namespace phynjo::runtime::manifold_detail {

/// out.points ← at most 4 of found[0..m) (m ≤ 8) and out.count (out.normal must be set): all when
/// m ≤ 4; else the deepest, the farthest from it, the one spanning the largest triangle
/// with those two, and the one adding the most area beyond that triangle (areas measured
/// across the normal). Ties go to the earlier point: the choice is deterministic.
void keep_four(const ManifoldPoint* found, int m, Manifold& out);

} // namespace phynjo::runtime::manifold_detail
