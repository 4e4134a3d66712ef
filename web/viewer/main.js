// The web viewer's page: loads the bundle, streams the photos in, navigates (orbit, fly,
// touch, a photo's viewpoint), keeps the view in the page's address, and offers a test hook
// (window.hdribr) for the browser test (tests/web/).
import { loadScene, loadPoints, loadPhoto } from './bundle.js';
import { Renderer, kTone } from './renderer.js';
import { worldFromCam, quaternionOf, axisAngle, mul3, apply3 } from './math.js';

const kBase = 'capture';
const kParallelFetches = 6;
const $ = (id) => document.getElementById(id);
const t0 = performance.now();
const hook = {
  ready: false, fullFrame: false, error: null, firstPictureMs: null, loadedMs: null, frames: 0, glErrors: 0,
};
window.hdribr = hook;

function showError(e) {
  const message = e && e.message ? e.message : String(e);
  hook.error = message;
  $('error').textContent = `error: ${message}`;
  $('error').hidden = false;
  console.error(`hdribr: ${message}`);
}

// The view: world_from_cam rotation (row-major) and centre; intrinsics from the reference
// camera, scaled to the output size.
const nav = { rot: null, center: null, target: null, refCam: null, photo: -1 };
const tone = { exposure: 0, key: kTone.key, gamma: kTone.gamma, logAverage: 0 };

function setPose(qvec, tvec, cam) {
  const w = worldFromCam(qvec, tvec);
  nav.rot = w.rotation;
  nav.center = w.center;
  if (cam) nav.refCam = cam;
}

function pose() {
  const r = nav.rot;
  const camFromWorldR = [r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]];
  const qvec = quaternionOf(camFromWorldR);
  const tvec = apply3(camFromWorldR, nav.center).map((v) => -v);
  return { qvec, tvec };
}

// Intrinsics of the reference camera for a w x h output: its vertical field of view, centred.
function viewAt(w, h, exact) {
  const c = nav.refCam;
  const cam = exact ? c : (() => {
    const fy = (c.fy * h) / c.height;
    return { fx: fy * (c.fx / c.fy), fy, cx: w / 2, cy: h / 2 };
  })();
  return { cam, w, h, ...pose() };
}

// ?camera=NAME (a photo's viewpoint) or "QW QX QY QZ TX TY TZ [CAMERA_ID]" (render --camera).
function parseCamera(scene, spec) {
  const i = scene.photos.findIndex((p) => p.name === spec);
  if (i >= 0) return { photo: i };
  const v = spec.trim().split(/[\s,]+/).map(Number);
  if ((v.length === 7 || v.length === 8) && v.every(Number.isFinite)) {
    const camId = v.length === 8 ? String(v[7]) : String(scene.photos[0].camera_id);
    const cam = scene.cameras[camId];
    if (!cam) throw new Error(`camera=${spec}: no camera ${camId}`);
    const n = Math.hypot(v[0], v[1], v[2], v[3]);
    if (Math.abs(n - 1) > 1e-3) throw new Error(`camera=${spec}: not a unit quaternion`);
    return { qvec: v.slice(0, 4), tvec: v.slice(4, 7), cam };
  }
  throw new Error(`camera=${spec}: no photo of that name, and not "QW QX QY QZ TX TY TZ [CAMERA_ID]"`);
}

function goToPhoto(scene, i) {
  const p = scene.photos[i];
  setPose(p.qvec, p.tvec, scene.cameras[String(p.camera_id)]);
  nav.photo = i;
  $('photo').value = String(i);
}

function link() {
  const { qvec, tvec } = pose();
  const url = new URL(window.location.href);
  const p = url.searchParams;
  const camId = Object.keys(window.hdribrScene.cameras).find((k) => window.hdribrScene.cameras[k] === nav.refCam);
  p.set('camera', nav.photo >= 0 ? window.hdribrScene.photos[nav.photo].name
    : [...qvec, ...tvec].map((x) => x.toPrecision(9)).join(' ') + (camId ? ` ${camId}` : ''));
  p.set('exposure', String(tone.exposure));
  if (tone.key !== kTone.key) p.set('key', String(tone.key)); else p.delete('key');
  if (tone.gamma !== kTone.gamma) p.set('gamma', String(tone.gamma)); else p.delete('gamma');
  return url.toString();
}

