// The Recorder (view/recorder.hpp): what to draw, the frames it keeps, and the page it writes.
#include "phynjo/runtime/view/recorder.hpp"

#include "phynjo/runtime/rigid/rigid_world.hpp"
#include "phynjo/runtime/system/constraint_projection.hpp"

#include "page.hpp"

#include <algorithm>
#include <bit>
#include <optional>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

#ifndef PHYNJO_THREE_DIR
#define PHYNJO_THREE_DIR "/usr/share/javascript/three"
#endif

namespace phynjo::runtime {

namespace {

/// A frame's float32 positions, int16 orientations and float64 series, appended by a reader.
struct FrameSink {
    std::vector<float>& positions;
    std::vector<std::int16_t>& orientations;
    std::vector<std::vector<double>>& series;
};

using Reader = std::function<void(const World&, FrameSink&)>;

std::int16_t quantize(double c) {
    return static_cast<std::int16_t>(std::lround(std::clamp(c, -1.0, 1.0) * 32767.0));
}

/// Σ ½ m v² + ½ ω·I_W ω of the rigid bodies `bodies` of `w`, J (rigid_kinetic_energy over
/// some of a world's components: a scene's proxies and coordinates are not bodies).
double kinetic_energy(const World& w, std::span<const Index> bodies) {
    double e = 0;
    for (const Index c : bodies) {
        const Eigen::Vector3d v = velocity(w, c), om = angular_velocity(w, c);
        e += 0.5 * w.at(kMass, c) * v.squaredNorm() + 0.5 * om.dot(world_inertia(w, c) * om);
    }
    return e;
}

std::string json_string(std::string_view s) {
    std::string out = "\"";
    for (const char c : s) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\r': out += "\\r"; break;
        case '\t': out += "\\t"; break;
        case '<': out += "\\u003c"; break; // never "</script>" inside the page's script element
        case '>': out += "\\u003e"; break;
        case '&': out += "\\u0026"; break;
        default:
            if (static_cast<unsigned char>(c) < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
                out += buf;
            } else out += c;
        }
    }
    return out + "\"";
}

