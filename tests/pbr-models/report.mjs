// Prints, for each GLB of models/pbr/, its size, generator, extensionsUsed /
// extensionsRequired and every material's factors and extensions, and checks that
//
// - every file is one this script knows, under 300 KB, with the fixed generator string
//   (no-material.glb has no material at all, lights-punctual.glb also uses
//   KHR_lights_punctual, variants.glb KHR_materials_variants, pointer.glb
//   KHR_animation_pointer, instanced.glb EXT_mesh_gpu_instancing, unknown-extension.glb
//   EXT_mesh_features);
// - each material is there, in order, with exactly the material extensions it is made to
//   have, and the file's extensionsUsed is exactly their union (extensionsRequired empty but
//   for instanced.glb, which requires EXT_mesh_gpu_instancing);
// - the two sphere grids have 25 nodes `sphere-m{m}-r{r}` at (i - 2, 2 - j, 0) with
//   material `m{m}-r{r}`, metallicFactor i/4 and roughnessFactor j/4 (node k = 5 j + i).
//
//   node report.mjs FILE.glb ...
//
// Exits 1 if a check fails. Reads the JSON chunk only (no glTF library involved).

import { readFile } from "node:fs/promises";
import path from "node:path";

const GENERATOR = "realist tests/pbr-models/make.mjs (glTF-Transform 4.5.1)";
const MAX_BYTES = 300 * 1024;

const GRID = [];
for (let j = 0; j < 5; j++) for (let i = 0; i < 5; i++) GRID.push(`m${(i / 4).toFixed(2)}-r${(j / 4).toFixed(2)}`);

/** Per file, its materials in order, each with the material extensions it must have. */
const EXPECTED = new Map([
  ["sphere-grid.glb", GRID.map((name) => [name, []])],
  ["sphere-grid-white.glb", GRID.map((name) => [name, []])],
  ["emissive-strength.glb", [["emissive-plain", []], ["emissive-strength-4", ["KHR_materials_emissive_strength"]]]],
  [
    "unlit.glb",
    [["unlit-factor", ["KHR_materials_unlit"]], ["unlit-texture", ["KHR_materials_unlit"]], ["unlit-vertex-color", ["KHR_materials_unlit"]]],
  ],
  [
    "ior-specular.glb",
    [["ior-default", []], ["ior-1.0", ["KHR_materials_ior"]], ["ior-2.5", ["KHR_materials_ior"]], ["specular-0.5", ["KHR_materials_specular"]]],
  ],
  ["unknown-extension.glb", [["plain-red", []]]],
  ["instanced.glb", [["bark", []]]],
  ["clearcoat.glb", [["clearcoat", ["KHR_materials_clearcoat"]]]],
  ["clearcoat-only.glb", [["clearcoat-only", ["KHR_materials_clearcoat", "KHR_materials_specular"]]]],
  ["sheen.glb", [["sheen", ["KHR_materials_sheen"]]]],
  ["sheen-only.glb", [["sheen-only", ["KHR_materials_sheen", "KHR_materials_specular"]]]],
  ...["layer-textures.glb", "layer-factors.glb"].map((file) => [
    file,
    [
      ["coat", ["KHR_materials_clearcoat"]],
      ["sheen", ["KHR_materials_sheen"]],
      ["specular", ["KHR_materials_specular"]],
      ["iridescence", ["KHR_materials_iridescence"]],
    ],
  ]),
  ["coat-normal.glb", [["coat-normal", ["KHR_materials_clearcoat", "KHR_materials_specular"]]]],
  ["iridescence.glb", [["film", ["KHR_materials_iridescence"]]]],
  ["anisotropy.glb", [["brushed", ["KHR_materials_anisotropy"]]]],
  ["anisotropy-texture.glb", [["brushed", ["KHR_materials_anisotropy"]]]],
  ["translucency.glb", [["leaf", ["KHR_materials_diffuse_transmission", "KHR_materials_specular"]]]],
  [
    "transmission-slab.glb",
    [["slab", ["KHR_materials_ior", "KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_volume"]]],
  ],
  [
    "dispersion.glb",
    [["ramp", ["KHR_materials_unlit"]], ["prism", ["KHR_materials_dispersion", "KHR_materials_specular", "KHR_materials_transmission", "KHR_materials_volume"]]],
  ],
  [
    "transmission.glb",
    [["glass", ["KHR_materials_dispersion", "KHR_materials_transmission", "KHR_materials_volume"]], ["behind", []]],
  ],
  ["no-material.glb", []],
  ["lights-punctual.glb", [["floor", []], ["red", []], ["green", []], ["blue", []]]],
  ["variants.glb", [["green", []], ["red", []], ["blue", []]]],
  ["pointer.glb", [["pulse", ["KHR_materials_emissive_strength"]]]],
  [
    "cornell-box.glb",
    [
      ["white", ["KHR_materials_specular"]],
      ["red", ["KHR_materials_specular"]],
      ["green", ["KHR_materials_specular"]],
      ["light", ["KHR_materials_emissive_strength", "KHR_materials_specular"]],
    ],
  ],
]);

/** Extensions a file requires (none for the others). */
const REQUIRED = new Map([["instanced.glb", ["EXT_mesh_gpu_instancing"]]]);

