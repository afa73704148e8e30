#!/usr/bin/env node
// Render a glTF/GLB file with three.js (WebGLRenderer) in headless Chromium
// (software WebGL via ANGLE + SwiftShader) and write the canvas as a PNG.
//
// Usage:
//   node render.mjs --model FILE.glb --out OUT.png --size 256x256 \
//     --eye x,y,z --target x,y,z --yfov DEG \
//     [--light directional:DX,DY,DZ:LUX]... [--env none|room|uniform:RADIANCE] [--exposure 1] \
//     [--tone none|neutral|aces|agx|linear|reinhard|cineon] [--background r,g,b] \
//     [--up x,y,z] [--near N] [--far F] [--chromium /usr/bin/chromium] [--quiet]
//
// Prints one JSON line to stdout with the versions, the camera planes, the
// scene bounds, the centre pixel (top-left origin, floor(W/2),floor(H/2)) and timings.

import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const HERE = path.dirname(fileURLToPath(import.meta.url));
const THREE_DIR = path.join(HERE, 'node_modules', 'three');
const t0 = performance.now();

// ---------------------------------------------------------------- arguments
const { values: a } = parseArgs({
  options: {
    model: { type: 'string' },
    out: { type: 'string' },
    size: { type: 'string', default: '256x256' },
    eye: { type: 'string' },
    target: { type: 'string', default: '0,0,0' },
    yfov: { type: 'string', default: '45' },
    up: { type: 'string', default: '0,1,0' },
    light: { type: 'string', multiple: true, default: [] },
    env: { type: 'string', default: 'none' },
    exposure: { type: 'string', default: '1' },
    tone: { type: 'string', default: 'none' },
    background: { type: 'string', default: '0,0,0' },
    near: { type: 'string' },
    far: { type: 'string' },
    chromium: { type: 'string', default: process.env.CHROMIUM || '/usr/bin/chromium' },
    quiet: { type: 'boolean', default: false },
    help: { type: 'boolean', short: 'h', default: false },
  },
  strict: true,
});

function die(msg) {
  console.error(`render.mjs: ${msg}`);
  process.exit(2);
}
if (a.help) {
  console.log(fs.readFileSync(fileURLToPath(import.meta.url), 'utf8').split('\n').slice(1, 13).join('\n'));
  process.exit(0);
}
function vec(s, n, name) {
  const v = String(s).split(',').map(Number);
  if (v.length !== n || v.some((x) => !Number.isFinite(x))) die(`--${name} needs ${n} comma-separated numbers, got "${s}"`);
  return v;
}
function num(s, name) {
  const x = Number(s);
  if (!Number.isFinite(x)) die(`--${name} needs a number, got "${s}"`);
  return x;
}
if (!a.model) die('--model is required');
if (!a.out) die('--out is required');
if (!a.eye) die('--eye is required');
const modelPath = path.resolve(a.model);
if (!fs.existsSync(modelPath)) die(`model not found: ${modelPath}`);
const sm = /^(\d+)x(\d+)$/.exec(a.size);
if (!sm) die(`--size must be WxH, got "${a.size}"`);

const TONES = ['none', 'neutral', 'aces', 'agx', 'linear', 'reinhard', 'cineon'];
if (!TONES.includes(a.tone)) die(`--tone must be one of ${TONES.join('|')}`);
const uniformEnv = /^uniform:([0-9.eE+-]+)$/.exec(a.env);
if (!['none', 'room'].includes(a.env) && !uniformEnv) die('--env must be none, room or uniform:RADIANCE');
if (uniformEnv) num(uniformEnv[1], 'env uniform radiance');

const lights = a.light.map((spec) => {
  const m = /^directional:([^:]+):([^:]+)$/.exec(spec);
  if (!m) die(`--light must look like directional:DX,DY,DZ:INTENSITY, got "${spec}"`);
  const dir = vec(m[1], 3, 'light direction');
  if (Math.hypot(...dir) === 0) die('--light direction must be non-zero');
  return { type: 'directional', dir, intensity: num(m[2], 'light intensity') };
});

