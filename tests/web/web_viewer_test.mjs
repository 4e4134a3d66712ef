// The web viewer in headless Chromium (Debian's package, driven through the DevTools protocol
// by puppeteer-core; no browser download): export a small synthetic capture, open it from a
// local server, read the canvas back at a photo's viewpoint and an exposure, and compare it with
// `hdribr render` of the same camera and exposure; broken bundles must show an error naming
// the file. Modes:
//   node web_viewer_test.mjs --hdribr BIN --work DIR [--capture WS] [--perf]   the test
//   node web_viewer_test.mjs --open BUNDLE                                   open one bundle:
//        prints its error and exits 1 when the page shows one, 0 when it loads
// Exit 77 (CTest's skip) only when /usr/bin/chromium is absent.
import { execFileSync, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const kChromium = '/usr/bin/chromium';
const kPsnrTarget = 35;  // dB, on the pixels both cover
const here = path.dirname(fileURLToPath(import.meta.url));
const webDir = path.resolve(here, '../../web');

function arg(name, fallback = undefined) {
  const i = process.argv.indexOf(name);
  return i >= 0 ? process.argv[i + 1] : fallback;
}

if (!fs.existsSync(kChromium)) {
  console.log(`SKIP: ${kChromium} is absent (bash .ci/setup installs the chromium package)`);
  process.exit(77);
}
const require = createRequire(path.join(webDir, 'package.json'));
let puppeteer, PNG;
try {
  puppeteer = require('puppeteer-core');
  ({ PNG } = require('pngjs'));
} catch (e) {
  console.error(`error: ${webDir}/node_modules: the test's npm packages are missing (npm ci --prefix web)`);
  process.exit(1);
}

// A static file server for one folder, on a free port.
function serve(root) {
  const types = { '.html': 'text/html', '.js': 'text/javascript', '.json': 'application/json',
    '.jpg': 'image/jpeg', '.bin': 'application/octet-stream' };
  const server = http.createServer((req, res) => {
    const rel = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    const file = path.join(root, rel.endsWith('/') ? `${rel}index.html` : rel);
    if (!file.startsWith(root) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      res.writeHead(404);
      res.end();
      return;
    }
    res.writeHead(200, { 'Content-Type': types[path.extname(file)] || 'application/octet-stream' });
    fs.createReadStream(file).pipe(res);
  });
  return new Promise((resolve) => server.listen(0, '127.0.0.1', () => resolve(server)));
}

async function launch() {
  return puppeteer.launch({
    executablePath: kChromium,
    headless: true,
    protocolTimeout: 900000,  // a soak on SwiftShader takes minutes
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--ignore-gpu-blocklist', '--enable-precise-memory-info'],
  });
}

// Opens the bundle at `root` with the URL's query; waits until it has loaded every photo or
// shows an error. Returns the page, its server and the error (null when none).
async function open(browser, root, query, width = 512, height = 384) {
  const server = await serve(path.resolve(root));
  const page = await browser.newPage();
  await page.setViewport({ width, height });
  const logs = [];
  page.on('console', (m) => logs.push(m.text()));
  page.on('pageerror', (e) => logs.push(String(e)));
  const url = `http://127.0.0.1:${server.address().port}/index.html${query}`;
  const opened = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.hdribr && (window.hdribr.ready || window.hdribr.error),
    { timeout: 120000, polling: 50 });
  const state = await page.evaluate(() => ({
    error: window.hdribr.error,
    shown: !document.getElementById('error').hidden ? document.getElementById('error').textContent : null,
    firstPictureMs: window.hdribr.firstPictureMs,
    loadedMs: window.hdribr.loadedMs,
  }));
  return { page, server, url, logs, openedMs: Date.now() - opened, ...state };
}

function readPng(file) {
  return PNG.sync.read(fs.readFileSync(file));
}

// PSNR (8-bit RGB) over the pixels where both images have a colour (alpha > 0), and the share
// of the native image's coloured pixels that the browser's covers too.
function compare(a, b) {
  let se = 0, n = 0, nativeCovered = 0;
  for (let i = 0; i < a.width * a.height; ++i) {
    if (b.data[i * 4 + 3] > 0) nativeCovered += 1;
    if (!(a.data[i * 4 + 3] > 0 && b.data[i * 4 + 3] > 0)) continue;
    for (let c = 0; c < 3; ++c) {
      const d = a.data[i * 4 + c] - b.data[i * 4 + c];
      se += d * d;
    }
    n += 1;
  }
  const mse = se / Math.max(1, 3 * n);
  return { psnr: mse > 0 ? 10 * Math.log10((255 * 255) / mse) : Infinity, pixels: n,
    coverage: n / Math.max(1, nativeCovered) };
}

