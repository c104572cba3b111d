// A row of 30 dominoes (2 × 10 × 5 cm boxes, 50 g, 6 cm apart) on the ground, the first given
// a push at its top: each knocks the next over. μ = 0.5 (domino–domino and ground), e = 0,
// dt = 1/480 s, 20 velocity iterations. Writes dominoes.csv (t and the tilt of every domino,
// degrees), dominoes_falls.csv (the time each passes 45°) and dominoes.html; prints the speed of
// the wave of falls along the row.
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const int n = 30;
    const Eigen::Vector3d h(0.01, 0.05, 0.025);
    const double gap = 0.06, dt = 1.0 / 480, t_end = 3;
    Registry reg;
    std::vector<RigidInit> init;
    for (int i = 0; i < n; ++i) {
        reg.add("d" + std::to_string(i));
        RigidInit s;
        s.position = {i * gap, h.y(), 0};
        init.push_back(s);
    }
    // The push: the first domino turns towards +x about its bottom edge at x = +h_x (ω about
    // −z), its centre moving as ω × (centre − edge).
    const Eigen::Vector3d omega(0, 0, -4);
    init[0].angular_velocity = omega;
    init[0].velocity = omega.cross(Eigen::Vector3d(-h.x(), h.y(), 0));
    World w = make_rigid_world(reg, std::vector<RigidBody>(n, RigidBody::solid_box(0.05, h)), init, contact_cache_fields(32));
    const std::vector<Plane> planes{Plane::ground()};
    Stepper stepper = contact_stepper(w, planes, ContactMaterial{restitution_curve(0, 0.05), constant_curve(0.5)}, 1e-5);
    Recorder page = rigid_page(w, planes, "30 dominoes (2 x 10 x 5 cm, 6 cm apart, mu = 0.5)");
    std::ofstream tilt_csv(dir / "dominoes.csv");
    tilt_csv << "t";
    for (int i = 0; i < n; ++i) tilt_csv << ",tilt_" << i;
    tilt_csv << '\n';
    std::vector<double> fell(n, -1);
    const bool ran = run_recorded(w, stepper, dt, t_end, page, [&](int s, const World& x) {
        const double t = s * dt;
        if (s % 4 == 0) tilt_csv << t;
        for (Index i = 0; i < x.size(); ++i) {
            // the tilt: the angle between the domino's long axis (body y) and the vertical
            const double up = orientation(x, i).rotate(Eigen::Vector3d::UnitY()).y();
            const double deg = std::acos(std::clamp(up, -1.0, 1.0)) * 180 / M_PI;
            if (s % 4 == 0) tilt_csv << ',' << deg;
            if (fell[i] < 0 && deg > 45) fell[i] = t;
        }
        if (s % 4 == 0) tilt_csv << '\n';
    });
    if (!ran) return 1;
    std::ofstream falls(dir / "dominoes_falls.csv");
    falls << "domino,x,t_45deg\n";
    int down = 0;
    for (int i = 0; i < n; ++i) {
        falls << i << ',' << i * gap << ',' << fell[i] << '\n';
        down += fell[i] >= 0;
    }
    // The wave's speed along the middle of the row (away from the push and the end).
    const int a = n / 3, b = 2 * n / 3;
    std::printf("dominoes: %d of %d fell; the wave of falls moves at %.3f m/s along the row (dominoes %d to %d)\n", down, n,
                fell[a] >= 0 && fell[b] > fell[a] ? (b - a) * gap / (fell[b] - fell[a]) : 0.0, a, b);
    page.write_html(dir / "dominoes.html");
}
