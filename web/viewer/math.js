// The few transforms the viewer needs, in COLMAP's conventions: quaternions (w, x, y, z),
// cam_from_world = [R | t], camera x right, y down, z forward. Matrices are row-major arrays.

// 3x3 rotation (row-major) of a unit quaternion (w, x, y, z).
export function rotationOf(q) {
  const [w, x, y, z] = q;
  return [
    1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
    2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
    2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
  ];
}

// Unit quaternion (w, x, y, z) of a row-major 3x3 rotation (Shepperd's method).
export function quaternionOf(r) {
  const tr = r[0] + r[4] + r[8];
  let q;
  if (tr > 0) {
    const s = 2 * Math.sqrt(tr + 1);
    q = [0.25 * s, (r[7] - r[5]) / s, (r[2] - r[6]) / s, (r[3] - r[1]) / s];
  } else if (r[0] > r[4] && r[0] > r[8]) {
    const s = 2 * Math.sqrt(1 + r[0] - r[4] - r[8]);
    q = [(r[7] - r[5]) / s, 0.25 * s, (r[1] + r[3]) / s, (r[2] + r[6]) / s];
  } else if (r[4] > r[8]) {
    const s = 2 * Math.sqrt(1 + r[4] - r[0] - r[8]);
    q = [(r[2] - r[6]) / s, (r[1] + r[3]) / s, 0.25 * s, (r[5] + r[7]) / s];
  } else {
    const s = 2 * Math.sqrt(1 + r[8] - r[0] - r[4]);
    q = [(r[3] - r[1]) / s, (r[2] + r[6]) / s, (r[5] + r[7]) / s, 0.25 * s];
  }
  const n = Math.hypot(...q) * (q[0] < 0 ? -1 : 1);
  return q.map((v) => v / n);
}

// cam_from_world as a row-major 4x4.
export function camFromWorld4(qvec, tvec) {
  const r = rotationOf(qvec);
  return [r[0], r[1], r[2], tvec[0], r[3], r[4], r[5], tvec[1], r[6], r[7], r[8], tvec[2], 0, 0, 0, 1];
}

// world_from_cam: rotation R^T, centre C = -R^T t, and its row-major 4x4.
export function worldFromCam(qvec, tvec) {
  const r = rotationOf(qvec);
  const rt = [r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]];
  const center = [0, 1, 2].map((i) => -(rt[i * 3] * tvec[0] + rt[i * 3 + 1] * tvec[1] + rt[i * 3 + 2] * tvec[2]));
  const matrix = [rt[0], rt[1], rt[2], center[0], rt[3], rt[4], rt[5], center[1], rt[6], rt[7], rt[8], center[2], 0, 0, 0, 1];
  return { rotation: rt, center, matrix };
}

// Column-major copy of a row-major 4x4 (WebGL's uniform layout).
export function transpose4(m) {
  const out = new Float32Array(16);
  for (let r = 0; r < 4; ++r) for (let c = 0; c < 4; ++c) out[c * 4 + r] = m[r * 4 + c];
  return out;
}

// Rotation (row-major 3x3) by angle (radians) about a unit axis (Rodrigues).
export function axisAngle(axis, angle) {
  const [x, y, z] = axis;
  const c = Math.cos(angle), s = Math.sin(angle), t = 1 - c;
  return [
    t * x * x + c, t * x * y - s * z, t * x * z + s * y,
    t * x * y + s * z, t * y * y + c, t * y * z - s * x,
    t * x * z - s * y, t * y * z + s * x, t * z * z + c,
  ];
}

export function mul3(a, b) {
  const o = new Array(9).fill(0);
  for (let i = 0; i < 3; ++i) for (let j = 0; j < 3; ++j) for (let k = 0; k < 3; ++k) o[i * 3 + j] += a[i * 3 + k] * b[k * 3 + j];
  return o;
}

export function apply3(m, v) {
  return [0, 1, 2].map((i) => m[i * 3] * v[0] + m[i * 3 + 1] * v[1] + m[i * 3 + 2] * v[2]);
}
