// Reading the bundle that `hdribr export-web` writes (capture/scene.json, points.bin, photos/):
// every failure is an Error whose message names the file and the problem.

// The newest capture/scene.json version this viewer reads (io/web_bundle.h, kWebBundleVersion).
export const kBundleVersion = 1;

async function fetchOk(url) {
  let response;
  try {
    response = await fetch(url);
  } catch (e) {
    throw new Error(`${url}: cannot be read (${e.message})`);
  }
  if (!response.ok) throw new Error(`${url}: missing (HTTP ${response.status})`);
  return response;
}

export async function loadScene(base) {
  const url = `${base}/scene.json`;
  const text = await (await fetchOk(url)).text();
  let scene;
  try {
    scene = JSON.parse(text);
  } catch (e) {
    throw new Error(`${url}: not JSON (${e.message})`);
  }
  if (scene.format !== 'hdribr-web') throw new Error(`${url}: not an hdribr web bundle`);
  if (!(scene.version <= kBundleVersion)) {
    throw new Error(`${url}: format version ${scene.version} is newer than this viewer's ` +
      `(${kBundleVersion}): export the capture again with this hdribr, or use a newer viewer`);
  }
  if (!Array.isArray(scene.photos) || scene.photos.length === 0) throw new Error(`${url}: no photos`);
  return scene;
}

// The points as the GPU takes them: kWebPointBytes (10) per point, x y z uint16, normal 2 int8,
// radius uint16, little-endian; points.bin holds them in Morton order, positions as differences
// from the previous point, by byte planes, deflated (io/web_bundle.cc, EncodePoints).
export async function loadPoints(base, scene) {
  const url = `${base}/${scene.points.file}`;
  const compressed = await (await fetchOk(url)).arrayBuffer();
  const n = scene.points.count;
  const expected = n * scene.points.bytes_per_point;
  if (scene.points.bytes_per_point !== 10) throw new Error(`${url}: unknown point layout`);
  let planes;
  try {
    const stream = new Blob([compressed]).stream().pipeThrough(new DecompressionStream('deflate'));
    planes = new Uint8Array(await new Response(stream).arrayBuffer());
  } catch (e) {
    planes = null;
  }
  if (!planes || planes.byteLength !== expected) {
    throw new Error(`${url}: truncated or corrupt (${compressed.byteLength} bytes` +
      `${planes ? ` inflate to ${planes.byteLength}` : ' do not inflate'}; ${n} points need ${expected})`);
  }
  const out = new Uint8Array(expected);
  const o16 = new Uint16Array(out.buffer);
  const prev = [0, 0, 0];
  for (let k = 0; k < n; ++k) {
    for (let f = 0; f < 5; ++f) {
      let v = planes[2 * f * n + k] | (planes[(2 * f + 1) * n + k] << 8);
      if (f < 3) {
        v = (v + prev[f]) & 0xffff;
        prev[f] = v;
      }
      o16[k * 5 + f] = v;
    }
  }
  return out;
}

// Photo i as an ImageBitmap of its stored pixels (no colour management, no EXIF rotation:
// the pixels COLMAP calibrated).
export async function loadPhoto(base, scene, i) {
  const p = scene.photos[i];
  const url = `${base}/${p.file}`;
  const blob = await (await fetchOk(url).catch((e) => {
    throw new Error(`${e.message} (photo ${p.name})`);
  })).blob();
  let bitmap;
  try {
    bitmap = await createImageBitmap(blob, {
      colorSpaceConversion: 'none', premultiplyAlpha: 'none', imageOrientation: 'from-image',
    });
  } catch (e) {
    throw new Error(`${url}: not a readable JPEG (photo ${p.name})`);
  }
  if (bitmap.width !== p.image_size[0] || bitmap.height !== p.image_size[1]) {
    throw new Error(`${url}: ${bitmap.width}x${bitmap.height}, scene.json says ` +
      `${p.image_size[0]}x${p.image_size[1]} (photo ${p.name})`);
  }
  return bitmap;
}
