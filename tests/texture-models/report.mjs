// Prints, for each GLB, its size, generator, extensionsUsed / extensionsRequired, how each
// vertex attribute is stored and every KHR_texture_transform, and checks that the files of
// models/texture/ use exactly the extensions they are made to test and stay small:
//
//   node report.mjs FILE.glb ...
//
// Exits 1 if a check fails. Reads the JSON chunk only (no glTF library involved).

import { readFile } from "node:fs/promises";
import path from "node:path";

/** The extensionsUsed each file must have (in this order); files not listed must have none. */
const EXPECTED = new Map([
  ["grid-torus-gltfpack.glb", ["KHR_mesh_quantization", "KHR_texture_transform"]],
  ["transform-quads.glb", ["KHR_texture_transform"]],
]);
/** ... and the extensionsRequired. */
const REQUIRED = new Map([["grid-torus-gltfpack.glb", ["KHR_mesh_quantization"]]]);
const MAX_BYTES = 300 * 1024;

const COMPONENT = { 5120: "i8", 5121: "u8", 5122: "i16", 5123: "u16", 5125: "u32", 5126: "f32" };

function json(bytes, file) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(0, true) !== 0x46546c67) throw new Error(`${file}: not a GLB`);
  const length = view.getUint32(12, true);
  return JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
}

/** Every textureInfo of a material, as [slot name, textureInfo]. */
function textureInfos(material) {
  const pbr = material.pbrMetallicRoughness ?? {};
  return [
    ["baseColorTexture", pbr.baseColorTexture],
    ["metallicRoughnessTexture", pbr.metallicRoughnessTexture],
    ["normalTexture", material.normalTexture],
    ["occlusionTexture", material.occlusionTexture],
    ["emissiveTexture", material.emissiveTexture],
  ].filter(([, info]) => info);
}

let ok = true;
const fail = (message) => {
  console.log(`  FAIL: ${message}`);
  ok = false;
};
const same = (a, b) => JSON.stringify(a ?? []) === JSON.stringify(b ?? []);

for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const gltf = json(bytes, file);
  const name = path.basename(file);
  console.log(`${file}: ${bytes.length} bytes, generator "${gltf.asset.generator}"`);
  console.log(`  extensionsUsed: ${JSON.stringify(gltf.extensionsUsed ?? [])}`);
  console.log(`  extensionsRequired: ${JSON.stringify(gltf.extensionsRequired ?? [])}`);
  if (bytes.length >= MAX_BYTES) fail(`${bytes.length} bytes, not under ${MAX_BYTES}`);
  if (!same(gltf.extensionsUsed, EXPECTED.get(name))) fail(`extensionsUsed should be ${JSON.stringify(EXPECTED.get(name) ?? [])}`);
  if (!same(gltf.extensionsRequired, REQUIRED.get(name))) fail(`extensionsRequired should be ${JSON.stringify(REQUIRED.get(name) ?? [])}`);
  const seen = new Set();
  for (const mesh of gltf.meshes ?? []) {
    for (const prim of mesh.primitives) {
      const attributes = Object.entries(prim.attributes).map(([semantic, i]) => {
        const a = gltf.accessors[i];
        return `${semantic} ${a.type} ${COMPONENT[a.componentType]}${a.normalized ? " normalized" : ""}`;
      });
      const line = `  attributes: ${attributes.join(", ")}`;
      if (!seen.has(line)) console.log(line);
      seen.add(line);
    }
  }
  for (const [m, material] of (gltf.materials ?? []).entries()) {
    for (const [slot, info] of textureInfos(material)) {
      const transform = info.extensions?.KHR_texture_transform;
      if (transform) console.log(`  material ${m} (${material.name ?? "unnamed"}) ${slot} KHR_texture_transform ${JSON.stringify(transform)}`);
    }
  }
  for (const node of gltf.nodes ?? []) {
    if (node.scale && name.includes("gltfpack")) {
      console.log(`  node ${node.name ?? "unnamed"}: translation ${JSON.stringify(node.translation)}, scale ${JSON.stringify(node.scale)}`);
    }
  }
}
process.exit(ok ? 0 : 1);
