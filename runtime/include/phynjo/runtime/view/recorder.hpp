#pragma once
/// \file
/// A run as a self-contained 3-D animation (docs/viewer.md): a Recorder is told what to draw
/// (rigid bodies, planes, generated models' shapes, scenes, time series), reads the world at a
/// display rate while the run goes on, and writes one HTML file that plays it offline in a
/// browser — three.js (Debian's libjs-three) inlined, the frames packed as binary in base64.
///
/// Recording is read-only: `capture` takes the world as `const World&` and keeps copies of
/// what it reads, so a run with a recorder is bit for bit the run without one.
///
/// What a frame holds, and at what precision (docs/viewer.md, *The file*):
///   time and every series           float64 (exact);
///   sphere centres and rod ends     float32 (relative error ≤ 2⁻²⁴ ≈ 6·10⁻⁸ of the coordinate);
///   orientations (unit quaternions) int16, q·32767 rounded (error ≤ 1.6·10⁻⁵ per component).
#include "phynjo/runtime/collision/narrow_phase.hpp"
#include "phynjo/runtime/contact/scene.hpp"
#include "phynjo/runtime/core/component.hpp"
#include "phynjo/runtime/core/world.hpp"
#include "phynjo/runtime/system/lagrangian_system.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace phynjo::runtime {

/// How a Recorder samples and writes.
struct RecorderOptions {
    /// Frames per simulated second: a frame is kept when the run's time reaches the next
    /// multiple of 1/fps after the first frame (the first and the last state always).
    double fps = 60;
    std::string title = "phynjo run";
    /// The largest frame data (binary, before base64) a page carries, bytes. A run past it
    /// keeps every other frame (and then every fourth …), with a warning on the page and on
    /// standard error, so the file always opens; browsers refuse strings near 512 MB.
    std::size_t max_bytes = std::size_t{96} << 20;
};

/// Something drawn (file comment): a sphere (centre, radius, and an orientation when it is a
/// rigid body), a rod (two ends; radius 0: the page chooses one from the scene's size), a box
/// or a capsule (centre and orientation, as a rigid body's Shape: half_extents (a, b, c) along
/// body x, y, z; a capsule's radius around the segment from (0, −L, 0) to (0, L, 0), L =
/// half_extents[1]).
struct ViewBody {
    enum class Kind : std::uint8_t { sphere, rod, box, capsule };
    std::string name;
    Kind kind = Kind::sphere;
    double radius = 0; ///< m
    bool oriented = false;
    std::string group; ///< what it belongs to ("bodies", a model instance's name …), for the page's legend
    std::array<double, 3> half_extents{}; ///< m: a box's, or a capsule's (0, L, 0)
};

/// A time series beside the 3-D view, in a group the page plots together.
struct ViewSeries {
    std::string name, unit, group;
};

/// Records a run and writes it as one HTML page (file comment).
class Recorder {
public:
    explicit Recorder(RecorderOptions options = {});
    ~Recorder();
    Recorder(Recorder&&) noexcept;
    Recorder& operator=(Recorder&&) noexcept;
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // ---- what to draw: declared before the first capture (else std::logic_error) -----------
    /// Rigid bodies of a rigid world or scene (fields of rigid_world.hpp), oriented: boxes and
    /// capsules as their shapes, spheres of the body's collision radius (or, with radius 0, of
    /// the radius of a uniform sphere with its mean moment of inertia, √(5 Ī / 2m)); and the
    /// series "kinetic energy" (J).
    void add_rigid_bodies(const World& w, const ComponentSet& bodies);
    /// Static planes, drawn as squares over the scene's extent.
    void add_planes(std::span<const Plane> planes);
    /// A generated model stepped in a world of make_lagrangian_world: its shapes (spheres of
    /// their radii, segments as rods, capsules as rods of their radius); with no shapes, one bead per coordinate on a rail (x =
    /// the coordinate's value, one rail per coordinate). Series: the coordinates, E − E(0) and,
    /// for a constrained model, the constraint residuals φ.
    void add_model(const LagrangianSystem& system);
    /// A scene: its rigid bodies (as add_rigid_bodies) and every model instance's shapes; the
    /// series "energy" (scene_energy, J).
    void add_scene(const Scene& scene);
    /// Any other series: value(w) at every frame.
    void add_series(ViewSeries series, std::function<double(const World&)> value);

    // ---- while the run goes on ---------------------------------------------------------------
    /// Keeps a frame of `w` when one is due (file comment): true when it did. Reads w only.
    bool capture(const World& w);
    /// Keeps the frame of `w` unless the last one kept is at its time: the end of a run.
    void capture_last(const World& w);
    /// An event at time t, named: a mark on the page's time axis and a flash in the scene.
    void mark_event(double t, std::string name);
    /// Why the run stopped early (shown on the page); empty: it finished.
    void set_stop_reason(std::string reason);

    // ---- the page ---------------------------------------------------------------------------
    /// Writes the page to `path` (through a temporary file renamed over it, so a reader never
    /// sees half a page). Throws std::runtime_error naming the path when it cannot be written,
    /// ViewerError when three.js (libjs-three) cannot be found.
    void write_html(const std::string& path) const;
    /// The page as a string (what write_html writes).
    [[nodiscard]] std::string html() const;

    [[nodiscard]] std::size_t frame_count() const noexcept;
    [[nodiscard]] std::span<const ViewBody> bodies() const noexcept;
    [[nodiscard]] std::span<const ViewSeries> series() const noexcept;
    /// The kept frames' times, s.
    [[nodiscard]] std::span<const double> times() const noexcept;
    /// Bytes of frame data (binary) the page will carry.
    [[nodiscard]] std::size_t frame_bytes() const noexcept;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// three.js (libjs-three) is missing: what the message says to install.
struct ViewerError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The folder holding three.min.js and examples/js/controls/OrbitControls.js: $PHYNJO_THREE_DIR
/// when set, else the one found when phynjo was configured (Debian: /usr/share/javascript/three).
std::string three_js_dir();
/// Throws ViewerError (naming the folder and the package) unless three_js_dir() holds both files.
void check_three_js();

/// Checks that `path` can be written (made, then removed if it did not exist): false when not.
/// What a simulator asks before a run, so an unwritable --html is refused before it starts.
bool can_write(const std::string& path);

} // namespace phynjo::runtime
