// The WebGL2 renderer: the points, the photos (a mipmapped 2D array), every photo's depth map
// (the splat pass from its viewpoint, once, as each photo arrives), and per frame: the view's
// splat depth -> blend -> log-average -> Reinhard (docs/usage/web.md).
import * as S from './shaders.js';
import { transpose4, worldFromCam, camFromWorld4 } from './math.js';

// Defaults of the native renderer's options (render/blend_options.h, BlendOptions; the
// tone mapping of render/tonemap_pass.h): the web viewer has no option of its own.
export const kBlend = { lambda: 1e-4, tolerance: 0.01, outlierScale: 0.08 };
export const kTone = { key: 0.18, gamma: 2.2, epsilon: 1e-6 };
const kDataTexels = 8;  // per photo in the photo-data texture
const kReduceBlock = 16;

function compile(gl, vs, fs, name) {
  const program = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) {
      throw new Error(`shader ${name}: ${gl.getShaderInfoLog(s)}`);
    }
    gl.attachShader(program, s);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
    throw new Error(`program ${name}: ${gl.getProgramInfoLog(program)}`);
  }
  const uniforms = {};
  const n = gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < n; ++i) {
    const info = gl.getActiveUniform(program, i);
    uniforms[info.name.replace(/\[0\]$/, '')] = gl.getUniformLocation(program, info.name);
  }
  return { program, u: uniforms };
}

function texture2d(gl, internal, w, h, filter = gl.NEAREST) {
  const t = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, t);
  gl.texStorage2D(gl.TEXTURE_2D, 1, internal, w, h);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, filter);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  return t;
}

function checkFramebuffer(gl, what) {
  const status = gl.checkFramebufferStatus(gl.FRAMEBUFFER);
  if (status !== gl.FRAMEBUFFER_COMPLETE) throw new Error(`${what}: framebuffer incomplete (${status})`);
}

export class Renderer {
  // gl: a WebGL2 context; scene: the parsed scene.json; points: the points.bin bytes.
  constructor(gl, scene, pointBytes) {
    this.gl = gl;
    this.scene = scene;
    if (!gl.getExtension('EXT_color_buffer_float')) {
      throw new Error('this browser cannot render to float textures (EXT_color_buffer_float)');
    }
    this.splat = compile(gl, S.SPLAT_VS, S.SPLAT_FS, 'splat');
    const maxPhotos = Math.floor(gl.getParameter(gl.MAX_UNIFORM_BLOCK_SIZE) / (kDataTexels * 16));
    if (scene.photos.length > maxPhotos) {
      throw new Error(`capture/scene.json: ${scene.photos.length} photos, this browser's WebGL2 takes ${maxPhotos}`);
    }
    this.blend = compile(gl, S.FULLSCREEN_VS, S.BLEND_FS(scene.photos.length), 'blend');
    gl.uniformBlockBinding(this.blend.program, gl.getUniformBlockIndex(this.blend.program, 'PhotoData'), 0);
    this.reduce = compile(gl, S.FULLSCREEN_VS, S.REDUCE_FS, 'reduce');
    this.tonemap = compile(gl, S.FULLSCREEN_VS, S.TONEMAP_FS, 'tonemap');
    this.maxPointSize = gl.getParameter(gl.ALIASED_POINT_SIZE_RANGE)[1];
    this.emptyVao = gl.createVertexArray();
    this.setPoints(pointBytes);
    this.setPhotos();
    this.setResponse();
    this.background = this.backgroundSphere();
    this.targets = new Map();  // by "WxH"
  }

