// A page with a box, a capsule and a sphere (tests/viewer/test_viewer.py): a turned 0.6 × 0.2 ×
// 0.4 m box and a capsule of radius 0.1 m around a 0.6 m segment fall onto the ground beside a
// sphere, 1.5 s. Usage: shaped_page OUT.html
#include "phynjo/runtime/runtime.hpp"

#include <cstdio>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: shaped_page OUT.html\n");
        return 2;
    }
    Registry reg;
    for (const char* name : {"box", "capsule", "ball"}) reg.add(name);
    std::vector<RigidInit> init(3);
    init[0].position = {0, 1, 0};
    init[0].orientation = Quaternion::from_axis_angle(Eigen::Vector3d(1, 2, 3).normalized(), 0.7);
    init[0].angular_velocity = {1, 0, 2};
    init[1].position = {1.2, 0.8, 0.3};
    init[1].orientation = Quaternion::from_axis_angle(Eigen::Vector3d(0, 0.3, 1).normalized(), 1.1);
    init[1].angular_velocity = {0, 3, 0};
    init[2].position = {-1, 0.6, -0.4};
    World w = make_rigid_world(reg,
                               {RigidBody::solid_box(2, {0.3, 0.1, 0.2}), RigidBody::solid_capsule(1, 0.1, 0.3),
                                RigidBody::solid_sphere(1, 0.15)},
                               init, contact_cache_fields(32));
    const std::vector<Plane> planes{Plane::ground()};
    Stepper s(rigid_contact_step(Force3D::gravity(9.81), all_bodies(w), planes,
                                 ContactMaterial{restitution_curve(0.3, 0.1), constant_curve(0.5)}, {}, w.layout_ptr()));
    Recorder page({.title = "a box, a capsule and a sphere"});
    page.add_rigid_bodies(w, all_bodies(w));
    page.add_planes(planes);
    for (int k = 0; k <= 360; ++k) {
        page.capture(w);
        if (k < 360) s.step(w, 1.0 / 240);
    }
    page.write_html(argv[1]);
}