let renderer = null;
let dirty = true;
let toneDirty = true;
const canvas = $('canvas');

// Frames: while the view moves or photos stream in, a reduced frame (half the size each way,
// at most one every kLoadingFrameMs while loading); the full-size frame once still.
const kReducedScale = 0.5;
const kLoadingScale = 0.25;  // while photos stream in
const kStillMs = 250;
const kLoadingFrameMs = 1000;
let lastInput = 0;
let lastRender = 0;
let reducedShown = false;

function frame() {
  requestAnimationFrame(frame);
  if (!renderer || hook.error || hook.busy) return;
  applyKeys();
  const w = Math.max(1, Math.floor(canvas.clientWidth));
  const h = Math.max(1, Math.floor(canvas.clientHeight));
  if (canvas.width !== w || canvas.height !== h) {
    canvas.width = w;
    canvas.height = h;
    dirty = true;
  }
  const now = performance.now();
  const loading = renderer.loadedCount() < renderer.photos.length;
  const still = now - lastInput > kStillMs && !loading;
  if (loading && dirty && hook.firstPictureMs !== null && now - lastRender < kLoadingFrameMs) return;
  if (still && reducedShown) dirty = true;
  if (!dirty && !toneDirty) return;
  const start = performance.now();
  try {
    if (dirty) {
      const s = still ? 1 : loading ? kLoadingScale : kReducedScale;
      renderer.render(viewAt(Math.max(1, Math.round(w * s)), Math.max(1, Math.round(h * s)), false));
      reducedShown = !still;
      hook.fullFrame = still;
      lastRender = now;
    }
    renderer.display(tone, true, w, h);
    const err = renderer.gl.getError();
    if (err !== renderer.gl.NO_ERROR) {
      hook.glErrors += 1;
      throw new Error(`WebGL error ${err}`);
    }
  } catch (e) {
    showError(e);
    return;
  }
  hook.frames += 1;
  if (hook.firstPictureMs === null && renderer.loadedCount() > 0) hook.firstPictureMs = performance.now() - t0;
  $('stats').textContent = `${renderer.loadedCount()}/${renderer.photos.length} photos, ` +
    `${(performance.now() - start).toFixed(0)} ms`;
  dirty = false;
  toneDirty = false;
}

// Keyboard: W/S forward and back, A/D left and right, Q/E down and up, arrows turn; N/P the
// next / previous photo's viewpoint.
const keys = new Set();
function applyKeys() {
  if (!keys.size) return;
  const step = 0.01 * window.hdribrScene.scene_scale;
  const move = [0, 0, 0];
  if (keys.has('w')) move[2] += step;
  if (keys.has('s')) move[2] -= step;
  if (keys.has('d')) move[0] += step;
  if (keys.has('a')) move[0] -= step;
  if (keys.has('e')) move[1] -= step;
  if (keys.has('q')) move[1] += step;
  const d = apply3(nav.rot, move);
  nav.center = nav.center.map((c, i) => c + d[i]);
  const turn = 0.01;
  if (keys.has('arrowleft')) turnBy(-turn, 0);
  if (keys.has('arrowright')) turnBy(turn, 0);
  if (keys.has('arrowup')) turnBy(0, -turn);
  if (keys.has('arrowdown')) turnBy(0, turn);
  moved();
}

function moved() {
  nav.photo = -1;
  dirty = true;
  lastInput = performance.now();
}

// Look around: yaw about the camera's up (-y), pitch about its x.
function turnBy(yaw, pitch) {
  const up = apply3(nav.rot, [0, -1, 0]);
  const right = apply3(nav.rot, [1, 0, 0]);
  nav.rot = mul3(axisAngle(right, pitch), mul3(axisAngle(up, -yaw), nav.rot));
}

// Orbit about the target: the same rotation applied to the centre around it.
function orbitBy(yaw, pitch) {
  const up = apply3(nav.rot, [0, -1, 0]);
  const right = apply3(nav.rot, [1, 0, 0]);
  const r = mul3(axisAngle(right, -pitch), axisAngle(up, -yaw));
  const tgt = orbitTarget();
  const rel = apply3(r, nav.center.map((c, i) => c - tgt[i]));
  nav.center = rel.map((v, i) => v + tgt[i]);
  nav.rot = mul3(r, nav.rot);
}

