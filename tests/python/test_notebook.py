"""What Jupyter shows of phynjo, in a real Chromium (Debian's chromium and chromium-driver,
tests/viewer/browser.py): a result's _repr_html_ plays the run it was made from."""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "viewer"))
import browser  # noqa: E402


def test_a_results_html_plays_this_run_in_the_notebooks_iframe(compile_model, tmp_path):
    """Catches: a notebook display that shows nothing (the page escaped wrongly into srcdoc, a
    script blocked by the sandbox), or another run than the result's (other parameters or
    initial values): the iframe's page loads offline, its last frame is the result's end."""
    dp = compile_model("double_pendulum.lag")
    r = dp.simulate(t_end=2, dt=1e-3, integrator="rk4", params={"m2": 2}, initial={"th1": 0.5, "th2": 1.0})
    cell = r._repr_html_()
    assert cell.startswith("<iframe") and "srcdoc=" in cell
    page = tmp_path / "notebook.html"
    page.write_text("<!doctype html><html><body><h1>a notebook cell</h1>" + cell + "</body></html>")
    # under the sanitizers (tests/CMakeLists.txt preloads their runtime into the interpreter)
    # Chromium runs as it is
    os.environ.pop("LD_PRELOAD", None)
    driver = browser.start()
    try:
        driver.get("file://" + str(page))
        frame = driver.find_element("tag name", "iframe")
        driver.switch_to.frame(frame)
        driver.execute_async_script(
            "const done = arguments[arguments.length - 1], until = performance.now() + 60000;"
            "(function wait() { if ((window.phynjo && window.phynjo.ready) || performance.now() > until) done(true);"
            " else setTimeout(wait, 50); })();")
        assert driver.execute_script("return !!(window.phynjo && window.phynjo.ready)")
        frames, bodies = driver.execute_script("return [phynjo.frameCount, phynjo.bodyCount]")
        assert frames > 10 and bodies > 0
        last = driver.execute_script("return phynjo.frameTime(phynjo.frameCount - 1)")
        assert abs(last - r.t_end) < 1e-9
        assert driver.execute_script("return phynjo.errors") == []
        # bob2 at the last frame is where the result's last state puts it (float32 on the page)
        import math
        names = driver.execute_script("return phynjo.meta.bodies.map(b => b.name)")
        shown = driver.execute_script("return phynjo.position(arguments[0], arguments[1])", names.index("bob2"), frames - 1)
        th1, th2 = r.q[-1]
        want = [math.sin(th1) + math.sin(th2), -math.cos(th1) - math.cos(th2), 0.0]
        assert all(abs(a - b) <= 1e-6 for a, b in zip(shown, want)), (shown, want)
        start, t = browser.plays(driver)
        assert t > start
    finally:
        driver.quit()