const cfg = {
  width: Number(sm[1]),
  height: Number(sm[2]),
  eye: vec(a.eye, 3, 'eye'),
  target: vec(a.target, 3, 'target'),
  up: vec(a.up, 3, 'up'),
  yfov: num(a.yfov, 'yfov'),
  lights,
  env: a.env,
  exposure: num(a.exposure, 'exposure'),
  tone: a.tone,
  background: vec(a.background, 3, 'background'),
  near: a.near !== undefined ? num(a.near, 'near') : null,
  far: a.far !== undefined ? num(a.far, 'far') : null,
  modelUrl: '/model/' + encodeURIComponent(path.basename(modelPath)),
};

// --------------------------------------------------------------- page (HTML)
const PAGE = `<!doctype html>
<html><head><meta charset="utf-8">
<style>html,body{margin:0;background:#000}</style>
<script type="importmap">
{ "imports": { "three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/" } }
</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';

const TONE = {
  none: THREE.NoToneMapping, neutral: THREE.NeutralToneMapping, aces: THREE.ACESFilmicToneMapping,
  agx: THREE.AgXToneMapping, linear: THREE.LinearToneMapping, reinhard: THREE.ReinhardToneMapping,
  cineon: THREE.CineonToneMapping,
};

window.renderScene = async (cfg) => {
  const canvas = document.createElement('canvas');
  document.body.appendChild(canvas);
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true, alpha: false });
  renderer.setPixelRatio(1);
  renderer.setSize(cfg.width, cfg.height, false);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = TONE[cfg.tone];
  renderer.toneMappingExposure = cfg.exposure;

  const loader = new GLTFLoader();
  loader.setDRACOLoader(new DRACOLoader().setDecoderPath('/three/examples/jsm/libs/draco/gltf/'));
  loader.setKTX2Loader(new KTX2Loader().setTranscoderPath('/three/examples/jsm/libs/basis/').detectSupport(renderer));
  loader.setMeshoptDecoder(MeshoptDecoder);
  const tLoad = performance.now();
  const gltf = await loader.loadAsync(cfg.modelUrl);
  const loadMs = performance.now() - tLoad;

  const scene = new THREE.Scene();
  scene.add(gltf.scene);
  // --background is given as display (sRGB-encoded) values in 0..1; three converts
  // it to the working (linear) space here and back to sRGB when clearing.
  scene.background = new THREE.Color().setRGB(...cfg.background, THREE.SRGBColorSpace);

  if (cfg.env === 'room') {
    const pmrem = new THREE.PMREMGenerator(renderer);
    scene.environment = pmrem.fromScene(new RoomEnvironment(), 0.04).texture;
  } else if (cfg.env.startsWith('uniform:')) {
    // A uniform surround of that linear radiance: the PMREM of an empty scene whose
    // background is the colour.
    const k = Number(cfg.env.slice('uniform:'.length));
    const surround = new THREE.Scene();
    surround.background = new THREE.Color().setRGB(k, k, k, THREE.LinearSRGBColorSpace);
    const pmrem = new THREE.PMREMGenerator(renderer);
    scene.environment = pmrem.fromScene(surround, 0).texture;
  }

  // Bounds of the model, used for the near/far planes and for placing lights.
  scene.updateMatrixWorld(true);
  const box = new THREE.Box3().setFromObject(gltf.scene);
  const sphere = box.isEmpty() ? new THREE.Sphere(new THREE.Vector3(), 1) : box.getBoundingSphere(new THREE.Sphere());
  const r = Math.max(sphere.radius, 1e-6);

  const eye = new THREE.Vector3(...cfg.eye);
  const d = eye.distanceTo(sphere.center);
  let far = cfg.far ?? (d + r) * 1.1;
  let near = cfg.near ?? Math.max((d - r) * 0.9, far * 1e-4);

  const camera = new THREE.PerspectiveCamera(cfg.yfov, cfg.width / cfg.height, near, far);
  camera.position.copy(eye);
  camera.up.set(...cfg.up);
  camera.lookAt(new THREE.Vector3(...cfg.target));
  camera.updateMatrixWorld(true);

  // DirectionalLight shines from light.position towards light.target.position,
  // so put it upstream of the scene centre along the travel direction.
  for (const L of cfg.lights) {
    const dir = new THREE.Vector3(...L.dir).normalize();
    const light = new THREE.DirectionalLight(0xffffff, L.intensity);
    light.target.position.copy(sphere.center);
    light.position.copy(sphere.center).addScaledVector(dir, -2 * r);
    scene.add(light, light.target);
  }

  const tRender = performance.now();
  renderer.render(scene, camera);
  const gl = renderer.getContext();
  gl.finish();
  const renderMs = performance.now() - tRender;

  // Centre pixel, image (top-left) coordinates -> GL (bottom-left) for readPixels.
  const cx = Math.floor(cfg.width / 2), cy = Math.floor(cfg.height / 2);
  const px = new Uint8Array(4);
  gl.readPixels(cx, cfg.height - 1 - cy, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);

  const dbg = gl.getExtension('WEBGL_debug_renderer_info');
  const materials = new Set();
  gltf.scene.traverse((o) => { if (o.isMesh) [].concat(o.material).forEach((m) => materials.add(m.type + (m.name ? ':' + m.name : ''))); });
  return {
    png: canvas.toDataURL('image/png'),
    info: {
      three: THREE.REVISION,
      webgl: gl.getParameter(gl.VERSION),
      glRenderer: dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER),
      bounds: { center: sphere.center.toArray(), radius: sphere.radius },
      near, far,
      materials: [...materials],
      centrePixel: { x: cx, y: cy, rgba: Array.from(px) },
      loadMs: +loadMs.toFixed(1), renderMs: +renderMs.toFixed(1),
    },
  };
};
window.harnessReady = true;
</script></head><body></body></html>`;

