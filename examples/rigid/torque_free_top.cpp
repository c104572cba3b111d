// The intermediate-axis flip (Dzhanibekov effect): a torque-free asymmetric top spun almost
// about its intermediate axis turns over again and again. Writes torque_free_top.csv
// (t, body-frame ω, relative energy and angular-momentum errors) and prints the flip
// half-period against Landau's elliptic-function value; torque_free_top.html plays the first
// 20 s (docs/viewer.md).
#include "example_io.hpp"
#include "phynjo/runtime/runtime.hpp"

#include <boost/math/special_functions/ellint_1.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

using namespace phynjo::runtime;

int main(int argc, char** argv) {
    const auto dir = output_dir(argc, argv);
    const double I1 = 1, I2 = 2, I3 = 3, dt = 1e-3, t_end = 80;
    const Eigen::Vector3d om0(0.01, 1.0, 0.02);
    Registry reg;
    reg.add("top");
    RigidBody body;
    body.mass = 1;
    body.inertia = Eigen::Vector3d(I1, I2, I3).asDiagonal();
    RigidInit s;
    s.angular_velocity = om0;
    World w = make_rigid_world(reg, {body}, {s});
    Stepper stepper(rigid_leapfrog(Force3D{}, all_bodies(w), w.layout_ptr()));

    const double E0 = rigid_kinetic_energy(w);
    const Eigen::Vector3d L0 = total_angular_momentum(w);
    std::ofstream csv(dir / "torque_free_top.csv");
    csv << "t,wx_body,wy_body,wz_body,energy_error,momentum_error\n";
    Recorder page({.fps = 30, .title = "torque-free top: the intermediate-axis flip"});
    page.add_rigid_bodies(w, all_bodies(w));
    page.add_series({"omega_y body", "rad/s", "body angular velocity"},
                    [](const World& now) { return orientation(now, 0).rotate_inverse(angular_velocity(now, 0)).y(); });
    std::vector<double> flips;
    double prev = om0.y(), worst_e = 0, worst_l = 0;
    const int steps = static_cast<int>(t_end / dt);
    for (int n = 0; n <= steps; ++n) {
        const Eigen::Vector3d ob = orientation(w, 0).rotate_inverse(angular_velocity(w, 0));
        const double de = (rigid_kinetic_energy(w) - E0) / E0, dl = (total_angular_momentum(w) - L0).norm() / L0.norm();
        worst_e = std::max(worst_e, std::abs(de));
        worst_l = std::max(worst_l, dl);
        if (n > 0 && (prev > 0) != (ob.y() > 0)) flips.push_back((n - 1 + prev / (prev - ob.y())) * dt);
        prev = ob.y();
        if (n * dt <= 20) page.capture(w);
        if (n % 20 == 0) csv << n * dt << ',' << ob.x() << ',' << ob.y() << ',' << ob.z() << ',' << de << ',' << dl << '\n';
        if (n < steps) stepper.step(w, dt);
    }
    // Landau & Lifshitz §37 (M² > 2E·I2): ω2 ∝ sn(λt), zeros 2K(k)/λ apart.
    const double E2 = 2 * E0, M2 = L0.squaredNorm();
    const double lambda = std::sqrt((I3 - I2) * (M2 - E2 * I1) / (I1 * I2 * I3));
    const double k = std::sqrt((I2 - I1) * (E2 * I3 - M2) / ((I3 - I2) * (M2 - E2 * I1)));
    const double theory = 2 * boost::math::ellint_1(k) / lambda;
    std::printf("torque-free top, I = diag(1, 2, 3) kg m^2, omega0 = (0.01, 1, 0.02) rad/s, dt = 1 ms, %g s\n", t_end);
    std::printf("  %zu flips of the intermediate axis; ", flips.size());
    if (flips.size() >= 2)
        std::printf("half-period %.4f s (Landau: %.4f s)\n", (flips.back() - flips.front()) / double(flips.size() - 1), theory);
    else
        std::printf("\n");
    std::printf("  largest relative energy error %.2e, angular momentum error %.2e\n", worst_e, worst_l);
    page.write_html(dir / "torque_free_top.html");
    std::printf("  wrote %s and %s\n", (dir / "torque_free_top.csv").c_str(), (dir / "torque_free_top.html").c_str());
}
