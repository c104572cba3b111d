// The phynjo viewer (docs/viewer.md): plays the frames of one run, written into this page by
// the Recorder (runtime/include/phynjo/runtime/view/recorder.hpp), with three.js.
(function () {
  'use strict';
  const errors = [];
  window.addEventListener('error', function (e) { errors.push(String(e.message)); });

  // ---- the data (docs/viewer.md, *The file*) -------------------------------------------------
  const meta = JSON.parse(document.getElementById('phynjo-meta').textContent);
  function decode(text) {
    const s = atob(text.replace(/\s+/g, ''));
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) u[i] = s.charCodeAt(i);
    return u.buffer;
  }
  const buffer = decode(document.getElementById('phynjo-frames').textContent);
  const F = meta.frames, S = meta.series.length, bodies = meta.bodies, B = bodies.length;
  let floatsPerFrame = 0, quatsPerFrame = 0;
  const posAt = [], quatAt = [];
  for (const b of bodies) {
    posAt.push(floatsPerFrame);
    floatsPerFrame += b.kind === 'rod' ? 6 : 3;
    quatAt.push(b.oriented ? quatsPerFrame++ : -1);
  }
  const expected = 8 * F * (1 + S) + 4 * F * floatsPerFrame + 8 * F * quatsPerFrame;
  if (buffer.byteLength !== expected)
    throw new Error('phynjo viewer: the frames hold ' + buffer.byteLength + ' bytes, not the ' + expected + ' the header describes');
  let offset = 0;
  const times = new Float64Array(buffer, 0, F);
  offset += 8 * F;
  const series = meta.series.map(function (s, i) { return new Float64Array(buffer, offset + 8 * F * i, F); });
  offset += 8 * F * S;
  const pos = new Float32Array(buffer, offset, F * floatsPerFrame);
  offset += 4 * F * floatsPerFrame;
  const quat = new Int16Array(buffer, offset, F * quatsPerFrame * 4);
  const t0 = F ? times[0] : 0, t1 = F ? times[F - 1] : 0;

  // the scene's extent over the whole run (the camera, planes, automatic radii)
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let k = 0; k < pos.length; ++k) {
    const x = pos[k], a = k % floatsPerFrame % 3;
    if (x === x) { if (x < lo[a]) lo[a] = x; if (x > hi[a]) hi[a] = x; }
  }
  let maxRadius = 0;
  for (const b of bodies) if (b.radius > maxRadius) maxRadius = b.radius;
  for (let a = 0; a < 3; ++a) {
    if (!(lo[a] <= hi[a])) { lo[a] = -1; hi[a] = 1; }
    lo[a] -= maxRadius; hi[a] += maxRadius;
  }
  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const extent = Math.max(Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]), 1e-3);

  // ---- the 3-D view ---------------------------------------------------------------------------
  const view = document.getElementById('view');
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const background = new THREE.Color(0xf4f4ef), flashColour = new THREE.Color(0xffe0c0);
  scene.background = background.clone();
  const camera = new THREE.PerspectiveCamera(40, 1, extent * 1e-3, extent * 100);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.enableKeys = false; // the arrows step frames
  controls.addEventListener('change', function () { needsRender = true; });
  function resetView() {
    const flat = hi[2] - lo[2] < 0.05 * extent; // a planar model (x, y): look along −z
    const dir = flat ? new THREE.Vector3(0.15, 0.12, 1) : new THREE.Vector3(1, 0.75, 1.4);
    const distance = 0.5 * extent / Math.sin(THREE.MathUtils ? THREE.MathUtils.degToRad(20) : 20 * Math.PI / 180) * 1.05;
    camera.position.copy(centre).addScaledVector(dir.normalize(), distance);
    camera.up.set(0, 1, 0);
    controls.target.copy(centre);
    controls.update();
    needsRender = true;
  }

  const palette = [0x1f77b4, 0xd62728, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf, 0xbcbd22, 0x7f7f7f];
  const baseColour = bodies.map(function (b, i) { return new THREE.Color(palette[i % palette.length]); });

  const vertexShader = [
    'attribute vec3 instColor;', 'varying vec3 vColor; varying vec3 vNormal; varying vec3 vLocal;',
    'void main() {', '  vColor = instColor; vLocal = position;',
    '  mat4 mv = modelViewMatrix * instanceMatrix;',
    '  vNormal = normalize(mat3(mv) * normal);',
    '  gl_Position = projectionMatrix * mv * vec4(position, 1.0);', '}'].join('\n');
  const fragmentShader = [
    'uniform float meridian;', 'varying vec3 vColor; varying vec3 vNormal; varying vec3 vLocal;',
    'void main() {', '  vec3 n = normalize(vNormal);',
    '  float d = max(dot(n, normalize(vec3(0.35, 0.6, 0.7))), 0.0);',
    '  vec3 c = vColor;',
    // a half great circle in the body's x = 0 plane, so a spin can be seen
    '  if (meridian > 0.5 && abs(vLocal.x) < 0.13 && vLocal.z > 0.0) c *= 0.35;',
    '  gl_FragColor = vec4(c * (0.5 + 0.5 * d), 1.0);', '}'].join('\n');
  function instanced(geometry, list, withMeridian) {
    const colours = new Float32Array(3 * list.length);
    geometry.setAttribute('instColor', new THREE.InstancedBufferAttribute(colours, 3));
    const material = new THREE.ShaderMaterial({ vertexShader: vertexShader, fragmentShader: fragmentShader,
                                                uniforms: { meridian: { value: withMeridian ? 1 : 0 } } });
    const mesh = new THREE.InstancedMesh(geometry, material, list.length);
    mesh.frustumCulled = false; // its bounding sphere is the geometry's, not the instances'
    scene.add(mesh);
    return { mesh: mesh, list: list, colours: colours };
  }
  const autoRadius = { sphere: 0.025 * extent, rod: 0.008 * extent, box: 0, capsule: 0 }; // a box's and a capsule's size are their own
  const radius = bodies.map(function (b) { return b.radius > 0 ? b.radius : autoRadius[b.kind]; });
  const oriented = [], plain = [], rods = [], boxes = [], capsules = new Map();
  bodies.forEach(function (b, i) {
    if (b.kind === 'capsule') { // one mesh per size: a capsule does not scale into another
      const key = b.radius + ' ' + b.half_extents[1];
      if (!capsules.has(key)) capsules.set(key, []);
      capsules.get(key).push(i);
    } else (b.kind === 'rod' ? rods : b.kind === 'box' ? boxes : b.oriented ? oriented : plain).push(i);
  });
  const detail = B > 2000 ? [10, 7] : [24, 16];
  const groups = [];
  if (oriented.length) groups.push(instanced(new THREE.SphereBufferGeometry(1, detail[0], detail[1]), oriented, true));
  if (plain.length) groups.push(instanced(new THREE.SphereBufferGeometry(1, detail[0], detail[1]), plain, false));
  if (rods.length) groups.push(instanced(new THREE.CylinderBufferGeometry(1, 1, 1, 14, 1), rods, false));
  if (boxes.length) groups.push(instanced(new THREE.BoxBufferGeometry(1, 1, 1), boxes, false));
  for (const list of capsules.values()) { // the outline (x = distance from the axis, y along it), turned about y
    const r = bodies[list[0]].radius, L = bodies[list[0]].half_extents[1], outline = [], arc = detail[1];
    for (let k = 0; k <= arc; ++k) { const a = -Math.PI / 2 + Math.PI / 2 * k / arc; outline.push(new THREE.Vector2(r * Math.cos(a), -L + r * Math.sin(a))); }
    for (let k = 0; k <= arc; ++k) { const a = Math.PI / 2 * k / arc; outline.push(new THREE.Vector2(r * Math.cos(a), L + r * Math.sin(a))); }
    outline[0].x = outline[outline.length - 1].x = 0;
    groups.push(instanced(new THREE.LatheBufferGeometry(outline, detail[0]), list, false));
  }

  for (const p of meta.planes) { // a square over the extent, centred where the scene's centre projects
    const n = new THREE.Vector3(p.normal[0], p.normal[1], p.normal[2]);
    const at = centre.clone().addScaledVector(n, p.offset - n.dot(centre));
    const ground = Math.abs(n.y) > 0.9;
    const square = new THREE.Mesh(new THREE.PlaneBufferGeometry(1.4 * extent, 1.4 * extent),
      new THREE.MeshBasicMaterial({ color: ground ? 0xc8c8bc : 0xb0c4de, transparent: true, opacity: ground ? 0.55 : 0.18,
                                    side: THREE.DoubleSide, depthWrite: false }));
    square.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
    square.position.copy(at);
    scene.add(square);
  }
  const axes = new THREE.AxesHelper(0.12 * extent);
  scene.add(axes);

  // ---- frames -------------------------------------------------------------------------------
  let current = 0, simTime = t0, playing = false, speed = 1, needsRender = true, bySpeed = false;
  let speedScale = null; // the largest speed of the run, for the colour map
  const m4 = new THREE.Matrix4(), v3 = new THREE.Vector3(), q4 = new THREE.Quaternion(), s3 = new THREE.Vector3();
  const up = new THREE.Vector3(0, 1, 0), a3 = new THREE.Vector3(), b3 = new THREE.Vector3();

  function position(i, f) {
    const k = f * floatsPerFrame + posAt[i];
    return Array.from(pos.subarray(k, k + (bodies[i].kind === 'rod' ? 6 : 3)));
  }
  function orientation(i, f) {
    if (quatAt[i] < 0) return null;
    const k = 4 * (f * quatsPerFrame + quatAt[i]);
    return [quat[k] / 32767, quat[k + 1] / 32767, quat[k + 2] / 32767, quat[k + 3] / 32767];
  }
  /// A body's speed at frame f: its centre's central difference over the neighbouring frames.
  function speedOf(i, f) {
    if (F < 2) return 0;
    const a = Math.max(f - 1, 0), b = Math.min(f + 1, F - 1), ka = a * floatsPerFrame + posAt[i], kb = b * floatsPerFrame + posAt[i];
    let d2 = 0;
    const n = bodies[i].kind === 'rod' ? 6 : 3;
    for (let c = 0; c < n; ++c) { const d = pos[kb + c] - pos[ka + c]; d2 += d * d; }
    const dt = times[b] - times[a];
    return dt > 0 ? Math.sqrt(d2 / (n / 3)) / dt : 0;
  }
  function colourMap(x, out) { // 0 → blue, 0.5 → green-yellow, 1 → red
    x = Math.min(Math.max(x, 0), 1);
    out.setHSL((1 - x) * 0.66, 0.85, 0.5);
    return out;
  }
  const tmpColour = new THREE.Color();
  function colourOf(i, f) {
    if (!bySpeed) return baseColour[i];
    if (speedScale === null) {
      speedScale = 1e-12;
      for (let g = 0; g < F; ++g) for (let j = 0; j < B; ++j) speedScale = Math.max(speedScale, speedOf(j, g));
    }
    return colourMap(speedOf(i, f) / speedScale, tmpColour);
  }

  function show(f) {
    f = Math.min(Math.max(f | 0, 0), Math.max(F - 1, 0));
    const previous = current;
    current = f;
    if (F === 0) return;
    for (const g of groups) {
      for (let k = 0; k < g.list.length; ++k) {
        const i = g.list[k], p = f * floatsPerFrame + posAt[i], r = radius[i];
        if (bodies[i].kind === 'rod') {
          a3.set(pos[p], pos[p + 1], pos[p + 2]);
          b3.set(pos[p + 3], pos[p + 4], pos[p + 5]);
          v3.addVectors(a3, b3).multiplyScalar(0.5);
          b3.sub(a3);
          const length = b3.length();
          if (length > 0) q4.setFromUnitVectors(up, b3.divideScalar(length)); else q4.set(0, 0, 0, 1);
          s3.set(r, Math.max(length, 1e-9), r);
        } else {
          v3.set(pos[p], pos[p + 1], pos[p + 2]);
          const o = orientation(i, f);
          if (o) q4.set(o[1], o[2], o[3], o[0]).normalize(); else q4.set(0, 0, 0, 1);
          const h = bodies[i].half_extents;
          if (bodies[i].kind === 'box') s3.set(2 * h[0], 2 * h[1], 2 * h[2]);
          else if (bodies[i].kind === 'capsule') s3.set(1, 1, 1);
          else s3.set(r, r, r);
        }
        m4.compose(v3, q4, s3);
        g.mesh.setMatrixAt(k, m4);
        const c = colourOf(i, f);
        g.colours[3 * k] = c.r; g.colours[3 * k + 1] = c.g; g.colours[3 * k + 2] = c.b;
      }
      g.mesh.instanceMatrix.needsUpdate = true;
      g.mesh.geometry.attributes.instColor.needsUpdate = true;
    }
    for (const t of trails.values()) t.line.geometry.setDrawRange(0, f + 1);
    // events passed while playing or stepping forward flash (not while scrubbing)
    if (f > previous && (playing || f === previous + 1)) {
      for (const e of meta.events) if (e.t > times[previous] && e.t <= times[f]) flash(e.name, e.t);
    }
    slider.value = String(f);
    clock.textContent = 't = ' + times[f].toFixed(4) + ' s of ' + t0.toFixed(3) + '\u2013' + t1.toFixed(3) + ' s  (frame ' + (f + 1) + ' / ' + F + ')';
    drawPlot();
    needsRender = true;
  }
  function frameAt(t) { // the last frame at or before t
    let a = 0, b = F - 1;
    if (F === 0 || t <= times[0]) return 0;
    if (t >= times[b]) return b;
    while (b - a > 1) { const m = (a + b) >> 1; if (times[m] <= t) a = m; else b = m; }
    return a;
  }
  let flashUntil = 0;
  const flashBox = document.getElementById('flash');
  function flash(name, t) {
    flashBox.textContent = 'event ' + name + ' at t = ' + t.toFixed(6) + ' s';
    flashBox.style.transition = 'none';
    flashBox.style.opacity = '1';
    scene.background.copy(flashColour);
    flashUntil = performance.now() + 250;
    needsRender = true;
  }

  // ---- trails -------------------------------------------------------------------------------
  const trails = new Map();
  function toggleTrail(i) {
    if (trails.has(i)) {
      scene.remove(trails.get(i).line);
      trails.delete(i);
    } else {
      const n = bodies[i].kind === 'rod' ? 6 : 3, data = new Float32Array(3 * F);
      for (let f = 0; f < F; ++f) {
        const p = f * floatsPerFrame + posAt[i];
        for (let c = 0; c < 3; ++c) data[3 * f + c] = n === 3 ? pos[p + c] : pos[p + 3 + c];
      }
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(data, 3));
      geometry.setDrawRange(0, current + 1);
      const line = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: baseColour[i].getHex() }));
      line.frustumCulled = false;
      scene.add(line);
      trails.set(i, { line: line });
    }
    trailSelect.options[i + 1].textContent = (trails.has(i) ? '\u2713 ' : '') + bodies[i].name;
    trailSelect.value = '';
    needsRender = true;
  }

  // ---- plots --------------------------------------------------------------------------------
  const plot = document.getElementById('plot'), legend = document.getElementById('legend');
  const groupSelect = document.getElementById('group');
  const groupNames = [];
  meta.series.forEach(function (s) { if (groupNames.indexOf(s.group) < 0) groupNames.push(s.group); });
  for (const g of groupNames) groupSelect.add(new Option(g, g));
  const plotRange = {};
  function plotted() { return meta.series.map(function (s, i) { return i; }).filter(function (i) { return meta.series[i].group === groupSelect.value; }); }
  function drawPlot() {
    const ctx = plot.getContext('2d'), W = plot.width, H = plot.height, L = 62, R = 8, T = 8, Bm = 22;
    ctx.clearRect(0, 0, W, H);
    const list = plotted();
    if (!list.length || F === 0) { legend.textContent = S ? '' : 'no series'; return; }
    let range = plotRange[groupSelect.value];
    if (!range) {
      let a = Infinity, b = -Infinity;
      for (const i of list) for (let f = 0; f < F; ++f) { const y = series[i][f]; if (y < a) a = y; if (y > b) b = y; }
      if (!(a <= b)) { a = -1; b = 1; }
      if (a === b) { a -= Math.abs(a) * 0.1 + 1e-12; b += Math.abs(b) * 0.1 + 1e-12; }
      range = plotRange[groupSelect.value] = [a, b];
    }
    const X = function (t) { return L + (W - L - R) * (t1 > t0 ? (t - t0) / (t1 - t0) : 0); };
    const Y = function (y) { return T + (H - T - Bm) * (1 - (y - range[0]) / (range[1] - range[0])); };
    ctx.strokeStyle = '#ccc'; ctx.strokeRect(L, T, W - L - R, H - T - Bm);
    ctx.fillStyle = '#555'; ctx.font = '11px sans-serif';
    ctx.fillText(range[1].toPrecision(4), 2, T + 9); ctx.fillText(range[0].toPrecision(4), 2, H - Bm);
    ctx.fillText(t0.toPrecision(4) + ' s', L, H - 6); ctx.fillText(t1.toPrecision(4) + ' s', W - R - 50, H - 6);
    ctx.strokeStyle = '#ff8c00';
    for (const e of meta.events) { ctx.beginPath(); ctx.moveTo(X(e.t), H - Bm); ctx.lineTo(X(e.t), H - Bm - 8); ctx.stroke(); }
    let html = '';
    list.forEach(function (i, k) {
      const colour = '#' + new THREE.Color(palette[k % palette.length]).getHexString();
      ctx.strokeStyle = colour; ctx.beginPath();
      const step = Math.max(1, Math.floor(F / (2 * (W - L - R))));
      for (let f = 0; f < F; f += step) { const x = X(times[f]), y = Y(series[i][f]); if (f === 0) ctx.moveTo(x, y); else ctx.lineTo(x, y); }
      ctx.stroke();
      const unit = meta.series[i].unit ? ' ' + meta.series[i].unit : '';
      html += '<div><span class="swatch" style="background:' + colour + '"></span>' + escapeHtml(meta.series[i].name) +
              ' = ' + series[i][current].toPrecision(10) + unit + '</div>';
    });
    ctx.strokeStyle = '#000'; ctx.beginPath(); ctx.moveTo(X(times[current]), T); ctx.lineTo(X(times[current]), H - Bm); ctx.stroke();
    legend.innerHTML = html;
  }
  function escapeHtml(s) { return String(s).replace(/[&<>"]/g, function (c) { return { '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]; }); }
  function seekFromPlot(ev) {
    const r = plot.getBoundingClientRect(), L = 62, R = 8;
    const u = ((ev.clientX - r.left) * plot.width / r.width - L) / (plot.width - L - R);
    seek(t0 + Math.min(Math.max(u, 0), 1) * (t1 - t0));
  }
  plot.addEventListener('mousedown', function (ev) { seekFromPlot(ev); plot.onmousemove = seekFromPlot; });
  window.addEventListener('mouseup', function () { plot.onmousemove = null; });
  groupSelect.addEventListener('change', drawPlot);

  // ---- the time line and controls -----------------------------------------------------------
  const slider = document.getElementById('slider'), clock = document.getElementById('clock');
  const playButton = document.getElementById('play');
  slider.max = String(Math.max(F - 1, 0));
  slider.addEventListener('input', function () { pause(); simTime = times[+slider.value]; show(+slider.value); });
  const marks = document.getElementById('marks');
  function drawMarks() {
    marks.width = marks.clientWidth || 800;
    const ctx = marks.getContext('2d');
    ctx.clearRect(0, 0, marks.width, marks.height);
    ctx.fillStyle = '#ff8c00';
    for (const e of meta.events) ctx.fillRect(Math.round((t1 > t0 ? (e.t - t0) / (t1 - t0) : 0) * (marks.width - 1)), 0, 2, marks.height);
  }
  const speeds = [0.1, 0.25, 0.5, 1, 2, 5, 10];
  const speedSelect = document.getElementById('speed');
  for (const s of speeds) speedSelect.add(new Option(s + '\u00d7', String(s)));
  speedSelect.value = '1';
  speedSelect.addEventListener('change', function () { speed = +speedSelect.value; });
  function setSpeed(s) { speed = Math.min(Math.max(s, 0.1), 10); speedSelect.value = String(speeds.reduce(function (a, b) { return Math.abs(b - speed) < Math.abs(a - speed) ? b : a; })); }
  const trailSelect = document.getElementById('trail');
  trailSelect.add(new Option('add / remove\u2026', ''));
  bodies.forEach(function (b, i) { trailSelect.add(new Option(b.name, String(i))); });
  trailSelect.addEventListener('change', function () { if (trailSelect.value !== '') toggleTrail(+trailSelect.value); });
  document.getElementById('bySpeed').addEventListener('change', function (e) { bySpeed = e.target.checked; show(current); });
  document.getElementById('reset').addEventListener('click', resetView);
  let lastTick = null;
  function play() { if (F < 2) return; if (current >= F - 1) { simTime = t0; show(0); } playing = true; lastTick = null; playButton.innerHTML = '&#10074;&#10074;'; }
  function pause() { playing = false; playButton.innerHTML = '&#9654;'; }
  function seek(t) { simTime = Math.min(Math.max(t, t0), t1); show(frameAt(simTime)); }
  function step(d) { pause(); const f = Math.min(Math.max(current + d, 0), F - 1); simTime = times[f]; show(f); }
  playButton.addEventListener('click', function () { if (playing) pause(); else play(); });
  document.getElementById('back').addEventListener('click', function () { step(-1); });
  document.getElementById('fwd').addEventListener('click', function () { step(1); });
  window.addEventListener('keydown', function (e) {
    if (e.target && e.target.tagName === 'SELECT') return;
    // a focused button or slider would act on the key too (space clicks a button on keyup)
    if (e.target && (e.target.tagName === 'BUTTON' || e.target.tagName === 'INPUT')) e.target.blur();
    const k = e.key;
    if (k === ' ') { if (playing) pause(); else play(); }
    else if (k === 'ArrowRight') step(1);
    else if (k === 'ArrowLeft') step(-1);
    else if (k === 'ArrowUp') setSpeed(speeds[Math.min(speeds.indexOf(+speedSelect.value) + 1, speeds.length - 1)]);
    else if (k === 'ArrowDown') setSpeed(speeds[Math.max(speeds.indexOf(+speedSelect.value) - 1, 0)]);
    else if (k === 'Home') step(-F);
    else if (k === 'End') step(F);
    else if (k === 'r') resetView();
    else return;
    e.preventDefault();
  });

  // ---- page text ------------------------------------------------------------------------------
  document.getElementById('name').textContent = meta.title;
  const notes = [];
  if (meta.stop) notes.push('The run stopped early: ' + meta.stop);
  for (const w of meta.warnings) notes.push(w);
  if (notes.length) { const b = document.getElementById('banner'); b.hidden = false; b.textContent = notes.join(' \u2014 '); }
  document.getElementById('about').innerHTML = escapeHtml(B + ' bodies, ' + F + ' frames (' + (+meta.fps).toPrecision(4) +
    ' per simulated second), ' + meta.events.length + ' events. Positions float32, orientations int16, time and series float64.') +
    '<br>Drag: orbit; right-drag: pan; wheel: zoom. Keys: space play/pause, \u2190 \u2192 frame, \u2191 \u2193 speed, r reset view.';

  // ---- the loop -------------------------------------------------------------------------------
  function resize() {
    const w = Math.max(view.clientWidth, 100), h = Math.max(view.clientHeight, 100);
    renderer.setSize(w, h);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    drawMarks();
    needsRender = true;
  }
  window.addEventListener('resize', resize);
  function render() { renderer.render(scene, camera); needsRender = false; }
  function tick(now) {
    if (playing) {
      if (lastTick !== null) simTime += (now - lastTick) / 1000 * speed;
      lastTick = now;
      if (simTime >= t1) { simTime = t1; pause(); }
      const f = frameAt(simTime);
      if (f !== current) show(f);
    }
    if (flashUntil && now > flashUntil) {
      flashUntil = 0;
      scene.background.copy(background);
      flashBox.style.transition = 'opacity 0.6s';
      flashBox.style.opacity = '0';
      needsRender = true;
    }
    if (needsRender) render();
    requestAnimationFrame(tick);
  }

  resize();
  resetView();
  show(0);
  render();
  requestAnimationFrame(tick);

  // ---- the test hook (tests/viewer): what the page shows, read back --------------------------
  window.phynjo = {
    ready: true, errors: errors, meta: meta,
    frameCount: F, bodyCount: B, timeSpan: [t0, t1],
    time: function () { return simTime; }, frame: function () { return current; },
    frameTime: function (f) { return times[f]; },
    position: position, orientation: orientation, seriesValue: function (i, f) { return series[i][f]; },
    play: play, pause: pause, isPlaying: function () { return playing; }, seek: seek,
    seekFrame: function (f) { pause(); f = Math.min(Math.max(f, 0), F - 1); simTime = times[f]; show(f); render(); },
    setSpeed: setSpeed, speed: function () { return speed; },
    /// [the animation tick's time stamp, ms, and the simulated time it showed, s]: playback's rate
    playClock: function () { return [lastTick, simTime]; },
    /// body i's centre (a rod: its first end) at the shown frame, in CSS pixels of the page
    project: function (i) {
      const p = position(i, current);
      const v = new THREE.Vector3(p[0], p[1], p[2]).project(camera);
      const r = renderer.domElement.getBoundingClientRect();
      return [r.left + (v.x + 1) / 2 * r.width, r.top + (1 - v.y) / 2 * r.height];
    },
    colour: function (i) { const c = colourOf(i, current); return [Math.round(c.r * 255), Math.round(c.g * 255), Math.round(c.b * 255)]; },
    render: render,
    /// the mean time of n renders of the shown frame, each waited for (gl.finish), ms
    drawTime: function (n) {
      const gl = renderer.getContext();
      render(); gl.finish();
      const a = performance.now();
      for (let k = 0; k < n; ++k) { show(current); render(); gl.finish(); }
      return (performance.now() - a) / n;
    },
    drawCalls: function () { return renderer.info.render.calls; },
    camera: function () { return { position: camera.position.clone(), target: controls.target.clone() }; },
    /// what is drawn for body i: its instance's position, quaternion (w, x, y, z) and scale
    drawn: function (i) {
      for (const g of groups) {
        const k = g.list.indexOf(i);
        if (k < 0) continue;
        const m = new THREE.Matrix4().fromArray(g.mesh.instanceMatrix.array, 16 * k);
        const p = new THREE.Vector3(), q = new THREE.Quaternion(), s = new THREE.Vector3();
        m.decompose(p, q, s);
        return { position: [p.x, p.y, p.z], quaternion: [q.w, q.x, q.y, q.z], scale: [s.x, s.y, s.z] };
      }
      return null;
    },
    /// the bounds of the mesh body i is drawn with, before its instance's scale: [min, max]
    geometryBounds: function (i) {
      for (const g of groups) {
        if (g.list.indexOf(i) < 0) continue;
        g.mesh.geometry.computeBoundingBox();
        const b = g.mesh.geometry.boundingBox;
        return [[b.min.x, b.min.y, b.min.z], [b.max.x, b.max.y, b.max.z]];
      }
      return null;
    }
  };
})();
