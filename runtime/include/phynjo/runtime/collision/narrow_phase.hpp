#pragma once
/// \file
/// Narrow phase: candidate pairs from a broad phase become
/// contacts between sphere shapes (bodies with radius > 0), and spheres meet static planes.
#include "phynjo/runtime/collision/broad_phase.hpp"
#include "phynjo/runtime/core/world.hpp"

#include <Eigen/Core>

#include <span>
#include <vector>

namespace phynjo::runtime {

/// A static plane {x : n·x = offset} with unit normal n; bodies belong on the side n·x > offset.
struct Plane {
    Eigen::Vector3d normal = Eigen::Vector3d(0, 1, 0);
    double offset = 0; ///< m
    /// The ground: y = 0, normal +y.
    static Plane ground() { return {}; }
    /// Throws std::invalid_argument unless the normal is unit (within 1e-9) and all is finite.
    void validate() const;
};

/// A contact seen from body a: b is another body, or the static plane `plane` (then b is unused).
struct Contact {
    Index a = 0, b = 0;
    int plane = -1;           ///< index of the plane, or −1 for a body–body contact
    Eigen::Vector3d normal;   ///< unit, from b (or the plane) towards a
    double separation = 0;    ///< signed surface distance, m: > 0 apart, < 0 penetrating
};

/// Sphere–sphere contacts of a rigid world for the candidate pairs of boxes `ids[k]` (box k
/// belongs to body ids[k]), kept when the surfaces are closer than `margin` (m):
///   n = (p_a − p_b)/|p_a − p_b|,  separation = |p_a − p_b| − r_a − r_b.
/// Coincident centres get n = +y (any unit vector would do; this one is deterministic).
void sphere_sphere_contacts(const World& w, std::span<const CandidatePair> pairs, std::span<const Index> ids,
                            double margin, std::vector<Contact>& out);
/// Sphere–plane contacts: separation = n·p − offset − r, kept when below `margin`.
void sphere_plane_contacts(const World& w, std::span<const Index> bodies, std::span<const Plane> planes,
                           double margin, std::vector<Contact>& out);
/// The same with a margin per body (margins[k] for ids[k]): a pair is kept when its surfaces
/// are closer than margins[a] + margins[b], a body and a plane closer than margins[a].
void sphere_sphere_contacts(const World& w, std::span<const CandidatePair> pairs, std::span<const Index> ids,
                            std::span<const double> margins, std::vector<Contact>& out);
void sphere_plane_contacts(const World& w, std::span<const Index> bodies, std::span<const Plane> planes,
                           std::span<const double> margins, std::vector<Contact>& out);

} // namespace phynjo::runtime
