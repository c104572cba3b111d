"""The viewer's pages (--html, docs/viewer.md) in a real, headless Chromium, offline.

Pages come from the simulators of tests/codegen/models/shapes.lag (a 3-D double pendulum:
spheres, rods, a fixed post, a sphere driven by t) and examples/models/bouncing_ball.lag
(events, a run stopped early), and the rigid top of examples/rigid/torque_free_top.cpp (an
oriented body); the programs' paths are in PHYNJO_SHAPES_SIM, PHYNJO_BALL_SIM and PHYNJO_TOP
(tests/CMakeLists.txt). Each test names the bug it catches."""
import colorsys
import csv
import math
import os
import subprocess

import pytest

import browser

T_END, DT, FPS = 2.005, 1e-3, 60  # the end between two frames: the last state is kept apart


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    d = tmp_path_factory.mktemp("pages")
    sim = os.environ["PHYNJO_SHAPES_SIM"]
    common = ["--t-end", str(T_END), "--dt", str(DT), "--every", "1"]
    subprocess.run([sim, *common, "-o", d / "plain.csv"], check=True)
    subprocess.run([sim, *common, "-o", d / "shapes.csv", "--shapes", d / "points.csv", "--html", d / "shapes.html"],
                   check=True)
    ball = os.environ["PHYNJO_BALL_SIM"]
    subprocess.run([ball, "--t-end", "3", "--events", d / "bounces.csv", "-o", d / "ball.csv",
                    "--html", d / "ball.html"], check=True)
    subprocess.run([os.environ["PHYNJO_TOP"], "--output", d], check=True, stdout=subprocess.DEVNULL)
    subprocess.run([os.environ["PHYNJO_SHAPED_PAGE"], d / "shaped.html"], check=True)
    return d


@pytest.fixture(scope="module")
def driver():
    drv = browser.start()
    yield drv
    drv.quit()


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def expected_frame_times(times, fps):
    """The frames of the recorder's rule, by brute force: the first step reaching each j/fps
    (within 1e-9 of an interval), then the last state."""
    kept, j = [], 0
    for t in times:
        if t >= (j - 1e-9) / fps:
            kept.append(t)
            j = math.floor(t * fps + 1e-9) + 1
    if kept[-1] != times[-1]:
        kept.append(times[-1])
    return kept


def test_page_loads_offline_without_a_console_error(pages, driver):
    """Catches: a page that fetches three.js (or anything) from the network, or one whose
    script fails (a console error, an exception caught by the page's own handler)."""
    browser.requested_urls(driver)
    for page in ("shapes.html", "ball.html"):
        browser.load(driver, pages / page)
        urls = browser.requested_urls(driver)
        assert urls and all(u.startswith("file://") or u.startswith("data:") for u in urls), urls
        assert browser.console_errors(driver) == []
        assert driver.execute_script("return phynjo.errors") == []
        assert driver.execute_script("return typeof THREE.OrbitControls") == "function"