/** Extensions a file uses besides its materials'. */
const OTHER_EXTENSIONS = new Map([
  ["lights-punctual.glb", ["KHR_lights_punctual"]],
  ["variants.glb", ["KHR_materials_variants"]],
  ["pointer.glb", ["KHR_animation_pointer", "KHR_lights_punctual"]],
  ["instanced.glb", ["EXT_mesh_gpu_instancing"]],
  ["unknown-extension.glb", ["EXT_mesh_features"]],
]);

function json(bytes, file) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error(`${file}: not a GLB`);
  const length = view.getUint32(12, true);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
}

let ok = true;
const fail = (message) => {
  console.log(`  FAIL: ${message}`);
  ok = false;
};
const same = (a, b) => JSON.stringify(a ?? []) === JSON.stringify(b ?? []);

/** One line per material: the factors as a reader sees them (schema defaults filled in, marked *). */
function describe(material) {
  const pbr = material.pbrMetallicRoughness ?? {};
  const value = (v, d) => (v === undefined ? `${JSON.stringify(d)}*` : JSON.stringify(v));
  const parts = [
    `baseColor ${value(pbr.baseColorFactor, [1, 1, 1, 1])}`,
    `metallic ${value(pbr.metallicFactor, 1)}`,
    `roughness ${value(pbr.roughnessFactor, 1)}`,
  ];
  if (material.emissiveFactor) parts.push(`emissive ${JSON.stringify(material.emissiveFactor)}`);
  if (pbr.baseColorTexture) parts.push(`baseColorTexture ${JSON.stringify(pbr.baseColorTexture)}`);
  for (const [name, ext] of Object.entries(material.extensions ?? {})) parts.push(`${name} ${JSON.stringify(ext)}`);
  return `  material ${material.name}: ${parts.join(", ")}`;
}

function checkGrid(gltf) {
  if ((gltf.nodes ?? []).length !== 25) return fail(`${(gltf.nodes ?? []).length} nodes, not 25`);
  const before = ok;
  ok = true;
  gltf.nodes.forEach((node, k) => {
    const [i, j] = [k % 5, Math.floor(k / 5)];
    const tag = GRID[k];
    const material = gltf.materials[gltf.meshes[node.mesh].primitives[0].material];
    const pbr = material.pbrMetallicRoughness ?? {};
    if (node.name !== `sphere-${tag}`) fail(`node ${k} is ${node.name}, not sphere-${tag}`);
    // glTF-Transform leaves out a zero translation (the centre sphere's).
    const translation = node.translation ?? [0, 0, 0];
    if (!same(translation, [i - 2, 2 - j, 0])) fail(`node ${k} at ${JSON.stringify(translation)}`);
    if (material.name !== tag) fail(`node ${k} has material ${material.name}, not ${tag}`);
    if ((pbr.metallicFactor ?? 1) !== i / 4 || (pbr.roughnessFactor ?? 1) !== j / 4) fail(`material ${tag}: wrong factors`);
  });
  if (ok) console.log("  grid: 25 nodes sphere-m{i/4}-r{j/4} at (i - 2, 2 - j, 0), k = 5 j + i, factors as named");
  ok = ok && before;
}

for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const gltf = json(bytes, file);
  const name = path.basename(file);
  console.log(`${file}: ${bytes.length} bytes, generator "${gltf.asset.generator}"`);
  console.log(`  extensionsUsed: ${JSON.stringify(gltf.extensionsUsed ?? [])}`);
  console.log(`  extensionsRequired: ${JSON.stringify(gltf.extensionsRequired ?? [])}`);
  const expected = EXPECTED.get(name);
  if (!expected) {
    fail(`not a file of models/pbr/ that this script knows`);
    continue;
  }
  if (bytes.length >= MAX_BYTES) fail(`${bytes.length} bytes, not under ${MAX_BYTES}`);
  if (gltf.asset.generator !== GENERATOR) fail(`generator should be "${GENERATOR}"`);
  const used = [...new Set([...expected.flatMap(([, exts]) => exts), ...(OTHER_EXTENSIONS.get(name) ?? [])])].sort();
  if (!same([...(gltf.extensionsUsed ?? [])].sort(), used)) fail(`extensionsUsed should be ${JSON.stringify(used)}`);
  const required = REQUIRED.get(name) ?? [];
  if (!same(gltf.extensionsRequired ?? [], required)) fail(`extensionsRequired should be ${JSON.stringify(required)}`);
  const materials = gltf.materials ?? [];
  if (materials.length !== expected.length) fail(`${materials.length} materials, not ${expected.length}`);
  materials.forEach((material, m) => {
    console.log(describe(material));
    const [wantName, wantExts] = expected[m] ?? [];
    if (material.name !== wantName) fail(`material ${m} is ${material.name}, not ${wantName}`);
    const exts = Object.keys(material.extensions ?? {}).sort();
    if (!same(exts, wantExts)) fail(`material ${material.name} has extensions ${JSON.stringify(exts)}, not ${JSON.stringify(wantExts)}`);
  });
  for (const node of gltf.nodes ?? []) {
    if (!name.startsWith("sphere-grid")) console.log(`  node ${node.name}: translation ${JSON.stringify(node.translation ?? [0, 0, 0])}`);
  }
  if (name.startsWith("sphere-grid")) checkGrid(gltf);
}
process.exit(ok ? 0 : 1);
