#!/usr/bin/env python3
"""The viewer's size and draw-time comparisons (bench_viewer runs it with the pages it wrote).

  ratio html_size_meshcat_pile          MeshCat's recorded animation of the same frames over ours.
      MeshCat's encoding, as meshcat-python's animation.py lowers it and a static MeshCat page
      embeds it: one `set_animation` command, msgpack, base64; per body a clip with a
      ".position" (vector3) and a ".quaternion" track, each key {time: frame, value: [...]},
      every number a float64 (msgpack written here, by the specification). Ours: the page's
      frame data (base64), times and series included.
  ratio html_draw_instanced_pile_8000   the naive three.js scene (one Mesh per sphere, the same
      geometry, shader, canvas size and camera) over ours (one InstancedMesh): the mean time
      to pose every sphere from a frame and draw it, waited for with gl.finish, in headless
      Chromium (SwiftShader: software WebGL, so both are CPU-bound; a GPU changes both).
usage: viewer_bench.py PILE_1000.html PILE_8000.html"""
import base64
import json
import os
import re
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "viewer"))
import browser  # noqa: E402  (tests/viewer/browser.py: Chromium offline)


def element(page, id_):
    m = re.search(r'id="%s">(.*?)</script>' % id_, page, re.S)
    return m.group(1)


# ---- msgpack (https://github.com/msgpack/msgpack/blob/master/spec.md), the subset MeshCat uses
def pack(x, out):
    if x is True or x is False:
        out.append(0xC3 if x else 0xC2)
    elif isinstance(x, int):
        if 0 <= x < 128:
            out.append(x)
        elif 0 <= x < 1 << 8:
            out += b"\xcc" + struct.pack(">B", x)
        elif 0 <= x < 1 << 16:
            out += b"\xcd" + struct.pack(">H", x)
        else:
            out += b"\xce" + struct.pack(">I", x)
    elif isinstance(x, float):
        out += b"\xcb" + struct.pack(">d", x)
    elif isinstance(x, str):
        b = x.encode()
        if len(b) < 32:
            out.append(0xA0 | len(b))
        elif len(b) < 256:
            out += b"\xd9" + struct.pack(">B", len(b))
        else:
            out += b"\xda" + struct.pack(">H", len(b))
        out += b
    elif isinstance(x, (list, tuple)):
        if len(x) < 16:
            out.append(0x90 | len(x))
        elif len(x) < 1 << 16:
            out += b"\xdc" + struct.pack(">H", len(x))
        else:
            out += b"\xdd" + struct.pack(">I", len(x))
        for v in x:
            pack(v, out)
    elif isinstance(x, dict):
        if len(x) < 16:
            out.append(0x80 | len(x))
        else:
            out += b"\xde" + struct.pack(">H", len(x))
        for k, v in x.items():
            pack(k, out)
            pack(v, out)
    else:
        raise TypeError(type(x))


def decode(page):
    meta = json.loads(element(page, "phynjo-meta"))
    frames_b64 = re.sub(r"\s+", "", element(page, "phynjo-frames"))
    raw = base64.b64decode(frames_b64)
    F, S = meta["frames"], len(meta["series"])
    P = sum(3 if b["kind"] == "sphere" else 6 for b in meta["bodies"])
    Q = sum(1 for b in meta["bodies"] if b["oriented"])
    at = 8 * F * (1 + S)
    pos = struct.unpack_from("<%df" % (F * P), raw, at)
    at += 4 * F * P
    quat = struct.unpack_from("<%dh" % (F * Q * 4), raw, at)
    return meta, frames_b64, pos, quat, P, Q