// The point orbited: on the view's axis at the distance of the scene's centroid.
function orbitTarget() {
  const c = window.hdribrScene.centroid;
  const fwd = apply3(nav.rot, [0, 0, 1]);
  const dist = Math.max(fwd.reduce((s, f, i) => s + f * (c[i] - nav.center[i]), 0), 0.1 * window.hdribrScene.scene_scale);
  return nav.center.map((v, i) => v + dist * fwd[i]);
}

function dolly(amount) {
  const fwd = apply3(nav.rot, [0, 0, 1]);
  nav.center = nav.center.map((v, i) => v + amount * window.hdribrScene.scene_scale * fwd[i]);
  moved();
}

function pan(dx, dy) {
  const s = 0.002 * window.hdribrScene.scene_scale;
  const d = apply3(nav.rot, [-dx * s, -dy * s, 0]);
  nav.center = nav.center.map((v, i) => v + d[i]);
  moved();
}

function bindInput(scene) {
  let drag = null;
  canvas.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, pan: e.button !== 0 || e.shiftKey, pointers: drag?.pointers };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag || e.pointerType === 'touch') return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) pan(dx, dy); else { orbitBy(dx * 0.005, dy * 0.005); moved(); }
  });
  canvas.addEventListener('pointerup', () => { drag = null; });
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('wheel', (e) => { e.preventDefault(); dolly(-0.0005 * e.deltaY); }, { passive: false });
  // Touch: one finger orbits, two pinch to move forward and back and drag to pan.
  let touches = [];
  canvas.addEventListener('touchstart', (e) => { touches = [...e.touches].map((t) => [t.clientX, t.clientY]); e.preventDefault(); }, { passive: false });
  canvas.addEventListener('touchmove', (e) => {
    e.preventDefault();
    const now = [...e.touches].map((t) => [t.clientX, t.clientY]);
    if (now.length === 1 && touches.length === 1) {
      orbitBy((now[0][0] - touches[0][0]) * 0.005, (now[0][1] - touches[0][1]) * 0.005);
      moved();
    } else if (now.length >= 2 && touches.length >= 2) {
      const span = (t) => Math.hypot(t[0][0] - t[1][0], t[0][1] - t[1][1]);
      dolly(0.002 * (span(now) - span(touches)));
      const mid = (t) => [(t[0][0] + t[1][0]) / 2, (t[0][1] + t[1][1]) / 2];
      pan(mid(now)[0] - mid(touches)[0], mid(now)[1] - mid(touches)[1]);
    }
    touches = now;
  }, { passive: false });
  window.addEventListener('keydown', (e) => {
    if (e.target.tagName === 'INPUT' || e.target.tagName === 'SELECT') return;
    const k = e.key.toLowerCase();
    if (k === 'n' || k === 'p') {
      const n = scene.photos.length;
      goToPhoto(scene, ((nav.photo < 0 ? 0 : nav.photo) + (k === 'n' ? 1 : n - 1)) % n);
      dirty = true;
      return;
    }
    keys.add(k);
  });
  window.addEventListener('keyup', (e) => keys.delete(e.key.toLowerCase()));
}

function bindPanel(scene) {
  const sel = $('photo');
  scene.photos.forEach((p, i) => sel.add(new Option(p.name, String(i))));
  sel.addEventListener('change', () => { goToPhoto(scene, Number(sel.value)); dirty = true; });
  for (const [id, field] of [['exposure', 'exposure'], ['key', 'key'], ['gamma', 'gamma']]) {
    const input = $(id);
    input.value = String(tone[field]);
    $(`${id}-value`).textContent = Number(tone[field]).toFixed(2);
    input.addEventListener('input', () => {
      tone[field] = Number(input.value);
      $(`${id}-value`).textContent = tone[field].toFixed(2);
      toneDirty = true;
    });
  }
  $('copy-link').addEventListener('click', async () => {
    const url = link();
    history.replaceState(null, '', url);
    try {
      await navigator.clipboard.writeText(url);
      $('copy-link').textContent = 'copied';
    } catch (e) {
      $('copy-link').textContent = 'in the address bar';
    }
    setTimeout(() => { $('copy-link').textContent = 'copy link to this view'; }, 1500);
  });
  if (!scene.response) {
    for (const id of ['key', 'gamma']) $(id).disabled = true;
  }
}