def test_the_hook_reports_the_run_and_positions_match_the_csv(pages, driver):
    """Catches: a recorder that drops the last frame, swaps two bodies or writes y for z, a
    page that decodes the frames wrongly, frames at the wrong times; and a run that --html
    changes (its CSV must be the same bytes as without)."""
    assert (pages / "plain.csv").read_bytes() == (pages / "shapes.csv").read_bytes()
    browser.load(driver, pages / "shapes.html")
    hook = driver.execute_script(
        "return [phynjo.frameCount, phynjo.bodyCount, phynjo.timeSpan, phynjo.meta.bodies.map(b => b.name)]")
    points = rows(pages / "points.csv")
    times = [float(r["t"]) for r in points]
    frames = expected_frame_times(times, FPS)
    assert hook[0] == len(frames)
    assert hook[1] == 11
    assert hook[2] == [0, T_END]
    assert hook[3] == ["bob1", "rod1", "bob2", "rod2", "post", "float", "arm", "lever", "lid", "tilt", "crate"]
    # the capsules: rods of their radii (r2/2 and 1/25 m), the segments thin rods; boxes
    kinds = driver.execute_script("return phynjo.meta.bodies.map(b => [b.kind, b.radius])")
    assert kinds[1] == ["rod", 0] and kinds[6] == ["rod", 0.0375] and kinds[7] == ["rod", 0.04]
    assert [k[0] for k in kinds[8:]] == ["box"] * 3
    assert driver.execute_script("return phynjo.meta.bodies[8].half_extents") == pytest.approx([0.05, 0.025, 0.125], rel=1e-12)
    by_time = {float(r["t"]): r for r in points}
    columns = {"bob1": ["bob1_x", "bob1_y", "bob1_z"], "rod1": ["rod1_x1", "rod1_y1", "rod1_z1", "rod1_x2", "rod1_y2", "rod1_z2"],
               "bob2": ["bob2_x", "bob2_y", "bob2_z"], "rod2": ["rod2_x1", "rod2_y1", "rod2_z1", "rod2_x2", "rod2_y2", "rod2_z2"],
               "post": ["post_x", "post_y", "post_z"], "float": ["float_x", "float_y", "float_z"],
               "arm": ["arm_x1", "arm_y1", "arm_z1", "arm_x2", "arm_y2", "arm_z2"],
               "lever": ["lever_x1", "lever_y1", "lever_z1", "lever_x2", "lever_y2", "lever_z2"]}
    for box in ("lid", "tilt", "crate"):
        columns[box] = [box + "_" + c for c in ("x", "y", "z")]
    for f in (0, len(frames) // 2, len(frames) - 1):
        t = driver.execute_script("return phynjo.frameTime(arguments[0])", f)
        assert t == frames[f]
        row = by_time[t]
        for i, name in enumerate(hook[3]):
            shown = driver.execute_script("return phynjo.position(arguments[0], arguments[1])", i, f)
            want = [float(row[c]) for c in columns[name]]
            # float32: relative error at most 2^-24 (docs/viewer.md)
            assert all(abs(a - b) <= 2 ** -24 * abs(b) + 1e-30 for a, b in zip(shown, want)), (name, f, shown, want)
            if name in ("lid", "tilt", "crate"):  # int16 quaternions: within 2^-15 of the CSV's (docs/viewer.md)
                shown = driver.execute_script("return phynjo.orientation(arguments[0], arguments[1])", i, f)
                want = [float(row[name + "_q" + c]) for c in "wxyz"]
                assert all(abs(a - b) <= 2e-5 for a, b in zip(shown, want)), (name, f, shown, want)


def test_events_and_the_stop_reason_are_on_the_page(pages, driver):
    """Catches: events missing from the page's time axis, or a run that stopped early shown as
    if it had finished."""
    browser.load(driver, pages / "ball.html")
    bounces = rows(pages / "bounces.csv")
    events = driver.execute_script("return phynjo.meta.events")
    assert [e["t"] for e in events] == [float(r["t"]) for r in bounces]
    assert all(e["name"] == "bounce" for e in events)
    banner = driver.execute_script("return document.getElementById('banner').hidden ? '' : document.getElementById('banner').textContent")
    stopped = driver.execute_script("return phynjo.meta.stop")
    if float(rows(pages / "ball.csv")[-1]["t"]) < 3:  # the run stopped early: the page says why
        assert stopped and stopped in banner
    else:
        assert stopped == "" and banner == ""


def test_the_slider_seeks_and_play_advances_in_real_time(pages, driver):
    """Catches: a slider that does not move the scene, a seek to the wrong frame, play that
    does not advance (or not at real time by default), keys that do nothing."""
    browser.load(driver, pages / "shapes.html")
    n = driver.execute_script("return phynjo.frameCount")
    driver.execute_script("const s = document.getElementById('slider'); s.value = arguments[0];"
                          "s.dispatchEvent(new Event('input'));", n // 3)
    assert driver.execute_script("return phynjo.frame()") == n // 3
    driver.execute_script("phynjo.seek(1.0)")
    f = driver.execute_script("return phynjo.frame()")
    assert driver.execute_script("return phynjo.frameTime(arguments[0])", f) <= 1.0 < \
        driver.execute_script("return phynjo.frameTime(arguments[0])", f + 1)
    # 1x by default: the simulated time advances with the animation ticks' wall clock; at 0.25x
    # a quarter as fast (a frame per tick would look like 1x at 60 frames per second, not 0.25x).
    # The rate between two ticks 0.6 s apart, so a slow machine's late ticks do not matter.
    for speed in (None, 0.25):
        driver.execute_script("phynjo.seek(0); if (arguments[0]) phynjo.setSpeed(arguments[0]); phynjo.play()", speed)
        a, b = driver.execute_async_script(
            "const done = arguments[0];"
            "setTimeout(() => { const a = phynjo.playClock();"
            "  setTimeout(() => { const b = phynjo.playClock(); phynjo.pause(); done([a, b]); }, 600); }, 150);")
        rate = (b[1] - a[1]) / ((b[0] - a[0]) / 1000)
        assert b[0] - a[0] > 300 and abs(rate - (speed or 1)) < 0.02 * (speed or 1), (speed, a, b, rate)
    driver.execute_script("phynjo.setSpeed(1)")
    # keyboard: space plays, the right arrow steps one frame
    driver.execute_script("phynjo.seekFrame(10)")
    driver.execute_script("window.dispatchEvent(new KeyboardEvent('keydown', {key: 'ArrowRight'}))")
    assert driver.execute_script("return phynjo.frame()") == 11
    driver.execute_script("window.dispatchEvent(new KeyboardEvent('keydown', {key: ' '}))")
    assert driver.execute_script("return phynjo.isPlaying()") is True
    driver.execute_script("phynjo.pause()")


def hue(rgb):
    return colorsys.rgb_to_hsv(*(c / 255 for c in rgb))


def test_a_screenshot_shows_the_spheres_where_the_camera_puts_them(pages, driver):
    """Catches: a blank or black canvas (a shader that does not compile, instances never
    updated, the camera pointing away), or a sphere drawn elsewhere than its position
    through the page's camera (positions misread, instances out of order)."""
    browser.load(driver, pages / "shapes.html")
    driver.execute_script("phynjo.seekFrame(60)")
    width, height, pixels = browser.png_pixels(driver.get_screenshot_as_png())
    rect = driver.execute_script("const r = document.querySelector('#view canvas').getBoundingClientRect();"
                                 "return [r.left, r.top, r.width, r.height]")
    x0, y0, w, h = (int(v) for v in rect)
    view = [pixels[y][x] for y in range(y0 + 2, y0 + h - 2, 4) for x in range(x0 + 2, x0 + w - 2, 4)]
    background = max(set(view), key=view.count)
    assert len(set(view)) > 50, "the 3-D view is blank"
    assert sum(p != background for p in view) > 0.002 * len(view)
    for body in (0, 2, 4):  # bob1, bob2 (out of the plane), the post
        x, y = driver.execute_script("return phynjo.project(arguments[0])", body)
        colour = driver.execute_script("return phynjo.colour(arguments[0])", body)
        seen = pixels[round(y)][round(x)]
        hs, hc = hue(seen), hue(colour)
        assert seen != background, (body, seen)
        assert min(abs(hs[0] - hc[0]), 1 - abs(hs[0] - hc[0])) < 0.04 and hs[1] > 0.3, (body, seen, colour)


def test_rigid_bodies_are_drawn_at_their_recorded_pose(pages, driver):
    """Catches: orientations recorded but not drawn (no spin visible), quaternion components
    out of order between the file and three.js, a body drawn at the wrong place or size."""
    browser.load(driver, pages / "torque_free_top.html")
    n = driver.execute_script("return phynjo.frameCount")
    radius = driver.execute_script("return phynjo.meta.bodies[0].radius")
    assert radius == pytest.approx(math.sqrt(2.5 * 2), rel=1e-12)  # I = diag(1, 2, 3) kg m^2, 1 kg: mean 2
    turned = 0
    for f in (0, n // 3, n // 2, n - 1):
        driver.execute_script("phynjo.seekFrame(arguments[0])", f)
        drawn = driver.execute_script("return phynjo.drawn(0)")
        q = driver.execute_script("return phynjo.orientation(0, arguments[0])", f)
        p = driver.execute_script("return phynjo.position(0, arguments[0])", f)
        norm = math.sqrt(sum(c * c for c in q))
        same = abs(sum(a * b / norm for a, b in zip(drawn["quaternion"], q)))  # q and -q: one rotation
        assert same > 1 - 1e-6, (f, drawn, q)
        assert drawn["position"] == pytest.approx(p, abs=1e-6)
        assert drawn["scale"] == pytest.approx([radius] * 3, rel=1e-5)
        turned += abs(q[0]) < 0.99
    assert turned >= 2  # the top turns: most of these frames are not the identity


def test_boxes_and_capsules_are_drawn_as_their_shapes(pages, driver):
    """Catches: a box or a capsule drawn as a sphere (the kind lost on the way to the page), a
    box scaled by its half-extents instead of its sides or with its axes swapped, a capsule
    whose outline is not its radius and segment (a diameter for a radius, the caps missing),
    an orientation not applied to them, or a shape invisible in the picture."""
    browser.load(driver, pages / "shaped.html")
    meta = driver.execute_script("return phynjo.meta.bodies")
    assert [b["kind"] for b in meta] == ["box", "capsule", "sphere"]
    assert meta[0]["half_extents"] == pytest.approx([0.3, 0.1, 0.2], rel=1e-12)
    assert meta[1]["radius"] == pytest.approx(0.1, rel=1e-12)
    assert meta[1]["half_extents"][1] == pytest.approx(0.3, rel=1e-12)
    lo, hi = driver.execute_script("return phynjo.geometryBounds(0)")
    assert lo == pytest.approx([-0.5] * 3, abs=1e-6) and hi == pytest.approx([0.5] * 3, abs=1e-6)
    lo, hi = driver.execute_script("return phynjo.geometryBounds(1)")
    assert hi[1] == pytest.approx(0.4, abs=1e-6) and lo[1] == pytest.approx(-0.4, abs=1e-6)  # L + r
    assert max(hi[0], hi[2]) == pytest.approx(0.1, rel=1e-3) and min(lo[0], lo[2]) == pytest.approx(-0.1, rel=1e-3)
    n = driver.execute_script("return phynjo.frameCount")
    for f in (0, n // 4, n - 1):
        driver.execute_script("phynjo.seekFrame(arguments[0])", f)
        for body, scale in ((0, [0.6, 0.2, 0.4]), (1, [1, 1, 1])):
            drawn = driver.execute_script("return phynjo.drawn(arguments[0])", body)
            q = driver.execute_script("return phynjo.orientation(arguments[0], arguments[1])", body, f)
            p = driver.execute_script("return phynjo.position(arguments[0], arguments[1])", body, f)
            norm = math.sqrt(sum(c * c for c in q))
            assert abs(sum(a * b / norm for a, b in zip(drawn["quaternion"], q))) > 1 - 1e-6, (f, body, drawn, q)
            assert drawn["position"] == pytest.approx(p, abs=1e-6)
            assert drawn["scale"] == pytest.approx(scale, rel=1e-5)
    # the picture: at each shape's projected centre, its own colour
    driver.execute_script("phynjo.seekFrame(arguments[0])", n - 1)
    width, height, pixels = browser.png_pixels(driver.get_screenshot_as_png())
    for body in (0, 1, 2):
        x, y = driver.execute_script("return phynjo.project(arguments[0])", body)
        colour = driver.execute_script("return phynjo.colour(arguments[0])", body)
        hs, hc = hue(pixels[round(y)][round(x)]), hue(colour)
        assert min(abs(hs[0] - hc[0]), 1 - abs(hs[0] - hc[0])) < 0.04 and hs[1] > 0.3, (body, hs, hc)