  setPoints(bytes) {
    const gl = this.gl;
    const pts = this.scene.points;
    this.pointCount = pts.count;
    this.vao = gl.createVertexArray();
    gl.bindVertexArray(this.vao);
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.bufferData(gl.ARRAY_BUFFER, bytes, gl.STATIC_DRAW);
    const stride = pts.bytes_per_point;
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.UNSIGNED_SHORT, true, stride, 0);
    gl.enableVertexAttribArray(1);
    gl.vertexAttribPointer(1, 2, gl.BYTE, true, stride, 6);
    gl.enableVertexAttribArray(2);
    gl.vertexAttribPointer(2, 1, gl.UNSIGNED_SHORT, true, stride, 8);
    gl.bindVertexArray(null);
    this.lo = pts.min;
    this.extent = pts.max.map((v, i) => Math.max(v - pts.min[i], 1e-12));
    // Decoded positions, for the background sphere and the near/far planes.
    const u16 = new Uint16Array(bytes.buffer, bytes.byteOffset, bytes.byteLength / 2);
    this.positionOf = (i) => [0, 1, 2].map((a) => this.lo[a] + (u16[i * 5 + a] / 65535) * this.extent[a]);
  }

  // The native renderer's BackgroundSphere (render/blend_pass.cc): centred on the centroid,
  // radius the larger of the 99th-percentile point distance and 1.25x the farthest camera's.
  backgroundSphere() {
    const c = this.scene.centroid;
    const d = new Float64Array(this.pointCount);
    for (let i = 0; i < this.pointCount; ++i) {
      const p = this.positionOf(i);
      d[i] = Math.hypot(p[0] - c[0], p[1] - c[1], p[2] - c[2]);
    }
    d.sort();
    let radius = d.length ? d[Math.floor(((d.length - 1) * 99) / 100)] : 0;
    for (const ph of this.photos) {
      radius = Math.max(radius, 1.25 * Math.hypot(ph.center[0] - c[0], ph.center[1] - c[1], ph.center[2] - c[2]));
    }
    if (!(radius > 0)) radius = this.scene.scene_scale;
    return [c[0], c[1], c[2], radius];
  }

  setPhotos() {
    const gl = this.gl;
    const photos = this.scene.photos;
    this.photos = photos.map((p) => {
      const cam = this.scene.cameras[String(p.camera_id)];
      const w = worldFromCam(p.qvec, p.tvec);
      return { ...p, cam, center: w.center, loaded: false };
    });
    this.arrayW = Math.max(...photos.map((p) => p.image_size[0]));
    this.arrayH = Math.max(...photos.map((p) => p.image_size[1]));
    const levels = Math.floor(Math.log2(Math.max(this.arrayW, this.arrayH))) + 1;
    this.photoArray = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.photoArray);
    gl.texStorage3D(gl.TEXTURE_2D_ARRAY, levels, gl.RGBA8, this.arrayW, this.arrayH, photos.length);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    this.depthW = Math.max(...this.photos.map((p) => p.cam.width));
    this.depthH = Math.max(...this.photos.map((p) => p.cam.height));
    this.photoDepth = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.photoDepth);
    gl.texStorage3D(gl.TEXTURE_2D_ARRAY, 1, gl.R32F, this.depthW, this.depthH, photos.length);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D_ARRAY, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    this.depthRb = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, this.depthRb);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, this.depthW, this.depthH);
    this.depthFb = gl.createFramebuffer();
    this.dataUbo = gl.createBuffer();
    this.mipsStale = false;
    this.uploadPhotoData();
  }

  // Per photo (blend.comp's PhotoGpu): cam_from_world rows, intrinsics, centre and
  // 1 / exposure, size (camera w, h, texels per camera pixel, loaded), texture coordinate scale
  // and clamp, depth-map scale and size.
  uploadPhotoData() {
    const gl = this.gl;
    const data = new Float32Array(this.photos.length * kDataTexels * 4);
    this.photos.forEach((p, i) => {
      const m = camFromWorld4(p.qvec, p.tvec);  // row-major 4x4
      const o = i * kDataTexels * 4;
      data.set(m.slice(0, 12), o);
      data.set([p.cam.fx, p.cam.fy, p.cam.cx, p.cam.cy], o + 12);
      data.set([...p.center, 1 / p.exposure], o + 16);
      const [iw, ih] = p.image_size;
      data.set([p.cam.width, p.cam.height, iw / p.cam.width, p.loaded ? 1 : 0], o + 20);
      data.set([iw / p.cam.width / this.arrayW, ih / p.cam.height / this.arrayH,
        (iw - 0.5) / this.arrayW, (ih - 0.5) / this.arrayH], o + 24);
      data.set([1, 1, p.cam.width, p.cam.height], o + 28);
    });
    gl.bindBuffer(gl.UNIFORM_BUFFER, this.dataUbo);
    gl.bufferData(gl.UNIFORM_BUFFER, data, gl.DYNAMIC_DRAW);
    gl.bindBuffer(gl.UNIFORM_BUFFER, null);
  }

  setResponse() {
    const gl = this.gl;
    const r = this.scene.response;
    this.radiance = !!r;
    const lut = new Float32Array(256 * 4);
    if (r) {
      for (let i = 0; i < 256; ++i) {
        lut.set([r.log_inverse.R[i], r.log_inverse.G[i], r.log_inverse.B[i], 0], i * 4);
      }
    }
    this.responseTex = texture2d(gl, gl.RGBA32F, 256, 1);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, 256, 1, gl.RGBA, gl.FLOAT, lut);
  }

  // Photo i's pixels (an ImageBitmap) into its layer, and its depth map from its viewpoint.
  addPhoto(i, bitmap) {
    const gl = this.gl;
    const p = this.photos[i];
    gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.photoArray);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, 0, 0, 0, i, bitmap.width, bitmap.height, 1, gl.RGBA,
      gl.UNSIGNED_BYTE, bitmap);
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.depthFb);
    gl.framebufferTextureLayer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, this.photoDepth, 0, i);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, this.depthRb);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0]);
    checkFramebuffer(gl, 'photo depth map');
    const cam = p.cam;
    gl.viewport(0, 0, cam.width, cam.height);
    gl.enable(gl.SCISSOR_TEST);
    gl.scissor(0, 0, this.depthW, this.depthH);
    gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
    gl.clear(gl.DEPTH_BUFFER_BIT);
    gl.disable(gl.SCISSOR_TEST);
    this.drawSplats(camFromWorld4(p.qvec, p.tvec), cam, cam.width, cam.height);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    p.loaded = true;
    this.mipsStale = true;
    this.uploadPhotoData();
  }

  loadedCount() { return this.photos.filter((p) => p.loaded).length; }

  // The photos by their Unstructured Lumigraph penalty (blend.comp's, angle + weighted
  // distance term) at the point of the view's axis at the centroid's depth, smallest first
  // (ordered = false: index order).
  visitOrder(view) {
    const ids = this.photos.map((_, i) => i);
    if (this.ordered === false) return new Int32Array(ids);
    const w = worldFromCam(view.qvec, view.tvec);
    const c = this.scene.centroid;
    const fwd = [w.rotation[2], w.rotation[5], w.rotation[8]];
    const depth = Math.max(fwd.reduce((s, f, k) => s + f * (c[k] - w.center[k]), 0), 1e-6);
    const P = w.center.map((v, k) => v + depth * fwd[k]);
    const unit = (v) => { const n = Math.hypot(...v); return v.map((x) => x / n); };
    const V = unit(w.center.map((v, k) => v - P[k]));
    const penalty = this.photos.map((p) => {
      const vk = p.center.map((v, k) => v - P[k]);
      const dk = Math.hypot(...vk);
      const cos = Math.min(1, Math.max(-1, unit(vk).reduce((s, x, k) => s + x * V[k], 0)));
      return Math.acos(cos) + (this.scene.blend.delta_weight * Math.abs(depth - dk)) / this.scene.scene_scale;
    });
    ids.sort((a, b) => penalty[a] - penalty[b] || a - b);
    return new Int32Array(ids);
  }

  // Near and far from the points' bounds in the view's camera space (depth_pass.cc).
  nearFar(m) {
    let far = 0;
    for (let c = 0; c < 8; ++c) {
      const x = [0, 1, 2].map((a) => this.lo[a] + ((c >> a) & 1) * this.extent[a]);
      const z = m[8] * x[0] + m[9] * x[1] + m[10] * x[2] + m[11];
      far = Math.max(far, z);
    }
    far = Math.max(far * 1.01, 1e-6);
    return [1e-5 * far, far];
  }

  // Step 1 of the splat pass into the bound framebuffer (depth test on).
  drawSplats(m, cam, w, h) {
    const gl = this.gl;
    const { program, u } = this.splat;
    gl.useProgram(program);
    gl.uniform3fv(u.u_lo, this.lo);
    gl.uniform3fv(u.u_extent, this.extent);
    gl.uniform1f(u.u_max_radius, this.scene.points.max_radius);
    gl.uniform1i(u.u_has_normals, this.scene.points.normals ? 1 : 0);
    gl.uniformMatrix4fv(u.u_cam_from_world, false, transpose4(m));
    gl.uniform4f(u.u_intrinsics, cam.fx, cam.fy, cam.cx, cam.cy);
    gl.uniform2f(u.u_size, w, h);
    gl.uniform2fv(u.u_near_far, this.nearFar(m));
    gl.uniform1f(u.u_max_point_size, this.maxPointSize);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.POINTS, 0, this.pointCount);
    gl.bindVertexArray(null);
    gl.disable(gl.DEPTH_TEST);
  }

  // The render targets of one output size.
  target(w, h) {
    const key = `${w}x${h}`;
    if (this.targets.has(key)) return this.targets.get(key);
    const gl = this.gl;
    const t = {
      w, h,
      depth: texture2d(gl, gl.R32F, w, h),
      normal: texture2d(gl, gl.RGBA16F, w, h),
      color: texture2d(gl, gl.RGBA32F, w, h),
      display: texture2d(gl, gl.RGBA8, w, h),
      rw: Math.ceil(w / kReduceBlock), rh: Math.ceil(h / kReduceBlock),
    };
    t.reduced = texture2d(gl, gl.RG32F, t.rw, t.rh);
    t.sum = texture2d(gl, gl.RG32F, 1, 1);
    t.rb = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, t.rb);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, w, h);
    const fb = (textures, rb) => {
      const f = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, f);
      textures.forEach((tex, k) => gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + k, gl.TEXTURE_2D, tex, 0));
      if (rb) gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, rb);
      checkFramebuffer(gl, 'render target');
      return f;
    };
    t.splatFb = fb([t.depth, t.normal], t.rb);
    t.colorFb = fb([t.color]);
    t.reducedFb = fb([t.reduced]);
    t.sumFb = fb([t.sum]);
    t.displayFb = fb([t.display]);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    // Older sizes (a resized window) are released.
    for (const [k, old] of this.targets) {
      if (k === key) continue;
      for (const tex of [old.depth, old.normal, old.color, old.display, old.reduced, old.sum]) gl.deleteTexture(tex);
      for (const f of [old.splatFb, old.colorFb, old.reducedFb, old.sumFb, old.displayFb]) gl.deleteFramebuffer(f);
      gl.deleteRenderbuffer(old.rb);
      this.targets.delete(k);
    }
    this.targets.set(key, t);
    return t;
  }

  // Renders the view (cam: intrinsics at w x h; qvec, tvec: cam_from_world) into the target's
  // radiance texture, and the log-average of it.
  render(view) {
    const gl = this.gl;
    if (this.mipsStale) {
      gl.bindTexture(gl.TEXTURE_2D_ARRAY, this.photoArray);
      gl.generateMipmap(gl.TEXTURE_2D_ARRAY);
      this.mipsStale = false;
    }
    const { cam, w, h } = view;
    const t = this.target(w, h);
    const m = camFromWorld4(view.qvec, view.tvec);
    // With `profiling`, each pass waits for the GPU (a one-pixel read) and its time is kept.
    const px = new Uint8Array(4);
    let last = performance.now();
    const mark = (name) => {
      if (!this.profiling) return;
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, t.displayFb);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      const now = performance.now();
      this.profile[name] = now - last;
      last = now;
    };
    this.profile = {};
    mark('start');
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.splatFb);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
    gl.viewport(0, 0, w, h);
    gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
    gl.clearBufferfv(gl.COLOR, 1, [0, 0, 0, 0]);
    gl.clear(gl.DEPTH_BUFFER_BIT);
    this.drawSplats(m, cam, w, h);
    mark('splat');

    gl.bindFramebuffer(gl.FRAMEBUFFER, t.colorFb);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0]);
    const { program, u } = this.blend;
    gl.useProgram(program);
    const bind = (unit, target, tex, loc) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(target, tex);
      gl.uniform1i(loc, unit);
    };
    bind(0, gl.TEXTURE_2D, t.depth, u.u_depth);
    bind(1, gl.TEXTURE_2D, t.normal, u.u_normal);
    bind(2, gl.TEXTURE_2D_ARRAY, this.photoArray, u.u_photos);
    bind(3, gl.TEXTURE_2D_ARRAY, this.photoDepth, u.u_photo_depth);
    gl.bindBufferBase(gl.UNIFORM_BUFFER, 0, this.dataUbo);
    bind(5, gl.TEXTURE_2D, this.responseTex, u.u_response);
    gl.uniform1i(u.u_photo_count, this.photos.length);
    gl.uniform1iv(u.u_order, this.visitOrder(view));
    gl.uniformMatrix4fv(u.u_world_from_cam, false, transpose4(worldFromCam(view.qvec, view.tvec).matrix));
    gl.uniform4f(u.u_intrinsics, cam.fx, cam.fy, cam.cx, cam.cy);
    gl.uniform1f(u.u_lambda, kBlend.lambda);
    gl.uniform1f(u.u_tolerance, kBlend.tolerance);
    gl.uniform1f(u.u_inv_scene_scale, 1 / this.scene.scene_scale);
    gl.uniform1f(u.u_delta_weight, this.scene.blend.delta_weight);
    gl.uniform1f(u.u_outlier_scale, view.outlierScale ?? kBlend.outlierScale);
    gl.uniform1i(u.u_radiance, this.radiance ? 1 : 0);
    gl.uniform4fv(u.u_sphere, this.background);
    const pl = this.scene.plane;
    gl.uniform1i(u.u_has_plane, pl ? 1 : 0);
    if (pl) {
      gl.uniform4f(u.u_plane, ...pl.normal, pl.offset);
      gl.uniform3fv(u.u_plane_u, pl.axis_u);
      gl.uniform3fv(u.u_plane_v, pl.axis_v);
      gl.uniform4fv(u.u_plane_extent, pl.extent);
    }
    gl.bindVertexArray(this.emptyVao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    mark('blend');

    // Log-average: 16 x 16 blocks, then the blocks into one texel.
    gl.useProgram(this.reduce.program);
    const r = this.reduce.u;
    gl.uniform1f(r.u_epsilon, kTone.epsilon);
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.reducedFb);
    gl.viewport(0, 0, t.rw, t.rh);
    bind(0, gl.TEXTURE_2D, t.color, r.u_src);
    gl.uniform1i(r.u_first, 1);
    gl.uniform1i(r.u_block, kReduceBlock);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.sumFb);
    gl.viewport(0, 0, 1, 1);
    bind(0, gl.TEXTURE_2D, t.reduced, r.u_src);
    gl.uniform1i(r.u_first, 0);
    gl.uniform1i(r.u_block, 64);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    mark('reduce');
    if (t.rw > 64 || t.rh > 64) throw new Error('view too large for the log-average reduction');
    gl.bindVertexArray(null);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.last = t;
    return t;
  }

  // Tone-maps the last render into the canvas (toCanvas) or into the target's RGBA8 texture.
  // outW x outH: the canvas's size (the render's when absent).
  display(tone, toCanvas, outW, outH) {
    const gl = this.gl;
    const t = this.last;
    if (!t) return;
    const w = outW || t.w, h = outH || t.h;
    gl.bindFramebuffer(gl.FRAMEBUFFER, toCanvas ? null : t.displayFb);
    gl.viewport(0, 0, w, h);
    const { program, u } = this.tonemap;
    gl.useProgram(program);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, t.color);
    gl.uniform1i(u.u_hdr, 0);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, t.sum);
    gl.uniform1i(u.u_sum, 1);
    gl.uniform1f(u.u_key, tone.key);
    gl.uniform1f(u.u_fixed_la, tone.logAverage || 0);
    gl.uniform1f(u.u_exposure, Math.pow(2, tone.exposure));
    gl.uniform1f(u.u_inv_gamma, this.radiance ? 1 / tone.gamma : 1);
    gl.uniform1i(u.u_reinhard, this.radiance ? 1 : 0);
    gl.uniform1i(u.u_flip, toCanvas ? 1 : 0);
    gl.uniform1f(u.u_height, h);
    gl.uniform1f(u.u_scale, t.w / w);
    gl.bindVertexArray(this.emptyVao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(null);
  }

  // The last display image, RGBA8 rows top first (after display(tone, false)); alpha 255 where
  // the pixel has a colour, as the native PNG.
  readDisplay() {
    const gl = this.gl;
    const t = this.last;
    gl.bindFramebuffer(gl.FRAMEBUFFER, t.displayFb);
    const px = new Uint8Array(t.w * t.h * 4);
    gl.readPixels(0, 0, t.w, t.h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return { width: t.w, height: t.h, data: px };
  }

  // The log-average luminance of the last render.
  logAverage() {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.last.sumFb);
    const s = new Float32Array(4);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.FLOAT, s);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return Math.exp(s[0] / Math.max(s[1], 1));
  }
}
