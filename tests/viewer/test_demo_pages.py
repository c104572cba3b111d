"""Every animation `make demo` wrote opens offline in a real Chromium and plays.

The pages are those demo-output/index.html links (PHYNJO_DEMO_OUTPUT; the demo's own test
writes them first, tests/CMakeLists.txt)."""
import os
import re

import browser


def test_every_animation_linked_from_the_index_opens_offline_and_plays():
    """Catches: an example whose page does not open (a script error, a page too large, a
    network request), has no frames or bodies, or does not play; an index that links a page
    the demo did not write, or links none."""
    out = os.environ["PHYNJO_DEMO_OUTPUT"]
    with open(os.path.join(out, "index.html")) as f:
        index = f.read()
    pages = re.findall(r'href="([a-z_]+\.html)"', index)
    assert len(pages) >= 18, pages  # the 18 examples with geometry (scripts/demo-index)
    driver = browser.start()
    try:
        for page in pages:
            path = os.path.join(out, page)
            assert os.path.exists(path), page
            browser.requested_urls(driver)
            browser.load(driver, path)
            assert all(u.startswith("file://") or u.startswith("data:") for u in browser.requested_urls(driver)), page
            assert browser.console_errors(driver) == [], page
            frames, bodies = driver.execute_script("return [phynjo.frameCount, phynjo.bodyCount]")
            assert frames > 10 and bodies > 0, (page, frames, bodies)
            # plays: the time moves past the first frame (waited for up to 20 s: software WebGL
            # on a loaded machine draws a big scene's first frames slowly; the rate is
            # test_viewer.py's)
            driver.execute_script("phynjo.seekFrame(0)")
            start, t = browser.plays(driver)
            assert t > start, (page, t, start)
            assert driver.execute_script("return phynjo.errors") == [], page
    finally:
        driver.quit()
