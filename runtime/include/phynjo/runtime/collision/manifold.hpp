#pragma once
/// \file
/// Contact manifolds between shapes (boxes, spheres, capsules, static planes): one normal and
/// up to four points, each with its separation and a feature id that names the pair of
/// features it came from, so that the solver recognises the same contact from step to step
/// and warm-starts it (Catto, "Contact manifolds", GDC 2007; Gregorius, "Robust contact
/// creation for physics simulations", GDC 2015).
///
/// Conventions: the normal is unit and points from b towards a; a point's `on_a` and `on_b`
/// lie on the two surfaces and separation = (on_a − on_b)·normal: > 0 apart, < 0 penetrating.
/// Points are kept while their separation is below `margin` (m; speculative contacts).
#include "phynjo/runtime/collision/bounding_volume.hpp"
#include "phynjo/runtime/collision/narrow_phase.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>

namespace phynjo::runtime {

/// The points within `radius` of the segment [p0, p1] (m).
struct Capsule {
    Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), p1 = Eigen::Vector3d::Zero();
    double radius = 0;
};

struct ManifoldPoint {
    Eigen::Vector3d on_a = Eigen::Vector3d::Zero(), on_b = Eigen::Vector3d::Zero(); ///< world, m
    double separation = 0;  ///< (on_a − on_b)·normal, m
    std::uint32_t feature = 0; ///< the pair of features (vertices, edges, faces) it came from
};

struct Manifold {
    Eigen::Vector3d normal = Eigen::Vector3d(0, 1, 0); ///< unit, from b towards a
    int count = 0;                                     ///< points in use (0: no contact)
    std::array<ManifoldPoint, 4> points{};
    /// The same contact seen from the other side: normal and points' sides swapped.
    void flip();
};

/// Box a against box b: separating axes (the 3 face normals of each and the 9 edge
/// cross products; an edge axis wins only when it separates clearly more than the best face,
/// a face of b only when clearly more than a's: the choice does not flicker for resting
/// boxes); for a face axis, the incident face of the other box (the most anti-parallel)
/// clipped against the side planes of the reference face (Sutherland–Hodgman), points
/// beyond the margin dropped, at most 4 kept (the deepest, the farthest from it, then
/// those spanning the largest area); for an edge axis, the closest points of the two edges.
/// Feature id: reference box and face, incident face, and the corner of the reference face
/// and vertex of the incident face nearest the point (so a point keeps its id when it turns
/// from an incident vertex into a clipped point, as points of equal stacked boxes do at
/// every jiggle); or the two edges.
void box_box(const OBB& a, const OBB& b, double margin, Manifold& out);
/// box_box given the boxes' rotation matrices ra = a.rotation.to_matrix(), rb likewise (a
/// scene computes each body's once a step, not once per pair): the same manifold.
void box_box(const OBB& a, const Eigen::Matrix3d& ra, const OBB& b, const Eigen::Matrix3d& rb, double margin, Manifold& out);
/// Box a on a static plane: the vertices below the margin (at most 4, chosen as box_box
/// does); feature id the vertex (bits: its signs along x, y, z).
void box_plane(const OBB& a, const Plane& plane, double margin, Manifold& out);
/// box_plane given r = a.rotation.to_matrix(): the same manifold.
void box_plane(const OBB& a, const Eigen::Matrix3d& r, const Plane& plane, double margin, Manifold& out);
/// Sphere a against box b: the closest point of the box to the centre (when the centre is
/// inside, the nearest face); feature id the box's face, edge or vertex region.
void sphere_box(const SphereBB& a, const OBB& b, double margin, Manifold& out);
/// Capsule a on a static plane: each end of its segment closer than margin + r (up to 2
/// points: a capsule lying on its side rests on both); feature id the end (0, 1).
void capsule_plane(const Capsule& a, const Plane& plane, double margin, Manifold& out);
/// Capsule a against sphere b: the closest point of the segment to the centre, then two
/// spheres; feature id 0.
void capsule_sphere(const Capsule& a, const SphereBB& b, double margin, Manifold& out);
/// Capsule a against capsule b: the closest points of the two segments (feature id 2), or,
/// for segments parallel within 1e-3 rad whose projections overlap, the two ends of the
/// overlap (ids 0, 1): parallel capsules rest on a line, not a point.
void capsule_capsule(const Capsule& a, const Capsule& b, double margin, Manifold& out);
/// Capsule a against box b: the closest points of the segment and the box (the distance
/// along the segment is convex: golden-section search); when the segment lies within
/// 1e-3 rad of parallel to the face it meets, the segment clipped against that face's side
/// planes gives two points (ids 8 + 2·face + end); a segment that enters the box is pushed
/// out along the separating axis (box faces, segment × box edges) of least overlap.
void capsule_box(const Capsule& a, const OBB& b, double margin, Manifold& out);

} // namespace phynjo::runtime