function writePng(file, w, h, rgba) {
  const png = new PNG({ width: w, height: h });
  png.data = Buffer.from(rgba);
  fs.writeFileSync(file, PNG.sync.write(png));
}

let failures = 0;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures += 1;
}

async function openOne(bundle) {
  const browser = await launch();
  try {
    const r = await open(browser, bundle, '?panel=0');
    r.server.close();
    if (r.error) {
      console.log(`page shows: ${r.shown}`);
      return 1;
    }
    console.log('loaded');
    return 0;
  } finally {
    await browser.close();
  }
}

function run(bin, args) {
  const t = Date.now();
  execFileSync(bin, args, { stdio: ['ignore', 'ignore', 'inherit'] });
  return (Date.now() - t) / 1000;
}

async function main() {
  if (arg('--open')) process.exit(await openOne(arg('--open')));
  const bin = path.resolve(arg('--hdribr', 'build/hdribr'));
  const work = path.resolve(arg('--work', 'build/web_test'));
  let ws = arg('--capture');
  const camera = arg('--camera', 's1_v02.jpg');
  const exposure = Number(arg('--exposure', '0.5'));
  // Larger captures (docs/usage/web.md): the photos' size in the bundle and in `render`, and
  // the output size.
  const maxPhoto = arg('--max-photo-size');
  const size = arg('--size');
  // direct (radiance through the calibrated response) or ldr (an uncalibrated workspace).
  const hdrMode = arg('--hdr-mode', 'direct');
  const [vw, vh] = arg('--viewport', '512x384').split('x').map(Number);  // the page's window
  fs.mkdirSync(work, { recursive: true });
  // The capture: the default synthetic scene, 2 series x 6 views at 256 x 192, calibrated.
  if (!ws) {
    ws = path.join(work, 'capture', 'workspace');
    if (!fs.existsSync(path.join(ws, 'calib', 'exposures.json'))) {
      fs.rmSync(path.join(work, 'capture'), { recursive: true, force: true });
      const s = run(bin, ['synth', path.join(work, 'capture'), '--series', '2', '--views', '6',
        '--size', '256x192', '--novel', '0', '--threads', '2']);
      const c = run(bin, ['calibrate', ws, '--no-depth-cache']);
      console.log(`capture: synth ${s.toFixed(1)} s, calibrate ${c.toFixed(1)} s`);
    }
  }
  const bundle = path.join(work, 'bundle');
  fs.rmSync(bundle, { recursive: true, force: true });
  const e = run(bin, ['export-web', ws, bundle, ...(maxPhoto ? ['--max-photo-size', maxPhoto] : [])]);
  console.log(`export-web ${e.toFixed(1)} s`);
  // Two views: a photo's viewpoint (by name) and a pose halfway between it and the next photo
  // (as render --camera takes it); each compared with the native picture with the refinements
  // the web viewer does not implement switched off (cubic sampling, the photo-consistent
  // depth, the fill, the lechelek depth mode's classification and pull-push, the candidate
  // limit), and with the plain default.
  const scene = JSON.parse(fs.readFileSync(path.join(bundle, 'capture/scene.json'), 'utf8'));
  const i0 = scene.photos.findIndex((p) => p.name === camera);
  if (i0 < 0) throw new Error(`--camera ${camera}: no such photo`);
  const p0 = scene.photos[i0], p1 = scene.photos[(i0 + 1) % scene.photos.length];
  const sign = p0.qvec.reduce((s, v, k) => s + v * p1.qvec[k], 0) < 0 ? -1 : 1;
  const q = p0.qvec.map((v, k) => v + sign * p1.qvec[k]);
  const qn = Math.hypot(...q);
  const pose = [...q.map((v) => v / qn), ...p0.tvec.map((v, k) => (v + p1.tvec[k]) / 2)]
    .map((v) => v.toFixed(9)).join(' ') + ` ${p0.camera_id}`;
  const views = [['photo', camera], ['novel', pose]];
  const matched = ['--depth-mode', 'plain', '--sampling', 'linear', '--refine-depth', '0',
    '--no-fill', '--candidates', '0'];
  for (const [kind, spec] of views) {
    const common = ['render', ws, '--camera', spec, '--hdr-mode', hdrMode,
      ...(hdrMode === 'ldr' ? [] : ['--exposure', String(exposure)]), '--no-depth-cache', ...(size ? ['--size', size] : []),
      ...(maxPhoto ? ['--max-photo-size', maxPhoto] : [])];
    run(bin, [...common, ...matched, '--out', path.join(work, `native_${kind}_matched.png`)]);
    run(bin, [...common, '--out', path.join(work, `native_${kind}_default.png`)]);
  }

  const browser = await launch();
  try {
    const version = await browser.version();
    console.log(`browser: ${version}`);
    for (const [kind, spec] of views) {
      const r = await open(browser, bundle, `?camera=${encodeURIComponent(spec)}&exposure=${exposure}&panel=0`, vw, vh);
      check(!r.error, `${kind}: the bundle loads${r.error ? `: ${r.error}` : ''}`);
      if (r.error) continue;
      console.log(`${kind}: first picture ${r.firstPictureMs?.toFixed(0)} ms, all photos ` +
        `${r.loadedMs?.toFixed(0)} ms after the page opened`);
      const [ow, oh] = size ? size.split('x').map(Number) : [0, 0];
      const out = await r.page.evaluate((width, height) => window.hdribr.renderExact({ width, height }), ow, oh);
      const web = { width: out.width, height: out.height, data: Buffer.from(out.data, 'base64') };
      writePng(path.join(work, `web_${kind}.png`), web.width, web.height, web.data);
      for (const variant of ['matched', 'default']) {
        const native = readPng(path.join(work, `native_${kind}_${variant}.png`));
        check(native.width === web.width && native.height === web.height, `${kind} ${variant}: same size`);
        const m = compare(web, native);
        console.log(`${kind} ${variant}: PSNR ${m.psnr.toFixed(2)} dB over ${m.pixels} pixels ` +
          `(${(100 * m.coverage).toFixed(1)} % of the native picture's)`);
        if (variant === 'matched') {
          check(m.psnr >= kPsnrTarget, `${kind} matched options: PSNR >= ${kPsnrTarget} dB`);
          check(m.coverage >= 0.95, `${kind}: the browser covers >= 95 % of the native picture`);
        }
      }
      const link = await r.page.evaluate(() => window.hdribr.link());
      const back = new URL(link).searchParams;
      const same = kind === 'photo' ? back.get('camera') === spec
        : back.get('camera').split(' ').every((v, k) => Math.abs(Number(v) - Number(spec.split(' ')[k])) < 1e-6);
      check(same && Number(back.get('exposure')) === exposure,
        `${kind}: the view's link holds the camera and exposure`);
      if (process.argv.includes('--perf') && kind === 'photo') {
        const soak = await r.page.evaluate(() => window.hdribr.soak(200));
        const t = [...soak.times].sort((a, b) => a - b);
        console.log(`soak: 200 frames at ${await r.page.evaluate(() => `${window.innerWidth}x${window.innerHeight}`)}, ` +
          `median ${t[100].toFixed(1)} ms, p95 ${t[190].toFixed(1)} ms, WebGL errors ${soak.errors}, ` +
          `JS heap ${(soak.heapBefore / 1e6).toFixed(1)} -> ${(soak.heapAfter / 1e6).toFixed(1)} MB`);
        check(soak.errors === 0, 'soak: no WebGL error');
      }
      if (process.argv.includes('--screenshot') && kind === 'photo') {
        // With the panel, once the full-size frame of the loaded capture is drawn.
        const shot = await open(browser, bundle, `?camera=${encodeURIComponent(spec)}&exposure=${exposure}`, 800, 500);
        await shot.page.waitForFunction(() => window.hdribr.fullFrame, { timeout: 600000 });
        await shot.page.screenshot({ path: path.join(work, 'screenshot.png') });
        await shot.page.close();
        shot.server.close();
      }
      await r.page.close();
      r.server.close();
    }
  } finally {
    await browser.close();
  }

  // Broken bundles: each must show one message naming the file, and --open must exit 1.
  const broken = [
    ['missing photo', 'capture/photos/1.jpg', (d) => fs.rmSync(path.join(d, 'capture/photos/1.jpg'))],
    ['truncated points', 'capture/points.bin', (d) => {
      const f = path.join(d, 'capture/points.bin');
      fs.truncateSync(f, Math.floor(fs.statSync(f).size / 2));
    }],
    ['newer version', 'capture/scene.json', (d) => {
      const f = path.join(d, 'capture/scene.json');
      const j = JSON.parse(fs.readFileSync(f, 'utf8'));
      j.version += 1;
      fs.writeFileSync(f, JSON.stringify(j));
    }],
  ];
  for (const [what, file, breakIt] of broken) {
    const d = path.join(work, `broken_${what.replace(/ /g, '_')}`);
    fs.rmSync(d, { recursive: true, force: true });
    fs.cpSync(bundle, d, { recursive: true });
    breakIt(d);
    const p = spawnSync(process.execPath, [fileURLToPath(import.meta.url), '--open', d], { encoding: 'utf8' });
    const shown = (p.stdout.match(/page shows: (.*)/) || [])[1] || '';
    check(p.status === 1 && shown.includes(file), `${what}: exit ${p.status}, page shows "${shown}"`);
  }
  if (failures) {
    console.log(`${failures} check(s) failed`);
    process.exit(1);
  }
  console.log('all checks passed');
}

main().catch((e) => {
  console.error(`error: ${e.stack || e}`);
  process.exit(1);
});