async function streamPhotos(scene) {
  let next = 0;
  let done = 0;
  const worker = async () => {
    while (next < scene.photos.length) {
      const i = next++;
      const bitmap = await loadPhoto(kBase, scene, i);
      renderer.addPhoto(i, bitmap);
      bitmap.close();
      done += 1;
      $('progress').value = done / scene.photos.length;
      dirty = true;
    }
  };
  await Promise.all(Array.from({ length: kParallelFetches }, worker));
  $('loading').hidden = true;
}

async function main() {
  const params = new URLSearchParams(window.location.search);
  if (params.get('panel') === '0') $('panel').hidden = true;
  const scene = await loadScene(kBase);
  window.hdribrScene = scene;
  const points = await loadPoints(kBase, scene);
  const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true, alpha: false });
  if (!gl) throw new Error('this browser has no WebGL2');
  renderer = new Renderer(gl, scene, points);
  hook.renderer = renderer;
  bindPanel(scene);
  bindInput(scene);
  goToPhoto(scene, 0);
  if (params.has('camera')) {
    const c = parseCamera(scene, params.get('camera'));
    if (c.photo !== undefined) goToPhoto(scene, c.photo);
    else { setPose(c.qvec, c.tvec, c.cam); nav.photo = -1; }
  }
  for (const f of ['exposure', 'key', 'gamma']) {
    if (!params.has(f)) continue;
    const v = Number(params.get(f));
    if (!Number.isFinite(v)) throw new Error(`${f}=${params.get(f)}: not a number`);
    tone[f] = v;
    $(f).value = String(v);
    $(`${f}-value`).textContent = v.toFixed(2);
  }
  requestAnimationFrame(frame);
  await streamPhotos(scene);
  hook.loadedMs = performance.now() - t0;
  hook.ready = true;
}

// Test hook: renders the current view at the reference camera's own size and intrinsics (as
// `hdribr render --camera` does) and returns the tone-mapped RGBA8 pixels, rows top first.
// opts.width, opts.height: another output size, the camera scaled to it (render --size).
hook.renderExact = (opts = {}) => {
  const c = nav.refCam;
  const view = viewAt(c.width, c.height, true);
  if (opts.width && opts.height) {
    const sx = opts.width / c.width, sy = opts.height / c.height;
    view.cam = { fx: c.fx * sx, fy: c.fy * sy, cx: c.cx * sx, cy: c.cy * sy };
    view.w = opts.width;
    view.h = opts.height;
  }
  if (opts.outlierScale !== undefined) view.outlierScale = opts.outlierScale;
  renderer.render(view);
  renderer.display({ ...tone, ...(opts.tone || {}) }, false);
  const out = renderer.readDisplay();
  dirty = true;
  return { width: out.width, height: out.height, logAverage: renderer.logAverage(),
    data: btoa(chunks(out.data)) };
};
function chunks(a) {
  let s = '';
  for (let i = 0; i < a.length; i += 0x8000) s += String.fromCharCode.apply(null, a.subarray(i, i + 0x8000));
  return s;
}
hook.link = () => link();
hook.tone = tone;
// Soak: n frames of an orbit drawn to the canvas, each finished (readPixels of one pixel);
// returns the frame times (ms), WebGL errors and the JS heap before and after.
hook.soak = (n) => {
  hook.busy = true;
  const gl = renderer.gl;
  const heap = () => (performance.memory ? performance.memory.usedJSHeapSize : 0);
  const heapBefore = heap();
  const times = [];
  let errors = 0;
  const px = new Uint8Array(4);
  for (let i = 0; i < n; ++i) {
    const s = performance.now();
    orbitBy((2 * Math.PI) / n, 0);
    tone.exposure = Math.sin(i / 10);
    renderer.render(viewAt(canvas.width, canvas.height, false));
    renderer.display(tone, true, canvas.width, canvas.height);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    if (gl.getError() !== gl.NO_ERROR) errors += 1;
    times.push(performance.now() - s);
  }
  hook.busy = false;
  dirty = true;
  return { times, errors, heapBefore, heapAfter: heap() };
};

main().catch(showError);