def size_ratio(path):
    page = open(path).read()
    meta, ours, pos, quat, P, Q = decode(page)
    F = meta["frames"]
    animations = []
    for i, b in enumerate(meta["bodies"]):
        keys_p = [{"time": f, "value": [float(v) for v in pos[f * P + 3 * i:f * P + 3 * i + 3]]} for f in range(F)]
        keys_q = []
        for f in range(F):
            w, x, y, z = (c / 32767 for c in quat[4 * (f * Q + i):4 * (f * Q + i) + 4])
            keys_q.append({"time": f, "value": [x, y, z, w]})  # three.js order (x, y, z, w)
        animations.append({"path": "/meshcat/pile/" + b["name"], "clip": {
            "fps": 60, "name": "default",
            "tracks": [{"name": ".position", "type": "vector3", "keys": keys_p},
                       {"name": ".quaternion", "type": "quaternion", "keys": keys_q}]}})
    out = bytearray()
    pack({"type": "set_animation", "animations": animations, "options": {"play": True, "repetitions": 1}}, out)
    meshcat = len(base64.b64encode(bytes(out)))
    print("  pile %d, %d frames: MeshCat's animation %.2f MB (msgpack %.2f MB, base64), ours %.2f MB (base64; %d bytes a "
          "sphere and frame before base64)" % (len(meta["bodies"]), F, meshcat / 1e6, len(out) / 1e6, len(ours) / 1e6,
                                              len(base64.b64decode(ours)) // max(F * len(meta["bodies"]), 1)))
    print("ratio html_size_meshcat_pile = %.2f" % (meshcat / len(ours)))


NAIVE = r"""
(function () {
  const meta = JSON.parse(document.getElementById('phynjo-meta').textContent);
  const s = atob(document.getElementById('phynjo-frames').textContent.replace(/\s+/g, ''));
  const u = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) u[i] = s.charCodeAt(i);
  const F = meta.frames, S = meta.series.length, B = meta.bodies.length;
  const pos = new Float32Array(u.buffer, 8 * F * (1 + S), F * 3 * B);
  const quat = new Int16Array(u.buffer, 8 * F * (1 + S) + 12 * F * B, F * 4 * B);
  const W = +document.body.dataset.width, H = +document.body.dataset.height;
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(W, H);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, W / H, 0.01, 1000);
  const c = JSON.parse(document.body.dataset.camera);
  camera.position.set(c[0], c[1], c[2]);
  camera.lookAt(c[3], c[4], c[5]);
  const vs = 'varying vec3 vNormal; varying vec3 vLocal; void main() { vLocal = position; mat4 mv = modelViewMatrix;' +
             ' vNormal = normalize(mat3(mv) * normal); gl_Position = projectionMatrix * mv * vec4(position, 1.0); }';
  const fs = 'uniform vec3 colour; varying vec3 vNormal; varying vec3 vLocal; void main() { vec3 n = normalize(vNormal);' +
             ' float d = max(dot(n, normalize(vec3(0.35, 0.6, 0.7))), 0.0); vec3 c = colour;' +
             ' if (abs(vLocal.x) < 0.13 && vLocal.z > 0.0) c *= 0.35; gl_FragColor = vec4(c * (0.5 + 0.5 * d), 1.0); }';
  const geometry = new THREE.SphereBufferGeometry(1, 10, 7);
  const palette = [0x1f77b4, 0xd62728, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf, 0xbcbd22, 0x7f7f7f];
  const materials = palette.map(function (p) {
    return new THREE.ShaderMaterial({ vertexShader: vs, fragmentShader: fs, uniforms: { colour: { value: new THREE.Color(p) } } });
  });
  const meshes = [];
  for (let i = 0; i < B; ++i) {
    const m = new THREE.Mesh(geometry, materials[i % materials.length]);
    m.scale.setScalar(meta.bodies[i].radius);
    scene.add(m);
    meshes.push(m);
  }
  function pose(f) {
    for (let i = 0; i < B; ++i) {
      const p = 3 * (f * B + i), q = 4 * (f * B + i);
      meshes[i].position.set(pos[p], pos[p + 1], pos[p + 2]);
      meshes[i].quaternion.set(quat[q + 1] / 32767, quat[q + 2] / 32767, quat[q + 3] / 32767, quat[q] / 32767).normalize();
    }
  }
  window.naive = {
    drawTime: function (f, n) {
      const gl = renderer.getContext();
      pose(f); renderer.render(scene, camera); gl.finish();
      const a = performance.now();
      for (let k = 0; k < n; ++k) { pose(f); renderer.render(scene, camera); gl.finish(); }
      return (performance.now() - a) / n;
    },
    drawCalls: function () { return renderer.info.render.calls; }
  };
})();
"""


def draw_ratio(path):
    page = open(path).read()
    driver = browser.start(1400, 850)
    try:
        browser.load(driver, path)
        n = driver.execute_script("return phynjo.frameCount")
        frame = n // 2
        driver.execute_script("phynjo.seekFrame(arguments[0])", frame)
        w, h = driver.execute_script("const c = document.querySelector('#view canvas'); return [c.width, c.height]")
        camera = driver.execute_script(
            "const c = phynjo.camera(); return [c.position.x, c.position.y, c.position.z, c.target.x, c.target.y, c.target.z]")
        ours = min(driver.execute_script("return phynjo.drawTime(20)") for _ in range(3))
        calls_ours = driver.execute_script("return phynjo.drawCalls()")
        three = re.search(r"<script>(\(function\(global,factory\).*?)</script>", page, re.S).group(1)
        naive_path = os.path.join(os.path.dirname(path), "naive_" + os.path.basename(path))
        with open(naive_path, "w") as f:
            f.write('<!DOCTYPE html><html><head><meta charset="utf-8"></head><body style="margin:0" data-width="%d" '
                    'data-height="%d" data-camera="%s"><script>%s</script>'
                    '<script type="application/json" id="phynjo-meta">%s</script>'
                    '<script type="application/octet-stream" id="phynjo-frames">%s</script><script>%s</script></body></html>'
                    % (w, h, json.dumps(camera), three, element(page, "phynjo-meta"), element(page, "phynjo-frames"), NAIVE))
        driver.get("file://" + os.path.abspath(naive_path))
        driver.execute_async_script("const done = arguments[0]; (function wait() { if (window.naive) done(); else setTimeout(wait, 50); })();")
        naive = min(driver.execute_script("return naive.drawTime(arguments[0], 5)", frame) for _ in range(3))
        calls_naive = driver.execute_script("return naive.drawCalls()")
    finally:
        driver.quit()
    print("  pile %s, a %dx%d canvas, frame %d: one mesh per sphere %.1f ms a frame (%d draw calls), instanced %.1f ms "
          "(%d draw calls)" % (re.search(r"pile_(\d+)", path).group(1), w, h, frame, naive, calls_naive, ours, calls_ours))
    print("ratio html_draw_instanced_pile_8000 = %.2f" % (naive / ours))


if __name__ == "__main__":
    size_ratio(sys.argv[1])
    draw_ratio(sys.argv[2])
