"""A real, headless Chromium for the viewer's tests (Debian's chromium, chromium-driver and
python3-selenium, which scripts/install-deps installs): offline, its console and network
requests logged, and a small PNG decoder for its screenshots (no imaging library needed)."""
import json
import os
import struct
import zlib

from selenium import webdriver
from selenium.webdriver.chrome.service import Service

CHROMIUM = os.environ.get("PHYNJO_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("PHYNJO_CHROMEDRIVER", "/usr/bin/chromedriver")


def start(width=1280, height=800):
    """Chromium, headless, software WebGL (SwiftShader), no network: every host unresolvable,
    a dead proxy, and the DevTools network emulation offline (set by `load`)."""
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for a in ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--no-first-run",
              "--disable-background-networking", "--disable-component-update", "--disable-sync",
              "--disable-extensions", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
              "--force-device-scale-factor=1", f"--window-size={width},{height}",
              "--host-resolver-rules=MAP * ~NOTFOUND", "--proxy-server=127.0.0.1:9",
              "--allow-file-access-from-files"]:
        options.add_argument(a)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_script_timeout(120)
    driver.set_page_load_timeout(120)
    return driver


def load(driver, path):
    """Opens a page from file:// with the network emulated offline; waits for the viewer."""
    driver.execute_cdp_cmd("Network.enable", {})
    driver.execute_cdp_cmd("Network.emulateNetworkConditions",
                           {"offline": True, "latency": 0, "downloadThroughput": 0, "uploadThroughput": 0})
    driver.get("file://" + os.path.abspath(path))
    driver.execute_async_script(
        "const done = arguments[0];"
        "(function wait() { if (window.phynjo && window.phynjo.ready) done(true); else setTimeout(wait, 50); })();")


def plays(driver, speed=10, seconds=20):
    """Plays the loaded page from where it is at `speed` until its time moves, or `seconds`
    of wall time have passed (software WebGL on a loaded machine draws a big scene's first
    frames slowly); then pauses. Returns (the time before, the time after)."""
    start = driver.execute_script("return phynjo.time()")
    driver.execute_script(f"phynjo.setSpeed({speed}); phynjo.play()")
    t = driver.execute_async_script(
        "const start = arguments[0], done = arguments[arguments.length - 1], until = performance.now() + arguments[1];"
        "(function wait() { const t = phynjo.time();"
        "  if (t > start || performance.now() > until) done(t); else setTimeout(wait, 50); })();", start, seconds * 1000)
    driver.execute_script("phynjo.pause()")
    return start, t


def requested_urls(driver):
    """Every URL the page asked for since the last call (DevTools performance log)."""
    urls = []
    for entry in driver.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        if message.get("method") == "Network.requestWillBeSent":
            urls.append(message["params"]["request"]["url"])
    return urls


def console_errors(driver):
    return [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def png_pixels(png):
    """(width, height, rows) of an 8-bit RGB or RGBA, non-interlaced PNG; rows[y][x] = (r, g, b)."""
    assert png[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    at, idat, header = 8, b"", None
    while at < len(png):
        (length,) = struct.unpack(">I", png[at:at + 4])
        kind, body = png[at + 4:at + 8], png[at + 8:at + 8 + length]
        at += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, f"unsupported PNG {header}"
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous, i = [], bytearray(stride), 0
    for _ in range(height):
        kind, line = raw[i], bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return width, height, rows
