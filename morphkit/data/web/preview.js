// morphkit preview: the page's program (inlined by morphkit.export.page; no network).
//
// Frames and conventions are morphkit's (morphkit/conventions.py): the world is +z up; a camera is
// OpenCV's (x right, y down, z forward), its pixel (u, v) the column and row from the top-left
// pixel's centre; each billboard pixel is drawn by the per-pixel depth morph of
// morphkit.views.depthmorph (march each of the three weighted views' depth along the pixel's ray,
// combine the hits), the sun's light view of each instance by the same morph of its sun atlas
// (morphkit.sunlit.sunatlas), and shading is morphkit.imaging.shading's Lambert model. The page
// computes every ray from its own camera matrices (not three.js's), so that its pixels are the
// rays morphkit's reference render casts (morphkit.export.preview.reference_image).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const DATA = JSON.parse(document.getElementById('morphkit-data').textContent);
const DEG = Math.PI / 180;
const EMPTY_HALF = 65000.0; // depths at or above it are empty texels (stored as 65504)

function say(text) {
  const el = document.getElementById('message');
  el.textContent = text;
  el.style.display = 'block';
}

function bytesOf(b64) {
  const s = atob(b64);
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}

// the page's arrays: zlib-compressed (morphkit.export.preview), inflated by the browser
async function inflate(b64) {
  const stream = new Blob([bytesOf(b64)]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

async function inflateAll(assets) {
  for (const a of assets) {
    for (const k of ['rgba', 'normal', 'depth', 'instances']) a[k] = await inflate(a[k]);
    if (a.sun_atlas) for (const k of ['depth', 'coverage']) a.sun_atlas[k] = await inflate(a.sun_atlas[k]);
  }
}

// ------------------------------------------------------------------ vectors and cameras
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const norm = (a) => { const n = Math.hypot(a[0], a[1], a[2]); return scale(a, 1 / n); };

// morphkit.views.domecameras.direction: from the pivot towards the eye (or the sun)
function direction(azDeg, elDeg) {
  const a = azDeg * DEG, e = elDeg * DEG;
  return [Math.cos(e) * Math.cos(a), Math.cos(e) * Math.sin(a), Math.sin(e)];
}

// morphkit.views.domecameras.quad_axes
function quadAxes(azDeg, elDeg) {
  const a = azDeg * DEG, e = elDeg * DEG;
  const up = [-Math.sin(e) * Math.cos(a), -Math.sin(e) * Math.sin(a), Math.cos(e)];
  const right = [-Math.sin(a), Math.cos(a), 0];
  return [right, up];
}

// morphkit.camera.look_at: OpenCV axes, +y (image down) as close to -up as can be
function lookAt(eye, target) {
  const z = norm(sub(target, eye));
  let up = [0, 0, 1];
  if (Math.abs(dot(z, up)) > 1 - 1e-9) up = [0, 1, 0];
  const x = norm(cross(z, up));
  const y = cross(z, x);
  return { x, y, z, c: eye };
}

// A camera: {R: {x, y, z, c}, fx, fy, cx, cy, w, h, near, far, ortho}; GL matrices as morphkit's
// CameraModel.gl_projection and the OpenCV-to-GL flip of the camera frame.
function glMatrices(cam) {
  const { x, y, z, c } = cam.R;
  // world -> GL camera: rows x, -y, -z
  const view = new THREE.Matrix4().set(
    x[0], x[1], x[2], -dot(x, c),
    -y[0], -y[1], -y[2], dot(y, c),
    -z[0], -z[1], -z[2], dot(z, c),
    0, 0, 0, 1);
  const { w, h, near: n, far: f } = cam;
  const P = new THREE.Matrix4();
  if (!cam.ortho) {
    P.set(2 * cam.fx / w, 0, 1 - 2 * (cam.cx + 0.5) / w, 0,
      0, 2 * cam.fy / h, 2 * (cam.cy + 0.5) / h - 1, 0,
      0, 0, (f + n) / (n - f), 2 * f * n / (n - f),
      0, 0, -1, 0);
  } else {
    P.set(2 * cam.fx / w, 0, 0, 0,
      0, 2 * cam.fy / h, 0, 0,
      0, 0, 2 / (n - f), (f + n) / (n - f),
      0, 0, 0, 1);
  }
  return { view, proj: P, viewProj: new THREE.Matrix4().multiplyMatrices(P, view) };
}

function camR3(cam) { // columns x, y, z: camera -> world rotation
  const { x, y, z } = cam.R;
  return new THREE.Matrix3().set(x[0], y[0], z[0], x[1], y[1], z[1], x[2], y[2], z[2]);
}

// ------------------------------------------------------------------ the dome's weights
// morphkit.views.dome.ViewDome.weights (and its one-ring case)
function domeWeights(dome, azDeg, elDeg) {
  const lo = dome.rings[0][0], hi = dome.top ? 90 : dome.rings[dome.rings.length - 1][0];
  const e = Math.min(Math.max(elDeg, lo), hi);
  if (dome.triangles.length === 0) {
    const k = dome.azimuths.length, step = 360 / k;
    const rel = (((azDeg - dome.azimuths[0]) % 360) + 360) % 360;
    const i = Math.floor(rel / step) % k, j = (i + 1) % k;
    const b = (step / 2) * DEG, t = (rel - i * step - step / 2) * DEG;
    const s = Math.min(Math.max((Math.tan(t) / Math.tan(b) + 1) / 2, 0), 1);
    return [[i, j, j], [1 - s, s, 0]];
  }
  const d = direction(azDeg, e);
  let best = -1, bestMin = -Infinity, bestLam = null;
  for (let t = 0; t < dome.triangles.length; t++) {
    const m = dome.inverse[t];
    const lam = [m[0] * d[0] + m[1] * d[1] + m[2] * d[2], m[3] * d[0] + m[4] * d[1] + m[5] * d[2],
      m[6] * d[0] + m[7] * d[1] + m[8] * d[2]];
    const mn = Math.min(lam[0], lam[1], lam[2]);
    if (mn > bestMin) { bestMin = mn; best = t; bestLam = lam; }
  }
  let w = bestLam.map((v) => Math.max(v, 0));
  let s = w[0] + w[1] + w[2];
  w = w.map((v) => v / s).map((v) => (v < 1e-9 ? 0 : v));
  s = w[0] + w[1] + w[2];
  return [dome.triangles[best].slice(), w.map((v) => v / s)];
}

// morphkit.billboard.impostor.OctahedralImpostor.weights: the grid triangle's frames around a
// direction (the elevation clamped at 0), on the hemi-octahedral map
function impostorWeights(n, azDeg, elDeg) {
  const d = direction(azDeg, Math.min(Math.max(elDeg, 0), 90));
  const s = Math.abs(d[0]) + Math.abs(d[1]) + d[2];
  const p = [d[0] / s, d[1] / s];
  let g = [(p[0] + p[1] + 1) * 0.5 * (n - 1), (p[0] - p[1] + 1) * 0.5 * (n - 1)];
  g = g.map((v) => (Math.abs(v - Math.round(v)) <= 1e-9 ? Math.round(v) : v));
  const c = g.map((v) => Math.min(Math.max(Math.floor(v), 0), n - 2));
  const fx = g[0] - c[0], fy = g[1] - c[1];
  const mid = fx > fy ? [c[0] + 1, c[1]] : [c[0], c[1] + 1];
  const out = new Map();
  for (const [[i, j], w] of [[[c[0], c[1]], Math.min(1 - fx, 1 - fy)], [[c[0] + 1, c[1] + 1], Math.min(fx, fy)],
    [mid, Math.abs(fx - fy)]]) {
    if (w > 0) out.set(j * n + i, (out.get(j * n + i) || 0) + w);
  }
  let total = 0;
  for (const w of out.values()) total += w;
  const k = [...out.keys()], w = [...out.values()].map((v) => v / total);
  while (k.length < 3) { k.push(k[0]); w.push(0); }
  return [k, w];
}

// ------------------------------------------------------------------ shaders
const HEAD = `precision highp float;
precision highp int;
precision highp sampler2DArray;
precision highp sampler2D;
`;

const COMMON = `
#define EMPTY_HALF ${EMPTY_HALF.toFixed(1)}
#define FAR 3.0e38
#define THICKNESS_STEPS ${DATA.constants.thickness_steps.toFixed(4)}
#define DEPTH_AGREE_STEPS ${DATA.constants.depth_agree_steps.toFixed(4)}
#define REFINE_STEPS ${DATA.constants.refine_steps}
#define ALPHA_FLOOR ${DATA.constants.alpha_floor.toExponential(6)}
#define IMP_MIN_COS ${DATA.constants.imp_min_cos.toExponential(6)}
uniform int uN;        // the views' side, pixels
uniform sampler2DArray uDepth;
uniform vec3 uPivot; uniform float uRadius;  // the bounding sphere, object frame
in vec4 vPose; in float vScale; flat in ivec3 vViews; in vec3 vWeights; flat in int vSteps;  // the instance's
bool sphere(vec3 o, vec3 d, vec3 c, float r, out float t0, out float t1) {
  vec3 oc = o - c;
  float b = dot(d, oc);
  float disc = b * b - (dot(oc, oc) - r * r);
  if (disc <= 0.0) return false;
  float sq = sqrt(disc);
  t0 = max(-b - sq, 0.0);
  t1 = -b + sq;
  return true;
}

mat3 yawMat(float yaw) { // Rz(yaw), columns
  float c = cos(yaw), s = sin(yaw);
  return mat3(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0);
}
uniform float uDist;   // the views' camera distance (stored depths are offsets from it)
uniform float uVF;      // the views' focal length (fx = fy), pixels (orthographic: fx)
uniform float uVFy;     // orthographic views: fy
uniform float uVCx;     // principal point (cx = cy), pixels
`;

// The views' depth march (morphkit.views.depthmorph)
const VIEWS = `
uniform bool uOrtho;   // orthographic reference views (a sun atlas)
uniform mat3 uViewR[NVIEWS];  // camera -> object rotation of each view
uniform vec3 uViewC[NVIEWS];  // its centre, object frame

float depthAt(int k, vec2 uv) { // nearest (cv2.INTER_NEAREST: round half to even), FAR outside
  ivec2 p = ivec2(roundEven(uv));
  if (p.x < 0 || p.y < 0 || p.x >= uN || p.y >= uN) return FAR;
  float d = texelFetch(uDepth, ivec3(p, k), 0).r;
  return d >= EMPTY_HALF ? FAR : d + uDist;
}

vec3 project(vec3 A, vec3 B, float t) { // (u, v, z) of the ray's point at t in a view
  vec3 c = A + t * B;
  if (uOrtho) return vec3(uVF * c.x + uVCx, uVFy * c.y + uVCx, c.z);
  float zs = c.z > 0.0 ? c.z : 1.0;
  return vec3(uVF * c.x / zs + uVCx, uVF * c.y / zs + uVCx, c.z);
}

// morphkit.views.depthmorph.march_view for one ray; returns (status, t, u, v): status 0 free,
// 1 hit, 2 occluded
vec4 marchView(int k, vec3 o, vec3 d, float t0, float t1, int steps) {
  mat3 R = uViewR[k];
  vec3 A = transpose(R) * (o - uViewC[k]);
  vec3 B = transpose(R) * d;
  float dt = (t1 - t0) / float(steps - 1);
  float status = 0.0, tHit = FAR;
  float prevF = -FAR, prevT = t0;
  bool prevSaw = false;
  float thick = THICKNESS_STEPS * dt;
  for (int i = 0; i < steps; i++) {
    float t = t0 + float(i) * dt;
    vec3 q = project(A, B, t);
    float dd = depthAt(k, q.xy);
    bool saw = dd < FAR;
    float f = q.z - dd;
    if (saw && f >= 0.0) {
      if (f <= thick) {
        status = 1.0;
        float frac = prevSaw ? -prevF / (f - prevF) : 1.0;
        tHit = prevT + clamp(frac, 0.0, 1.0) * (t - prevT);
      } else {
        status = 2.0;
      }
      break;
    }
    prevF = f; prevSaw = saw; prevT = t;
  }
  if (status == 1.0) {
    float lo = max(tHit - dt, t0), hi = tHit + 0.5 * dt;
    float fLo = 0.0, fHi = 0.0;
    bool hasLo = false, hasHi = false;
    for (int i = 0; i < REFINE_STEPS; i++) {
      float mid = 0.5 * (lo + hi);
      vec3 q = project(A, B, mid);
      float dd = depthAt(k, q.xy);
      bool saw = dd < FAR;
      bool behind = saw && q.z >= dd;
      float f = q.z - dd;
      if (behind) { hi = mid; fHi = f; hasHi = true; }
      else { lo = mid; fLo = f; hasLo = saw; }
    }
    if (hasLo && hasHi) {
      float frac = -fLo / (fHi - fLo);
      tHit = (frac >= 0.0 && frac <= 1.0) ? lo + frac * (hi - lo) : hi;
    } else {
      tHit = hi;
    }
  }
  vec3 q = project(A, B, status == 1.0 ? tHit : t0);
  return vec4(status, tHit, q.xy);
}

// the instance's three weighted views marched along one ray (object frame): each one's
// (status, t, u, v), the nearest hit's t and the march's step; false where the ray misses the sphere
bool marchThree(vec3 o, vec3 d, out vec4 h[3], out float tMin, out float dt) {
  float t0, t1;
  tMin = FAR; dt = 0.0;
  if (!sphere(o, d, uPivot, uRadius, t0, t1)) return false;
  dt = (t1 - t0) / float(vSteps - 1);
  for (int j = 0; j < 3; j++) {
    h[j] = vWeights[j] > 0.0 ? marchView(vViews[j], o, d, t0, t1, vSteps) : vec4(-1.0, FAR, 0.0, 0.0);
    if (h[j].x == 1.0) tMin = min(tMin, h[j].y);
  }
  return true;
}

`;

const INSTANCE_VERT = `
in vec3 position;
in vec4 iPose;      // x, y, z, yaw (radians)
in float iScale;
in vec3 iViews;
in vec3 iWeights;
in float iSteps;
uniform mat4 uViewProj;
uniform vec3 uLo, uHi;   // the box holding every drawn point of the views, object frame
out vec4 vPose;
out float vScale;
flat out ivec3 vViews;
out vec3 vWeights;
flat out int vSteps;
void main() {
  mat3 Rz = mat3(cos(iPose.w), sin(iPose.w), 0.0, -sin(iPose.w), cos(iPose.w), 0.0, 0.0, 0.0, 1.0);
  // the box's back faces: a pixel is drawn where its ray passes through the box (where none does, no
  // view can hit anything), and once only
  vec3 p = iPose.xyz + iScale * (Rz * mix(uLo, uHi, 0.5 * position + 0.5));
  vPose = iPose; vScale = iScale;
  vViews = ivec3(iViews + 0.5); vWeights = iWeights; vSteps = int(iSteps + 0.5);
  gl_Position = uViewProj * vec4(p, 1.0);
}
`;

// The billboards: per pixel, the morph of the instance's three views, lit.
// Reading the stored views: straight sRGB albedo and coverage, round(127 n) + 128 normals
const SAMPLE = `
uniform sampler2DArray uRgba;
uniform sampler2DArray uNormal;
float s2l(float c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

vec4 texRgba(int k, ivec2 p) { // premultiplied linear albedo (morphkit.views.gbuffer.decode_surface)
  if (p.x < 0 || p.y < 0 || p.x >= uN || p.y >= uN) return vec4(0.0);
  vec4 t = texelFetch(uRgba, ivec3(p, k), 0);
  vec3 c = vec3(s2l(t.r), s2l(t.g), s2l(t.b));
  return vec4(c * t.a, t.a);
}
vec3 texNormal(int k, ivec2 p) {
  if (p.x < 0 || p.y < 0 || p.x >= uN || p.y >= uN) return vec3(0.0);
  vec3 n = floor(texelFetch(uNormal, ivec3(p, k), 0).rgb * 255.0 + 0.5) - 128.0;
  float l = length(n);
  return l > 0.0 ? n / max(l, ALPHA_FLOOR) : vec3(0.0);
}
vec4 bilinRgba(int k, vec2 uv) { // cv2.INTER_LINEAR, BORDER_CONSTANT 0
  vec2 f0 = floor(uv); vec2 fr = uv - f0; ivec2 p = ivec2(f0);
  return mix(mix(texRgba(k, p), texRgba(k, p + ivec2(1, 0)), fr.x),
             mix(texRgba(k, p + ivec2(0, 1)), texRgba(k, p + ivec2(1, 1)), fr.x), fr.y);
}
vec3 bilinNormal(int k, vec2 uv) {
  vec2 f0 = floor(uv); vec2 fr = uv - f0; ivec2 p = ivec2(f0);
  return mix(mix(texNormal(k, p), texNormal(k, p + ivec2(1, 0)), fr.x),
             mix(texNormal(k, p + ivec2(0, 1)), texNormal(k, p + ivec2(1, 1)), fr.x), fr.y);
}

`;

const BILLBOARD_FRAG = `
uniform mat3 uCamR; uniform vec3 uEye;
uniform float uFx, uFy, uCxs, uCys, uH;
uniform mat4 uViewProjB;
uniform vec3 uSunDir;   // towards the sun, world frame
uniform float uAmbient, uSunTerm;
out vec4 fragColor;

void main() {
  float px = gl_FragCoord.x - 0.5, py = uH - gl_FragCoord.y - 0.5;
  vec3 dw = normalize(uCamR * vec3((px - uCxs) / uFx, (py - uCys) / uFy, 1.0));
  mat3 Rz = yawMat(vPose.w);
  mat3 Rt = transpose(Rz);
  vec3 o = Rt * (uEye - vPose.xyz) / vScale;
  vec3 d = Rt * dw;
  vec4 h[3];
  float tMin, dt;
  if (!marchThree(o, d, h, tMin, dt)) discard;
  vec3 col = vec3(0.0), nrm = vec3(0.0);
  float aNum = 0.0, aDen = 0.0, cDen = 0.0;
  for (int j = 0; j < 3; j++) {
    float w = vWeights[j];
    if (h[j].x == 0.0 || h[j].x == 1.0) aDen += w;
    if (h[j].x != 1.0) continue;
    vec4 alb = bilinRgba(vViews[j], h[j].zw);
    aNum += w * alb.a;
    if (h[j].y <= tMin + DEPTH_AGREE_STEPS * dt && alb.a > ALPHA_FLOOR) {
      col += w * alb.rgb / alb.a;
      nrm += w * bilinNormal(vViews[j], h[j].zw);
      cDen += w;
    }
  }
  if (cDen <= 0.0) discard;
  float alpha = aDen > 0.0 ? aNum / max(aDen, ALPHA_FLOOR) : 0.0;
  if (alpha <= 0.0) discard;
  col /= max(cDen, ALPHA_FLOOR);
  float nl = length(nrm);
  nrm = nl > 0.0 ? nrm / max(nl, ALPHA_FLOOR) : vec3(0.0);
  vec3 l = Rt * uSunDir;
  float e = uAmbient + uSunTerm * max(0.0, dot(nrm, l));
  vec3 lit = min(col * e, 1.0);
  vec3 enc = pow(lit, vec3(1.0 / 2.2));
  vec3 pw = uEye + dw * (tMin * vScale);
  vec4 clip = uViewProjB * vec4(pw, 1.0);
  gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
  fragColor = vec4(enc * alpha, alpha);
}
`;

// The octahedral impostor beside (morphkit.billboard.impostor): per pixel, its three frames of the
// grid triangle around the instance's direction, each read where the pixel's ray meets its plane
// moved by one parallax step (the engines'), blended by weight; rays from the real eye.
const IMPOSTOR_FRAG = `
uniform sampler2D uFrames;  // per frame k (column): its direction, right and up (rows 0, 1, 2)
uniform float uScale, uCentre;  // frame pixels per scene unit, the frame's centre pixel
uniform mat3 uCamR; uniform vec3 uEye;
uniform float uFx, uFy, uCxs, uCys, uH;
uniform mat4 uViewProjB;
uniform vec3 uSunDir;
uniform float uAmbient, uSunTerm;
out vec4 fragColor;
vec2 texHeight(int k, ivec2 p) { // (alpha, h alpha); h = D - depth, the height above the frame's plane
  if (p.x < 0 || p.y < 0 || p.x >= uN || p.y >= uN) return vec2(0.0);
  float a = texelFetch(uRgba, ivec3(p, k), 0).a;
  float d = texelFetch(uDepth, ivec3(p, k), 0).r;
  return vec2(a, d >= EMPTY_HALF ? 0.0 : (uDist - d) * a);  // the frames store depths, not offsets
}
vec2 bilinHeight(int k, vec2 uv) {
  vec2 f0 = floor(uv); vec2 fr = uv - f0; ivec2 p = ivec2(f0);
  return mix(mix(texHeight(k, p), texHeight(k, p + ivec2(1, 0)), fr.x),
             mix(texHeight(k, p + ivec2(0, 1)), texHeight(k, p + ivec2(1, 1)), fr.x), fr.y);
}
void main() {
  float px = gl_FragCoord.x - 0.5, py = uH - gl_FragCoord.y - 0.5;
  vec3 dw = normalize(uCamR * vec3((px - uCxs) / uFx, (py - uCys) / uFy, 1.0));
  mat3 Rt = transpose(yawMat(vPose.w));
  vec3 o = Rt * (uEye - vPose.xyz) / vScale;
  vec3 d = Rt * dw;
  vec4 alb = vec4(0.0); vec3 nrm = vec3(0.0); float dsum = 0.0;
  for (int j = 0; j < 3; j++) {
    float w = vWeights[j];
    if (w <= 0.0) continue;
    int k = vViews[j];
    vec3 dk = texelFetch(uFrames, ivec2(k, 0), 0).xyz;
    vec3 rk = texelFetch(uFrames, ivec2(k, 1), 0).xyz;
    vec3 uk = texelFetch(uFrames, ivec2(k, 2), 0).xyz;
    vec3 op = o - uPivot;
    float base = dot(op, dk), qk = min(dot(d, dk), -IMP_MIN_COS);
    vec2 f0 = vec2(dot(op, rk), dot(op, uk)), q = vec2(dot(d, rk), dot(d, uk));
    float t = -base / qk;                       // the frame's plane
    vec2 uv = vec2((f0.x + t * q.x) * uScale + uCentre, -(f0.y + t * q.y) * uScale + uCentre);
    vec2 ah = bilinHeight(k, uv);
    float h = ah.x > ALPHA_FLOOR ? ah.y / max(ah.x, ALPHA_FLOOR) : 0.0;
    t = (h - base) / qk;                        // one parallax step: the ray at that height
    uv = vec2((f0.x + t * q.x) * uScale + uCentre, -(f0.y + t * q.y) * uScale + uCentre);
    vec4 fa = bilinRgba(k, uv);
    vec3 fn = bilinNormal(k, uv);
    ah = bilinHeight(k, uv);
    h = fa.a > ALPHA_FLOOR ? ah.y / max(fa.a, ALPHA_FLOOR) : 0.0;
    t = (h - base) / qk;
    alb += w * fa; nrm += w * fn; dsum += w * fa.a * t;
  }
  float alpha = alb.a;
  if (alpha <= ALPHA_FLOOR) discard;
  float nl = length(nrm);
  nrm = nl > 0.0 ? nrm / max(nl, ALPHA_FLOOR) : vec3(0.0);
  alb = clamp(alb, 0.0, 1.0);
  alpha = alb.a;
  vec3 col = alb.rgb / max(alpha, ALPHA_FLOOR);
  vec3 l = Rt * uSunDir;
  float e = uAmbient + uSunTerm * max(0.0, dot(nrm, l));
  vec3 enc = pow(min(col * e, 1.0), vec3(1.0 / 2.2));
  vec3 pw = uEye + dw * (dsum / max(alpha, ALPHA_FLOOR) * vScale);
  vec4 clip = uViewProjB * vec4(pw, 1.0);
  gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
  fragColor = vec4(enc * alpha, alpha);
}
`;

// The sun's shadow map: per texel of the scene's light view, each instance's light view morphed
// from its sun atlas; the colour holds the depth along the light (0: empty).
const SHADOW_FRAG = `
uniform sampler2DArray uCoverage;
uniform mat3 uCamR; uniform vec3 uCamC;
uniform float uFx, uFy, uCxs, uCys, uH;
uniform mat4 uViewProjB;
out vec4 fragColor;
float cov(int k, ivec2 p) {
  if (p.x < 0 || p.y < 0 || p.x >= uN || p.y >= uN) return 0.0;
  return texelFetch(uCoverage, ivec3(p, k), 0).r;
}
float bilinCov(int k, vec2 uv) {
  vec2 f0 = floor(uv); vec2 fr = uv - f0; ivec2 p = ivec2(f0);
  return mix(mix(cov(k, p), cov(k, p + ivec2(1, 0)), fr.x),
             mix(cov(k, p + ivec2(0, 1)), cov(k, p + ivec2(1, 1)), fr.x), fr.y);
}
void main() {
  float px = gl_FragCoord.x - 0.5, py = uH - gl_FragCoord.y - 0.5;
  vec3 ow = uCamC + uCamR * vec3((px - uCxs) / uFx, (py - uCys) / uFy, 0.0);
  vec3 dw = uCamR[2];
  mat3 Rt = transpose(yawMat(vPose.w));
  vec3 o = Rt * (ow - vPose.xyz) / vScale;
  vec3 d = Rt * dw;
  vec4 h[3];
  float tMin, dt;
  if (!marchThree(o, d, h, tMin, dt)) discard;
  float aNum = 0.0, aDen = 0.0, cDen = 0.0;
  for (int j = 0; j < 3; j++) {
    float w = vWeights[j];
    if (h[j].x == 0.0 || h[j].x == 1.0) aDen += w;
    if (h[j].x != 1.0) continue;
    float a = bilinCov(vViews[j], h[j].zw);
    aNum += w * a;
    if (h[j].y <= tMin + DEPTH_AGREE_STEPS * dt && a > ALPHA_FLOOR) cDen += w;
  }
  float alpha = (cDen > 0.0 && aDen > 0.0) ? aNum / max(aDen, ALPHA_FLOOR) : 0.0;
  if (alpha < ${DATA.constants.sun_view_min_coverage.toFixed(4)}) discard;
  float depth = tMin * vScale;   // along the light's axis from its image plane
  vec4 clip = uViewProjB * vec4(ow + dw * depth, 1.0);
  gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
  fragColor = vec4(depth, 0.0, 0.0, 1.0);
}
`;

// The ground (z = 0) and the sky, per pixel, with the sun's shadow map.
const GROUND_VERT = `
in vec3 position;
void main() { gl_Position = vec4(position.xy, 0.0, 1.0); }
`;
const GROUND_FRAG = `
uniform mat3 uCamR; uniform vec3 uEye;
uniform float uFx, uFy, uCxs, uCys, uH;
uniform mat4 uViewProjB;
uniform vec3 uSunDir; uniform float uAmbient, uSunTerm;
uniform vec3 uGround, uSky;
uniform bool uHasShadow;
uniform sampler2D uShadow;
uniform mat3 uSR; uniform vec3 uSC;
uniform float uSFx, uSFy, uSCx, uSCy; uniform int uSN;
out vec4 fragColor;
void main() {
  float px = gl_FragCoord.x - 0.5, py = uH - gl_FragCoord.y - 0.5;
  vec3 dw = normalize(uCamR * vec3((px - uCxs) / uFx, (py - uCys) / uFy, 1.0));
  if (dw.z >= 0.0 || uEye.z <= 0.0) { fragColor = vec4(uSky, 1.0); gl_FragDepth = 1.0; return; }
  float t = -uEye.z / dw.z;
  vec3 p = uEye + t * dw;
  float vis = 1.0;
  if (uHasShadow) {
    vec3 q = transpose(uSR) * (p - uSC);
    float u = uSFx * q.x + uSCx, v = uSFy * q.y + uSCy;
    ivec2 c = ivec2(roundEven(vec2(u, v)));
    if (c.x >= 0 && c.y >= 0 && c.x < uSN && c.y < uSN) {
      float occ = texelFetch(uShadow, ivec2(c.x, uSN - 1 - c.y), 0).r;
      if (occ > 0.0 && q.z > occ + ${DATA.constants.sun_ground_bias_texels.toFixed(4)} / uSFx) vis = 0.0;
    }
  }
  float e = uAmbient + uSunTerm * max(0.0, uSunDir.z) * vis;
  vec3 enc = pow(min(uGround * e, 1.0), vec3(1.0 / 2.2));
  vec4 clip = uViewProjB * vec4(p, 1.0);
  gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
  fragColor = vec4(enc, 1.0);
}
`;

// ------------------------------------------------------------------ state
const state = { camera: { ...DATA.camera }, sun: { ...DATA.sun } };

function readFragment() {
  const f = new URLSearchParams(location.hash.replace(/^#/, ''));
  const nums = (key, n) => {
    if (!f.has(key)) return null;
    const v = f.get(key).split(',').map(Number);
    return v.length >= n && v.every(Number.isFinite) ? v : null;
  };
  const c = nums('camera', 3);
  if (c) Object.assign(state.camera, { azimuth_deg: c[0], elevation_deg: c[1], distance: c[2] });
  const fov = nums('fov', 1);
  if (fov) state.camera.fov_deg = fov[0];
  const s = nums('sun', 2);
  if (s) Object.assign(state.sun, { azimuth_deg: s[0], elevation_deg: s[1] });
  const size = f.has('size') ? f.get('size').split('x').map(Number) : null;
  state.size = size && size.length === 2 && size.every((v) => Number.isInteger(v) && v > 0) ? size : null;
}

function writeFragment() {
  const c = state.camera, s = state.sun;
  const r = (v) => Number(v.toFixed(3));
  let h = `camera=${r(c.azimuth_deg)},${r(c.elevation_deg)},${r(c.distance)}&fov=${r(c.fov_deg)}`
    + `&sun=${r(s.azimuth_deg)},${r(s.elevation_deg)}`;
  if (state.size) h += `&size=${state.size[0]}x${state.size[1]}`;
  history.replaceState(null, '', '#' + h);
}

// The screen camera (morphkit.export.preview.PreviewView.camera)
function screenCamera(w, h) {
  const c = state.camera;
  const el = Math.min(Math.max(c.elevation_deg, -89), 89);
  const eye = add(DATA.target, scale(direction(c.azimuth_deg, el), c.distance));
  const f = 0.5 * h / Math.tan(0.5 * c.fov_deg * DEG);
  const reach = DATA.reach;
  return { R: lookAt(eye, DATA.target), fx: f, fy: f, cx: (w - 1) / 2, cy: (h - 1) / 2, w, h,
    near: Math.max(1e-3, 0.01 * c.distance), far: c.distance + 4 * reach + 100, ortho: false };
}

// ------------------------------------------------------------------ the program
function boxGeometry() {
  const g = new THREE.BoxGeometry(2, 2, 2);
  const ig = new THREE.InstancedBufferGeometry();
  ig.index = g.index;
  ig.setAttribute('position', g.getAttribute('position'));
  return ig;
}

function arrayTexture(bytes, n, layers, kind) {
  let tex;
  if (kind === 'half') {
    tex = new THREE.DataArrayTexture(new Uint16Array(bytes.buffer, bytes.byteOffset, bytes.length / 2), n, n, layers);
    tex.format = THREE.RedFormat; tex.type = THREE.HalfFloatType;
  } else if (kind === 'red') {
    tex = new THREE.DataArrayTexture(bytes, n, n, layers);
    tex.format = THREE.RedFormat; tex.type = THREE.UnsignedByteType;
  } else {
    tex = new THREE.DataArrayTexture(bytes, n, n, layers);
    tex.format = THREE.RGBAFormat; tex.type = THREE.UnsignedByteType;
  }
  tex.minFilter = tex.magFilter = THREE.NearestFilter;
  tex.generateMipmaps = false; tex.unpackAlignment = 1;
  tex.colorSpace = THREE.NoColorSpace;
  tex.needsUpdate = true;
  return tex;
}

function viewUniforms(views) {
  const R = [], C = [];
  for (const v of views) {
    R.push(new THREE.Matrix3().fromArray(v.R, 0).transpose()); // rows given: row-major
    C.push(new THREE.Vector3(...v.C));
  }
  return { uViewR: { value: R }, uViewC: { value: C } };
}

function stepsFor(w, h) { return Math.min(96, Math.max(16, Math.floor(Math.max(w, h) / 3))); }

class Asset {
  constructor(a, scene, shadowScene) {
    this.a = a;
    const inst = new Float32Array(a.instances.buffer, a.instances.byteOffset, a.instances.length / 4);
    this.count = inst.length / 5;
    this.inst = inst;
    const impostor = a.kind === 'impostor';
    const n = a.size, V = impostor ? a.frames * a.frames : a.views.length;
    const geo = boxGeometry();
    const pose = new Float32Array(this.count * 4), sc = new Float32Array(this.count);
    for (let i = 0; i < this.count; i++) {
      pose.set([inst[5 * i], inst[5 * i + 1], inst[5 * i + 2], inst[5 * i + 3] * DEG], 4 * i);
      sc[i] = inst[5 * i + 4];
    }
    geo.setAttribute('iPose', new THREE.InstancedBufferAttribute(pose, 4));
    geo.setAttribute('iScale', new THREE.InstancedBufferAttribute(sc, 1));
    this.views = new THREE.InstancedBufferAttribute(new Float32Array(this.count * 3), 3);
    this.weights = new THREE.InstancedBufferAttribute(new Float32Array(this.count * 3), 3);
    this.views.setUsage(THREE.DynamicDrawUsage); this.weights.setUsage(THREE.DynamicDrawUsage);
    geo.setAttribute('iViews', this.views);
    geo.setAttribute('iWeights', this.weights);
    this.steps = new THREE.InstancedBufferAttribute(new Float32Array(this.count), 1);
    this.steps.setUsage(THREE.DynamicDrawUsage);
    geo.setAttribute('iSteps', this.steps);
    geo.instanceCount = this.count;
    const common = (views, dist, f, fy, cx, ortho) => ({
      uDist: { value: dist }, uVF: { value: f }, uVFy: { value: fy }, uVCx: { value: cx },
      uN: { value: n }, uOrtho: { value: ortho }, ...viewUniforms(views),
    });
    this.uniforms = {
      ...(impostor ? { uDist: { value: a.distance }, uN: { value: n } } : common(a.views, a.distance, a.f, a.f, a.c, false)),
      uDepth: { value: arrayTexture(a.depth, n, V, 'half') },
      uRgba: { value: arrayTexture(a.rgba, n, V, 'rgba') },
      uNormal: { value: arrayTexture(a.normal, n, V, 'rgba') },
      uPivot: { value: new THREE.Vector3(...a.pivot) }, uRadius: { value: a.radius },
      uLo: { value: new THREE.Vector3(...a.bounds[0]) }, uHi: { value: new THREE.Vector3(...a.bounds[1]) },
      uCamR: { value: new THREE.Matrix3() }, uEye: { value: new THREE.Vector3() },
      uFx: { value: 1 }, uFy: { value: 1 }, uCxs: { value: 0 }, uCys: { value: 0 }, uH: { value: 1 },
      uViewProj: { value: new THREE.Matrix4() }, uViewProjB: { value: new THREE.Matrix4() },
      uSunDir: { value: new THREE.Vector3() },
      uAmbient: { value: DATA.lighting.ambient }, uSunTerm: { value: 0 },
    };
    if (impostor) {
      const frames = new THREE.DataTexture(new Float32Array(a.frame_axes), V, 3, THREE.RGBAFormat, THREE.FloatType);
      frames.minFilter = frames.magFilter = THREE.NearestFilter; frames.needsUpdate = true;
      Object.assign(this.uniforms, { uFrames: { value: frames }, uScale: { value: a.scale },
        uCentre: { value: a.centre } });
    }
    const defs = `#define NVIEWS ${V}\n`;
    const frag = impostor ? COMMON + SAMPLE + IMPOSTOR_FRAG : COMMON + VIEWS + SAMPLE + BILLBOARD_FRAG;
    const mat = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3, uniforms: this.uniforms,
      vertexShader: HEAD + INSTANCE_VERT, fragmentShader: HEAD + defs + frag,
      side: THREE.BackSide, transparent: true, depthTest: true, depthWrite: true,
      blending: THREE.CustomBlending, blendSrc: THREE.OneFactor, blendDst: THREE.OneMinusSrcAlphaFactor,
      blendSrcAlpha: THREE.OneFactor, blendDstAlpha: THREE.OneMinusSrcAlphaFactor,
    });
    this.mesh = new THREE.Mesh(geo, mat);
    this.mesh.frustumCulled = false; this.mesh.renderOrder = 1;
    scene.add(this.mesh);
    this.sun = null;
    if (a.sun_atlas) {
      const s = a.sun_atlas, sn = s.size, sv = s.views.length;
      const sgeo = boxGeometry();
      for (const k of ['position', 'iPose', 'iScale']) sgeo.setAttribute(k, geo.getAttribute(k));
      this.sunViews = new THREE.InstancedBufferAttribute(new Float32Array(this.count * 3), 3);
      this.sunWeights = new THREE.InstancedBufferAttribute(new Float32Array(this.count * 3), 3);
      sgeo.setAttribute('iViews', this.sunViews); sgeo.setAttribute('iWeights', this.sunWeights);
      this.sunSteps = new THREE.InstancedBufferAttribute(new Float32Array(this.count), 1);
      this.sunSteps.setUsage(THREE.DynamicDrawUsage);
      sgeo.setAttribute('iSteps', this.sunSteps);
      sgeo.instanceCount = this.count;
      this.sunUniforms = {
        ...common(s.views, s.distance, s.fx, s.fy, s.c, true),
        uN: { value: sn },
        uDepth: { value: arrayTexture(s.depth, sn, sv, 'half') },
        uCoverage: { value: arrayTexture(s.coverage, sn, sv, 'red') },
        uPivot: { value: new THREE.Vector3(...s.pivot) }, uRadius: { value: s.radius },
        uLo: { value: new THREE.Vector3(...s.bounds[0]) }, uHi: { value: new THREE.Vector3(...s.bounds[1]) },
        uCamR: { value: new THREE.Matrix3() }, uCamC: { value: new THREE.Vector3() },
        uFx: { value: 1 }, uFy: { value: 1 }, uCxs: { value: 0 }, uCys: { value: 0 }, uH: { value: 1 },
        uViewProj: { value: new THREE.Matrix4() }, uViewProjB: { value: new THREE.Matrix4() },
      };
      const smat = new THREE.RawShaderMaterial({
        glslVersion: THREE.GLSL3, uniforms: this.sunUniforms,
        vertexShader: HEAD + INSTANCE_VERT, fragmentShader: HEAD + `#define NVIEWS ${sv}\n` + COMMON + VIEWS + SHADOW_FRAG,
        side: THREE.BackSide, depthTest: true, depthWrite: true, blending: THREE.NoBlending,
      });
      this.sunMesh = new THREE.Mesh(sgeo, smat);
      this.sunMesh.frustumCulled = false;
      shadowScene.add(this.sunMesh);
    }
  }

  // per instance: the views around its direction towards the eye (or the sun), object frame
  // and the march's samples: morphkit.views.depthmorph.steps_for the instance's image on screen (its
  // quad's side in pixels) or in the light view (its atlas's side, scaled by the light view's texels)
  update(eye, focal, sunDir, sunFocal) {
    const a = this.a, inst = this.inst, V = this.views.array, W = this.weights.array, S = this.steps.array;
    for (let i = 0; i < this.count; i++) {
      const yaw = inst[5 * i + 3] * DEG, s = inst[5 * i + 4];
      const cy = Math.cos(yaw), sy = Math.sin(yaw);
      const rel = sub(eye, [inst[5 * i], inst[5 * i + 1], inst[5 * i + 2]]);
      const local = [(cy * rel[0] + sy * rel[1]) / s, (-sy * rel[0] + cy * rel[1]) / s, rel[2] / s];
      const d = sub(local, a.pivot);
      const az = Math.atan2(d[1], d[0]) / DEG, el = Math.asin(Math.max(-1, Math.min(1, d[2] / Math.hypot(...d)))) / DEG;
      const [k, w] = a.kind === 'impostor' ? impostorWeights(a.frames, az, el) : domeWeights(a.dome, az, el);
      V.set(k, 3 * i); W.set(w, 3 * i);
      const far = Math.hypot(...d) * s;  // eye to pivot, world units
      const side = 2 * a.half_extent * s * focal / Math.max(far, 1e-6);
      S[i] = stepsFor(Math.floor(Math.min(side, 1e6)), 0);
    }
    this.views.needsUpdate = true; this.weights.needsUpdate = true; this.steps.needsUpdate = true;
    if (this.sunMesh && sunDir) {
      const s = a.sun_atlas, SV = this.sunViews.array, SW = this.sunWeights.array;
      const az0 = Math.atan2(sunDir[1], sunDir[0]) / DEG;
      const el = Math.max(Math.asin(sunDir[2]) / DEG, DATA.constants.sun_min_elevation_deg);
      for (let i = 0; i < this.count; i++) {
        const [k, w] = domeWeights(s.dome, az0 - inst[5 * i + 3], el);
        SV.set(k, 3 * i); SW.set(w, 3 * i);
        this.sunSteps.array[i] = stepsFor(Math.round(s.size * inst[5 * i + 4] * sunFocal / s.fx), 0);
      }
      this.sunViews.needsUpdate = true; this.sunWeights.needsUpdate = true; this.sunSteps.needsUpdate = true;
    }
  }
}

function setCamUniforms(u, cam, mats) {
  u.uCamR.value.copy(camR3(cam));
  if (u.uEye) u.uEye.value.set(...cam.R.c);
  if (u.uCamC) u.uCamC.value.set(...cam.R.c);
  u.uFx.value = cam.fx; u.uFy.value = cam.fy; u.uCxs.value = cam.cx; u.uCys.value = cam.cy; u.uH.value = cam.h;
  if (u.uViewProj) u.uViewProj.value.copy(mats.viewProj);
  u.uViewProjB.value.copy(mats.viewProj);
}

// The scene's light view: along the sun, covering every caster's sphere (one instance at the
// origin, unturned and unscaled: exactly that asset's own light-view camera, so the shadow is
// morphkit.sunlit.sunatlas.ground_shadow's).
function shadowCamera(assets, sunDir) {
  const casters = assets.filter((x) => x.sunMesh && x.count > 0);
  if (!casters.length) return null;
  const az = Math.atan2(sunDir[1], sunDir[0]) / DEG;
  const el = Math.max(Math.asin(sunDir[2]) / DEG, DATA.constants.sun_min_elevation_deg);
  const d = direction(az, el);
  const [right, up] = quadAxes(az, el);
  let centres = [], radii = [], size = 0, ratio = 1, dist = 0;
  for (const x of casters) {
    const s = x.a.sun_atlas, inst = x.inst;
    size = Math.max(size, s.size); ratio = s.half_extent / s.radius;
    for (let i = 0; i < x.count; i++) {
      const yaw = inst[5 * i + 3] * DEG, sc = inst[5 * i + 4], p = s.pivot;
      centres.push([inst[5 * i] + sc * (Math.cos(yaw) * p[0] - Math.sin(yaw) * p[1]),
        inst[5 * i + 1] + sc * (Math.sin(yaw) * p[0] + Math.cos(yaw) * p[1]), inst[5 * i + 2] + sc * p[2]]);
      radii.push(s.radius * sc);
      dist = Math.max(dist, s.distance * sc);
    }
  }
  let c = [0, 0, 0];
  for (const p of centres) c = add(c, p);
  c = scale(c, 1 / centres.length);
  let reach = 0;
  for (let i = 0; i < centres.length; i++) reach = Math.max(reach, Math.hypot(...sub(centres[i], c)) + radii[i]);
  const half = reach * ratio;
  const maxR = Math.max(...radii);
  const n = Math.min(DATA.constants.shadow_max_texels, Math.max(size, Math.round(size * reach / maxR)));
  dist = Math.max(dist, reach * 1.5 + 1e-3);
  const eye = add(c, scale(d, dist));
  const R = { x: right, y: scale(up, -1), z: scale(d, -1), c: eye };
  const f = 0.5 * n / half;
  return { R, fx: f, fy: f, cx: (n - 1) / 2, cy: (n - 1) / 2, w: n, h: n,
    near: dist - 2 * reach, far: dist + 2 * reach, ortho: true }; // the proxy boxes reach 1.77 radii
}

async function main() {
  readFragment();
  const probe = document.createElement('canvas');
  if (!probe.getContext('webgl2')) {
    say('This page needs WebGL 2, which this browser does not provide (or has turned off): '
      + 'nothing can be drawn. Turn on hardware acceleration, or open the page in a browser with WebGL 2.');
    document.title = 'morphkit: no WebGL';
    return;
  }
  const canvas = document.getElementById('view');
  const fit = () => {
    const [w, h] = state.size || [window.innerWidth, window.innerHeight];
    canvas.width = w; canvas.height = h;
    canvas.style.width = w + 'px'; canvas.style.height = h + 'px';
    return [w, h];
  };
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas, antialias: false, alpha: false, preserveDrawingBuffer: true });
  } catch (err) {
    say('This page needs WebGL 2, and the browser refused to start it: ' + err.message);
    document.title = 'morphkit: no WebGL';
    return;
  }
  renderer.setPixelRatio(1);
  renderer.autoClear = true;
  const scene = new THREE.Scene();
  const shadowScene = new THREE.Scene();
  const dummy = new THREE.PerspectiveCamera();
  const groundU = {
    uCamR: { value: new THREE.Matrix3() }, uEye: { value: new THREE.Vector3() },
    uFx: { value: 1 }, uFy: { value: 1 }, uCxs: { value: 0 }, uCys: { value: 0 }, uH: { value: 1 },
    uViewProjB: { value: new THREE.Matrix4() }, uSunDir: { value: new THREE.Vector3() },
    uAmbient: { value: DATA.lighting.ambient }, uSunTerm: { value: 0 },
    uGround: { value: new THREE.Vector3(...DATA.ground.albedo) }, uSky: { value: new THREE.Vector3(...DATA.ground.sky) },
    uHasShadow: { value: false }, uShadow: { value: null },
    uSR: { value: new THREE.Matrix3() }, uSC: { value: new THREE.Vector3() },
    uSFx: { value: 1 }, uSFy: { value: 1 }, uSCx: { value: 0 }, uSCy: { value: 0 }, uSN: { value: 1 },
  };
  const tri = new THREE.BufferGeometry();
  tri.setAttribute('position', new THREE.BufferAttribute(new Float32Array([-1, -1, 0, 3, -1, 0, -1, 3, 0]), 3));
  const ground = new THREE.Mesh(tri, new THREE.RawShaderMaterial({
    glslVersion: THREE.GLSL3, uniforms: groundU, vertexShader: HEAD + GROUND_VERT, fragmentShader: HEAD + GROUND_FRAG,
    depthTest: true, depthWrite: true,
  }));
  ground.frustumCulled = false; ground.renderOrder = 0;
  if (DATA.ground.show) scene.add(ground);
  await inflateAll(DATA.assets);
  const assets = DATA.assets.map((a) => new Asset(a, scene, shadowScene));
  let gltfRoot = null;
  const sunLight = new THREE.DirectionalLight(0xffffff, DATA.lighting.sun_intensity);
  const ambient = new THREE.AmbientLight(0xffffff, DATA.lighting.ambient * Math.PI);
  const notes = [...DATA.notes];
  let shadowTarget = null;
  let shadow = { key: null, texels: 0 };  // the sun the light view was drawn for, and its side
  let lastMs = null, drawn = false;

  function draw() {
    const [w, h] = fit();
    renderer.setSize(w, h, false);
    const cam = screenCamera(w, h);
    const mats = glMatrices(cam);
    const sunDir = direction(state.sun.azimuth_deg, state.sun.elevation_deg);
    const above = sunDir[2] > 0;
    const sunTerm = above ? DATA.lighting.sun_intensity / Math.PI : 0;
    const t0 = performance.now();
    // the light view depends on the sun alone: drawn again only when the sun has moved
    const sunKey = above ? `${state.sun.azimuth_deg},${state.sun.elevation_deg}` : null;
    const scam = sunKey !== null && sunKey !== shadow.key ? shadowCamera(assets, sunDir) : null;
    for (const x of assets) {
      x.update(cam.R.c, cam.fy, scam ? sunDir : null, scam ? scam.fx : 0);
      setCamUniforms(x.uniforms, cam, mats);
      x.uniforms.uSunDir.value.set(...sunDir); x.uniforms.uSunTerm.value = sunTerm;
    }
    setCamUniforms(groundU, cam, mats);
    groundU.uSunDir.value.set(...sunDir); groundU.uSunTerm.value = sunTerm;
    if (sunKey !== shadow.key) shadow = { key: sunKey, texels: scam ? scam.w : 0 };
    groundU.uHasShadow.value = shadow.texels > 0;
    if (scam) {
      if (!shadowTarget || shadowTarget.width !== scam.w) {
        if (shadowTarget) shadowTarget.dispose();
        shadowTarget = new THREE.WebGLRenderTarget(scam.w, scam.h, {
          type: THREE.FloatType, format: THREE.RedFormat, depthBuffer: true,
          minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
        });
      }
      const smats = glMatrices(scam);
      for (const x of assets) if (x.sunMesh) setCamUniforms(x.sunUniforms, scam, smats);
      renderer.setRenderTarget(shadowTarget);
      renderer.setClearColor(0x000000, 0);
      renderer.clear();
      renderer.render(shadowScene, dummy);
      renderer.setRenderTarget(null);
      groundU.uShadow.value = shadowTarget.texture;
      groundU.uSR.value.copy(camR3(scam)); groundU.uSC.value.set(...scam.R.c);
      groundU.uSFx.value = scam.fx; groundU.uSFy.value = scam.fy;
      groundU.uSCx.value = scam.cx; groundU.uSCy.value = scam.cy; groundU.uSN.value = scam.w;
    }
    if (gltfRoot) {
      dummy.matrixAutoUpdate = false; dummy.matrixWorldAutoUpdate = false;
      const { x, y, z, c } = cam.R;
      dummy.matrixWorld.set(x[0], -y[0], -z[0], c[0], x[1], -y[1], -z[1], c[1], x[2], -y[2], -z[2], c[2], 0, 0, 0, 1);
      dummy.matrixWorldInverse.copy(dummy.matrixWorld).invert();
      dummy.projectionMatrix.copy(mats.proj); dummy.projectionMatrixInverse.copy(mats.proj).invert();
      sunLight.position.set(...scale(sunDir, 100)); sunLight.intensity = above ? DATA.lighting.sun_intensity : 0;
    }
    renderer.setClearColor(0x000000, 1);
    renderer.render(scene, dummy);
    const gl = renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4)); // waits for the frame
    lastMs = performance.now() - t0;
    figures();
    writeFragment();
    if (!drawn) { drawn = true; document.title = 'morphkit: ready'; }
    window.morphkitStats = { frame_ms: lastMs, width: w, height: h, instances: assets.reduce((s, x) => s + x.count, 0),
      page_bytes: Number(DATA.page_bytes), shadow_texels: shadow.texels, notes };
  }

  function glName() { // the GL renderer (unmasked where the browser says it)
    const gl = renderer.getContext(), dbg = gl.getExtension('WEBGL_debug_renderer_info');
    return gl.getParameter(dbg ? dbg.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
  }

  function figures() {
    const n = assets.reduce((s, x) => s + x.count, 0);
    const lines = [
      `${DATA.title}`,
      `instances: ${n.toLocaleString()}` + (gltfRoot ? ' (a glTF file from another tool: drawn as meshes)' : ''),
      `bytes: ${DATA.texture_bytes.toLocaleString()} in textures, ${Number(DATA.page_bytes).toLocaleString()} page`,
      `frame: ${lastMs === null ? '-' : lastMs.toFixed(1) + ' ms'} (${glName()})`,
    ];
    for (const x of assets) {
      lines.push(`${x.a.name}: ${x.count.toLocaleString()} instance${x.count === 1 ? '' : 's'}, `
        + `${x.a.view_bytes.toLocaleString()} bytes of ${x.a.kind === 'impostor' ? 'frames' : 'views'}`);
    }
    for (const m of DATA.measured) lines.push(m);
    for (const x of notes) lines.push(x);
    document.getElementById('figures').textContent = lines.join('\n');
    document.getElementById('sun-az').value = state.sun.azimuth_deg;
    document.getElementById('sun-el').value = state.sun.elevation_deg;
  }

  let pending = false;
  const request = () => { if (!pending) { pending = true; requestAnimationFrame(() => { pending = false; draw(); }); } };
  document.getElementById('sun-az').addEventListener('input', (e) => { state.sun.azimuth_deg = Number(e.target.value); request(); });
  document.getElementById('sun-el').addEventListener('input', (e) => { state.sun.elevation_deg = Number(e.target.value); request(); });
  window.addEventListener('hashchange', () => { readFragment(); request(); });
  window.addEventListener('resize', request);
  let drag = null;
  canvas.addEventListener('pointerdown', (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener('pointerup', () => { drag = null; });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag) return;
    state.camera.azimuth_deg -= 0.4 * (e.clientX - drag[0]);
    state.camera.elevation_deg = Math.min(89, Math.max(-10, state.camera.elevation_deg + 0.4 * (e.clientY - drag[1])));
    drag = [e.clientX, e.clientY];
    request();
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    state.camera.distance = Math.max(0.05, state.camera.distance * Math.exp(0.001 * e.deltaY));
    request();
  }, { passive: false });

  if (DATA.gltf) {
    new GLTFLoader().parse(bytesOf(DATA.gltf).buffer, '', (g) => {
      gltfRoot = new THREE.Group();
      gltfRoot.rotation.x = Math.PI / 2; // the file's +y up is morphkit's +z up
      gltfRoot.add(g.scene);
      gltfRoot.updateMatrixWorld(true);
      const box = new THREE.Box3().setFromObject(gltfRoot);
      if (!box.isEmpty()) { // stand it on the ground, centred; fit the camera unless the URL set it
        const c = box.getCenter(new THREE.Vector3());
        gltfRoot.position.set(-c.x, -c.y, -box.min.z);
        const r = 0.5 * box.getSize(new THREE.Vector3()).length();
        DATA.target = [0, 0, c.z - box.min.z];
        DATA.reach = r;
        if (DATA.fit_gltf && !new URLSearchParams(location.hash.slice(1)).has('camera')) {
          state.camera.distance = 1.25 * r / Math.sin(0.5 * state.camera.fov_deg * DEG);
        }
      }
      scene.add(gltfRoot, sunLight, ambient);
      draw();
    }, (err) => { say('The glTF file could not be read: ' + err.message); document.title = 'morphkit: error'; });
  } else {
    draw();
  }
}

main().catch((err) => {
  say('morphkit preview failed: ' + err.message);
  document.title = 'morphkit: error';
  throw err;
});