// ------------------------------------------------------------ static server
const MIME = {
  '.js': 'text/javascript', '.mjs': 'text/javascript', '.wasm': 'application/wasm',
  '.json': 'application/json', '.gltf': 'model/gltf+json', '.glb': 'model/gltf-binary',
  '.bin': 'application/octet-stream', '.png': 'image/png', '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg',
  '.webp': 'image/webp', '.ktx2': 'image/ktx2', '.html': 'text/html',
};
const roots = { '/three/': THREE_DIR, '/model/': path.dirname(modelPath) };
const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://x');
  if (url.pathname === '/favicon.ico') { res.writeHead(204); return res.end(); }
  if (url.pathname === '/' || url.pathname === '/index.html') {
    res.writeHead(200, { 'content-type': 'text/html' });
    return res.end(PAGE);
  }
  for (const [prefix, root] of Object.entries(roots)) {
    if (!url.pathname.startsWith(prefix)) continue;
    const rel = decodeURIComponent(url.pathname.slice(prefix.length));
    const file = path.resolve(root, rel);
    if (!file.startsWith(root + path.sep)) break; // no escaping the root
    return fs.readFile(file, (err, data) => {
      if (err) { res.writeHead(404); return res.end(); }
      res.writeHead(200, { 'content-type': MIME[path.extname(file).toLowerCase()] || 'application/octet-stream' });
      res.end(data);
    });
  }
  res.writeHead(404);
  res.end();
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const base = `http://127.0.0.1:${server.address().port}/`;

// ------------------------------------------------------------------ browser
const browser = await chromium.launch({
  executablePath: a.chromium,
  args: [
    '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    '--ignore-gpu-blocklist', '--no-sandbox', '--force-color-profile=srgb',
  ],
});
let code = 0;
try {
  const page = await browser.newPage({ viewport: { width: cfg.width, height: cfg.height }, deviceScaleFactor: 1 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => {
    if (!a.quiet && (m.type() === 'error' || m.type() === 'warning')) console.error(`[page ${m.type()}] ${m.text()}`);
  });
  await page.goto(base);
  await page.waitForFunction(() => window.harnessReady === true, null, { timeout: 30000 }).catch(() => {
    throw new Error('page did not initialise: ' + errors.join('; '));
  });
  const { png, info } = await page.evaluate((c) => window.renderScene(c), cfg);
  fs.mkdirSync(path.dirname(path.resolve(a.out)), { recursive: true });
  fs.writeFileSync(a.out, Buffer.from(png.split(',')[1], 'base64'));
  info.out = path.resolve(a.out);
  info.totalMs = +(performance.now() - t0).toFixed(0);
  console.log(JSON.stringify(info));
} catch (e) {
  console.error(`render.mjs: ${e.message || e}`);
  code = 1;
} finally {
  await browser.close();
  server.close();
}
process.exit(code);
