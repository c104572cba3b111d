#include <phynjo/cas/cas.hpp>
#include <phynjo/grammar/expression.hpp>
#include <phynjo/runtime/runtime.hpp>

#include <iostream>

int main() {
    using namespace phynjo;
    const cas::Expr L = grammar::parse("1/2*m*l^2*theta'^2 + m*g*l*cos(theta)");
    const cas::Expr p = cas::diff(L, grammar::parse("theta'"));
    std::cout << cas::to_string(p) << "\n";
    // The runtime's public Eigen dependency reaches the consumer: a ball dropped on the ground.
    runtime::Registry r;
    r.add("ball");
    runtime::RigidInit s;
    s.position = {0, 1, 0};
    runtime::World w = runtime::make_rigid_world(r, {runtime::RigidBody::solid_sphere(1, 0.1)}, {s});
    runtime::Stepper st(runtime::rigid_contact_step(runtime::Force3D::gravity(9.81), runtime::all_bodies(w),
                                                    {runtime::Plane::ground()}, {}, {}, w.layout_ptr()));
    st.run(w, 1e-3, 2000);
    std::cout << "ball at rest at y = " << w.at(runtime::kY, 0) << "\n";
    return cas::to_string(p) == "l^2*m*theta'" && std::abs(w.at(runtime::kY, 0) - 0.1) < 1e-6 ? 0 : 1;
}