std::string json_number(double x) {
    if (!std::isfinite(x)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

void append_base64(std::string& out, const unsigned char* p, std::size_t n) {
    static constexpr char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    out.reserve(out.size() + (n + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 3 <= n; i += 3) {
        const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (std::uint32_t{p[i + 1]} << 8) | p[i + 2];
        out += table[v >> 18];
        out += table[(v >> 12) & 63];
        out += table[(v >> 6) & 63];
        out += table[v & 63];
    }
    if (i < n) {
        const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (i + 1 < n ? std::uint32_t{p[i + 1]} << 8 : 0);
        out += table[v >> 18];
        out += table[(v >> 12) & 63];
        out += i + 1 < n ? table[(v >> 6) & 63] : '=';
        out += '=';
    }
}

/// Little-endian bytes of a vector of numbers (the page reads typed arrays, little-endian on
/// every machine a browser runs on; a big-endian writer swaps).
template <class T>
void append_bytes(std::vector<unsigned char>& out, const std::vector<T>& v) {
    const std::size_t at = out.size();
    out.resize(at + v.size() * sizeof(T));
    if (!v.empty()) std::memcpy(out.data() + at, v.data(), v.size() * sizeof(T));
    if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1)
        for (std::size_t i = at; i < out.size(); i += sizeof(T)) std::reverse(out.begin() + static_cast<std::ptrdiff_t>(i), out.begin() + static_cast<std::ptrdiff_t>(i + sizeof(T)));
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

void replace_once(std::string& text, std::string_view marker, const std::string& with) {
    const std::size_t at = text.find(marker);
    if (at == std::string::npos) throw std::logic_error("viewer page template without " + std::string(marker));
    text.replace(at, marker.size(), with);
}

} // namespace

struct Recorder::Impl {
    RecorderOptions options;
    std::vector<ViewBody> bodies;
    std::vector<ViewSeries> series;
    std::vector<Reader> readers;
    std::vector<Plane> planes;
    std::vector<std::pair<double, std::string>> events;
    std::string stop_reason;
    std::vector<std::string> warnings;
    // the frames
    std::vector<double> times;
    std::vector<std::vector<double>> series_values;
    std::vector<float> positions;
    std::vector<std::int16_t> orientations;
    std::size_t floats_per_frame = 0, quaternions_per_frame = 0;
    double t_first = 0, interval = 1.0 / 60;
    long next_k = 0;

    /// The index k of the next frame due at t_first + k·interval after a frame at time t
    /// (within 1e-9 of an interval counts as reached: k·dt meeting j/fps to rounding).
    [[nodiscard]] long next_after(double t) const {
        return static_cast<long>(std::floor((t - t_first) / interval + 1e-9)) + 1;
    }
    void declare() const {
        if (!times.empty()) throw std::logic_error("Recorder: what to draw is declared before the first capture");
    }
    std::size_t add_body(ViewBody b) {
        floats_per_frame += b.kind == ViewBody::Kind::rod ? 6 : 3;
        quaternions_per_frame += b.oriented ? 1 : 0;
        bodies.push_back(std::move(b));
        return bodies.size() - 1;
    }
    std::size_t add_series(ViewSeries s) {
        series.push_back(std::move(s));
        series_values.emplace_back();
        return series.size() - 1;
    }
    [[nodiscard]] std::size_t bytes_per_frame() const {
        return 8 * (1 + series.size()) + 4 * floats_per_frame + 8 * quaternions_per_frame;
    }
    void take(const World& w) {
        times.push_back(w.time);
        FrameSink sink{positions, orientations, series_values};
        for (const Reader& r : readers) r(w, sink);
        if (times.size() * bytes_per_frame() > options.max_bytes && times.size() > 2) thin();
    }
    /// The shapes of one model as bodies (spheres; segments as thin rods, capsules as rods of
    /// their radius; boxes oriented) and the reader of their points from the model's q;
    /// `q_of(w, q)` fills q from the world.
    template <class QOf>
    Reader model_shapes(std::shared_ptr<const LagrangianSystem> sys, const std::string& group, QOf q_of) {
        std::vector<double> spheres(sys->n_spheres), capsules(sys->n_capsules), boxes(3 * sys->n_boxes);
        if (sys->n_spheres > 0) sys->sphere_radii(spheres);
        if (sys->n_capsules > 0) sys->capsule_radii(capsules);
        if (sys->n_boxes > 0) sys->box_half_extents(boxes);
        std::size_t sphere = 0, capsule = 0, box = 0;
        for (std::size_t k = 0; k < sys->n_shapes; ++k) {
            const ModelShape kind = sys->shape_kinds[k];
            ViewBody b{group.empty() ? sys->shape_names[k] : group + "." + sys->shape_names[k], ViewBody::Kind::rod, 0.0, false,
                       group.empty() ? "model" : group};
            if (kind == ModelShape::sphere) b.kind = ViewBody::Kind::sphere, b.radius = spheres[sphere++];
            if (kind == ModelShape::capsule) b.radius = capsules[capsule++];
            if (kind == ModelShape::box) {
                b.kind = ViewBody::Kind::box;
                b.oriented = true;
                for (std::size_t d = 0; d < 3; ++d) b.half_extents[d] = boxes[3 * box + d];
                ++box;
            }
            add_body(std::move(b));
        }
        const std::size_t dof = sys->dof;
        return [sys, q_of, q = std::vector<double>(dof), X = std::vector<double>(sys->n_shape_values())](
                   const World& w, FrameSink& s) mutable {
            q_of(w, q);
            sys->shape_positions(w.time, q, X);
            std::size_t at = 0;
            for (ModelShape kind : sys->shape_kinds) {
                const std::size_t points = kind == ModelShape::box ? 3 : shape_values(kind);
                for (std::size_t i = 0; i < points; ++i) s.positions.push_back(static_cast<float>(X[at + i]));
                if (kind == ModelShape::box)
                    for (std::size_t i = 3; i < 7; ++i) s.orientations.push_back(quantize(X[at + i]));
                at += shape_values(kind);
            }
        };
    }
    /// Keeps every other frame (the first among them) and doubles the interval: the page stays
    /// under max_bytes however long the run.
    void thin() {
        const std::size_t n = times.size(), keep = (n + 1) / 2;
        auto halve = [&](auto& v, std::size_t per) {
            for (std::size_t k = 1; k < keep; ++k)
                std::copy_n(v.begin() + static_cast<std::ptrdiff_t>(2 * k * per), per, v.begin() + static_cast<std::ptrdiff_t>(k * per));
            v.resize(keep * per);
        };
        halve(times, 1);
        for (auto& s : series_values) halve(s, 1);
        halve(positions, floats_per_frame);
        halve(orientations, 4 * quaternions_per_frame);
        interval *= 2;
        next_k = next_after(times.back());
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "the run is longer than a page carries (%zu MB of frames): kept %.4g frames per simulated second",
                      options.max_bytes >> 20, 1 / interval);
        if (warnings.empty() || warnings.back().rfind("the run is longer", 0) != 0) {
            warnings.emplace_back(buf);
        } else warnings.back() = buf;
    }
};

Recorder::Recorder(RecorderOptions options) : impl_(std::make_unique<Impl>()) {
    if (!(options.fps > 0) || !std::isfinite(options.fps)) throw std::invalid_argument("Recorder: fps must be positive");
    impl_->interval = 1 / options.fps;
    impl_->options = std::move(options);
}
Recorder::~Recorder() = default;
Recorder::Recorder(Recorder&&) noexcept = default;
Recorder& Recorder::operator=(Recorder&&) noexcept = default;

void Recorder::add_rigid_bodies(const World& w, const ComponentSet& bodies) {
    impl_->declare();
    const Registry& reg = w.layout().components;
    std::vector<Index> idx(bodies.indices().begin(), bodies.indices().end());
    const bool shaped = shape_field(w.layout()) >= 0;
    for (const Index c : idx) {
        const Shape shape = shaped ? shape_of(w, c) : Shape::sphere;
        if (shape != Shape::sphere) {
            const Eigen::Vector3d h = half_extents(w, c);
            ViewBody b{reg.label(c), shape == Shape::box ? ViewBody::Kind::box : ViewBody::Kind::capsule,
                       shape == Shape::box ? 0.0 : w.at(kRadius, c), true, "bodies", {h.x(), h.y(), h.z()}};
            impl_->add_body(std::move(b));
            continue;
        }
        double r = w.at(kRadius, c);
        if (!(r > 0)) { // no collision sphere: the uniform sphere of the same mean moment of inertia
            const double m = w.at(kMass, c), mean_i = (w.at(kIxx, c) + w.at(kIyy, c) + w.at(kIzz, c)) / 3;
            r = m > 0 && mean_i > 0 ? std::sqrt(2.5 * mean_i / m) : 0;
        }
        impl_->add_body({reg.label(c), ViewBody::Kind::sphere, r, true, "bodies"});
    }
    const std::size_t energy = impl_->add_series({"kinetic energy", "J", "energy"});
    impl_->readers.push_back([idx = std::move(idx), energy](const World& world, FrameSink& s) {
        for (const Index c : idx) {
            s.positions.push_back(static_cast<float>(world.at(kX, c)));
            s.positions.push_back(static_cast<float>(world.at(kY, c)));
            s.positions.push_back(static_cast<float>(world.at(kZ, c)));
            for (FieldId f : {kQW, kQX, kQY, kQZ}) s.orientations.push_back(quantize(world.at(f, c)));
        }
        s.series[energy].push_back(kinetic_energy(world, idx));
    });
}

void Recorder::add_planes(std::span<const Plane> planes) {
    impl_->declare();
    for (const Plane& p : planes) {
        p.validate();
        impl_->planes.push_back(p);
    }
}

void Recorder::add_model(const LagrangianSystem& system) {
    impl_->declare();
    auto sys = std::make_shared<const LagrangianSystem>(system);
    const std::size_t dof = sys->dof;
    if (sys->n_shapes > 0) {
        impl_->readers.push_back(impl_->model_shapes(sys, "", [](const World& w, std::vector<double>& q) {
            const auto f = w.field(kGQ);
            std::copy(f.begin(), f.end(), q.begin());
        }));
    } else { // beads on rails: x = q_i, y = −i
        for (std::size_t i = 0; i < dof; ++i) impl_->add_body({sys->coordinate_names[i], ViewBody::Kind::sphere, 0.0, false, "coordinates"});
        impl_->readers.push_back([dof](const World& w, FrameSink& s) {
            for (std::size_t i = 0; i < dof; ++i) {
                s.positions.push_back(static_cast<float>(w.at(kGQ, static_cast<Index>(i))));
                s.positions.push_back(static_cast<float>(-static_cast<double>(i)));
                s.positions.push_back(0.0F);
            }
        });
    }
    const std::size_t first = impl_->series.size();
    for (std::size_t i = 0; i < dof; ++i) impl_->add_series({sys->coordinate_names[i], "", "coordinates"});
    for (std::size_t i = 0; i < dof; ++i) impl_->add_series({sys->coordinate_names[i] + "'", "", "velocities"});
    impl_->add_series({"E - E(0)", "J", "energy"});
    for (std::size_t i = 0; i < sys->n_constraints; ++i)
        impl_->add_series({"phi_" + sys->constraint_names[i], "", "constraint residuals"});
    impl_->readers.push_back([sys, first, dof, e0 = std::optional<double>(), phi = std::vector<double>(sys->n_constraints)](
                                 const World& w, FrameSink& s) mutable {
        const auto q = w.field(kGQ), v = w.field(kGV);
        for (std::size_t i = 0; i < dof; ++i) s.series[first + i].push_back(q[i]);
        for (std::size_t i = 0; i < dof; ++i) s.series[first + dof + i].push_back(v[i]);
        const double e = sys->energy(w.time, q, v);
        if (!e0) e0 = e;
        s.series[first + 2 * dof].push_back(e - *e0);
        if (!phi.empty()) {
            sys->constraint_residuals(w.time, q, v, phi);
            for (std::size_t i = 0; i < phi.size(); ++i) s.series[first + 2 * dof + 1 + i].push_back(phi[i]);
        }
    });
}

void Recorder::add_scene(const Scene& scene) {
    impl_->declare();
    if (!scene.bodies.empty()) add_rigid_bodies(scene.world, scene.bodies);
    for (const PlacedModel& m : scene.models) {
        impl_->readers.push_back(impl_->model_shapes(m.system, m.name,
                                              [coords = m.coordinates, f = scene.q](const World& w, std::vector<double>& q) {
                                                  for (std::size_t i = 0; i < coords.size(); ++i) q[i] = w.at(f, coords[i]);
                                              }));
    }
    // the scene's energy (scene_energy) read from the world captured, not scene.world
    const std::size_t energy = impl_->add_series({"energy", "J", "energy"});
    std::vector<Index> bodies(scene.bodies.indices().begin(), scene.bodies.indices().end());
    impl_->readers.push_back([bodies = std::move(bodies), models = scene.models, f = scene.q, fd = scene.qd, energy,
                              q = std::vector<double>(), v = std::vector<double>()](const World& w, FrameSink& s) mutable {
        double e = kinetic_energy(w, bodies);
        for (const PlacedModel& m : models) {
            q.resize(m.coordinates.size());
            v.resize(m.coordinates.size());
            for (std::size_t i = 0; i < q.size(); ++i) q[i] = w.at(f, m.coordinates[i]), v[i] = w.at(fd, m.coordinates[i]);
            e += m.system->energy(w.time, q, v);
        }
        s.series[energy].push_back(e);
    });
}

void Recorder::add_series(ViewSeries series, std::function<double(const World&)> value) {
    impl_->declare();
    if (!value) throw std::invalid_argument("Recorder::add_series: no function for " + series.name);
    const std::size_t k = impl_->add_series(std::move(series));
    impl_->readers.push_back([k, value = std::move(value)](const World& w, FrameSink& s) { s.series[k].push_back(value(w)); });
}

bool Recorder::capture(const World& w) {
    Impl& m = *impl_;
    if (m.times.empty()) {
        m.t_first = w.time;
        m.next_k = 1;
        m.take(w);
        return true;
    }
    // due at t_first + next_k·interval (next_after's tolerance)
    if (w.time - m.t_first < (static_cast<double>(m.next_k) - 1e-9) * m.interval) return false;
    m.take(w);
    m.next_k = m.next_after(w.time);
    return true;
}

void Recorder::capture_last(const World& w) {
    if (impl_->times.empty() || impl_->times.back() != w.time) impl_->take(w);
}

void Recorder::mark_event(double t, std::string name) { impl_->events.emplace_back(t, std::move(name)); }
void Recorder::set_stop_reason(std::string reason) { impl_->stop_reason = std::move(reason); }

std::size_t Recorder::frame_count() const noexcept { return impl_->times.size(); }
std::span<const ViewBody> Recorder::bodies() const noexcept { return impl_->bodies; }
std::span<const ViewSeries> Recorder::series() const noexcept { return impl_->series; }
std::span<const double> Recorder::times() const noexcept { return impl_->times; }
std::size_t Recorder::frame_bytes() const noexcept { return impl_->times.size() * impl_->bytes_per_frame(); }

std::string three_js_dir() {
    if (const char* env = std::getenv("PHYNJO_THREE_DIR"); env && *env) return env;
    return PHYNJO_THREE_DIR;
}

namespace {
constexpr const char* kThreeMin = "/three.min.js";
constexpr const char* kOrbitControls = "/examples/js/controls/OrbitControls.js";
} // namespace

void check_three_js() {
    const std::string dir = three_js_dir();
    for (const char* f : {kThreeMin, kOrbitControls})
        if (!std::filesystem::is_regular_file(dir + f))
            throw ViewerError("three.js not found: " + dir + f +
                              " is missing (install Debian's libjs-three, or set PHYNJO_THREE_DIR to the folder that "
                              "holds three.min.js)");
}

bool can_write(const std::string& path) {
    if (path.empty() || std::filesystem::is_directory(path)) return false;
    const bool existed = std::filesystem::exists(path);
    std::FILE* f = std::fopen(path.c_str(), "a");
    if (!f) return false;
    std::fclose(f);
    if (!existed) std::remove(path.c_str());
    return true;
}

std::string Recorder::html() const {
    check_three_js();
    const Impl& m = *impl_;
    const std::string dir = three_js_dir();
    const std::string three = read_file(dir + kThreeMin), controls = read_file(dir + kOrbitControls);
    if (three.empty() || controls.empty()) throw ViewerError("three.js could not be read from " + dir);

    // the meta data (JSON) and the frames (binary, base64): docs/viewer.md, *The file*
    const std::size_t frames = m.times.size();
    std::string meta = "{\"format\":\"phynjo-view 1\",\"title\":" + json_string(m.options.title) +
                       ",\"frames\":" + std::to_string(frames) + ",\"fps\":" + json_number(1 / m.interval) +
                       ",\"precision\":{\"time\":\"float64\",\"series\":\"float64\",\"positions\":\"float32\","
                       "\"orientations\":\"int16/32767\"}";
    meta += ",\"bodies\":[";
    for (std::size_t i = 0; i < m.bodies.size(); ++i) {
        const ViewBody& b = m.bodies[i];
        static constexpr const char* kKinds[] = {"\"sphere\"", "\"rod\"", "\"box\"", "\"capsule\""};
        meta += (i ? "," : "") + std::string("{\"name\":") + json_string(b.name) + ",\"kind\":" +
                kKinds[static_cast<int>(b.kind)] + ",\"radius\":" + json_number(b.radius) +
                ",\"oriented\":" + (b.oriented ? "true" : "false") + ",\"group\":" + json_string(b.group);
        if (b.kind == ViewBody::Kind::box || b.kind == ViewBody::Kind::capsule)
            meta += ",\"half_extents\":[" + json_number(b.half_extents[0]) + "," + json_number(b.half_extents[1]) + "," +
                    json_number(b.half_extents[2]) + "]";
        meta += "}";
    }
    meta += "],\"planes\":[";
    for (std::size_t i = 0; i < m.planes.size(); ++i) {
        const Plane& p = m.planes[i];
        meta += (i ? "," : "") + std::string("{\"normal\":[") + json_number(p.normal.x()) + "," + json_number(p.normal.y()) +
                "," + json_number(p.normal.z()) + "],\"offset\":" + json_number(p.offset) + "}";
    }
    meta += "],\"series\":[";
    for (std::size_t i = 0; i < m.series.size(); ++i) {
        const ViewSeries& s = m.series[i];
        meta += (i ? "," : "") + std::string("{\"name\":") + json_string(s.name) + ",\"unit\":" + json_string(s.unit) +
                ",\"group\":" + json_string(s.group) + "}";
    }
    meta += "],\"events\":[";
    for (std::size_t i = 0; i < m.events.size(); ++i)
        meta += (i ? "," : "") + std::string("{\"t\":") + json_number(m.events[i].first) + ",\"name\":" +
                json_string(m.events[i].second) + "}";
    meta += "],\"stop\":" + json_string(m.stop_reason) + ",\"warnings\":[";
    for (std::size_t i = 0; i < m.warnings.size(); ++i) meta += (i ? "," : "") + json_string(m.warnings[i]);
    meta += "]}";

    std::vector<unsigned char> bytes;
    bytes.reserve(frame_bytes());
    append_bytes(bytes, m.times);
    for (const auto& s : m.series_values) append_bytes(bytes, s);
    append_bytes(bytes, m.positions);
    append_bytes(bytes, m.orientations);
    std::string blob;
    append_base64(blob, bytes.data(), bytes.size());

    std::string page(detail::kViewerHtml);
    replace_once(page, "PHYNJO_TITLE", [&] {
        std::string t;
        for (char c : m.options.title) t += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
        return t;
    }());
    replace_once(page, "/*PHYNJO_CSS*/", std::string(detail::kViewerCss));
    replace_once(page, "/*PHYNJO_THREE*/", three);
    replace_once(page, "/*PHYNJO_ORBIT_CONTROLS*/", controls);
    replace_once(page, "PHYNJO_META", meta);
    replace_once(page, "PHYNJO_FRAMES", blob);
    replace_once(page, "/*PHYNJO_VIEWER*/", std::string(detail::kViewerJs));
    return page;
}

void Recorder::write_html(const std::string& path) const {
    for (const std::string& w : impl_->warnings) std::fprintf(stderr, "phynjo viewer: %s\n", w.c_str());
    const std::string page = html();
    const std::string tmp = path + ".part";
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw std::runtime_error("cannot write " + path);
    const bool written = std::fwrite(page.data(), 1, page.size(), f) == page.size();
    const bool closed = std::fclose(f) == 0;
    if (!written || !closed || std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write " + path + (written ? "" : " (disk full?)"));
    }
}

} // namespace phynjo::runtime
