// Prints, for each GLB of models/anim/, its size, generator, animations (per channel: the
// node, path, interpolation, key count and times), skins and morph targets (which accessors
// are sparse), and checks what each file is made to cover:
//
//   node report.mjs FILE.glb ...
//
// Exits 1 if a check fails. Reads the JSON chunk only (no glTF library involved).

import { readFile } from "node:fs/promises";
import path from "node:path";

const MAX_BYTES = 64 * 1024;
const COMPONENT = { 5120: "i8", 5121: "u8", 5122: "i16", 5123: "u16", 5125: "u32", 5126: "f32" };

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
const describe = (a) => `${a.type} ${COMPONENT[a.componentType]}${a.normalized ? " normalized" : ""}${a.sparse ? ` sparse (${a.sparse.count} of ${a.count})` : ""}`;

for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(file));
  const gltf = json(bytes, file);
  const name = path.basename(file);
  console.log(`${file}: ${bytes.length} bytes, generator "${gltf.asset.generator}"`);
  if (bytes.length >= MAX_BYTES) fail(`${bytes.length} bytes, not under ${MAX_BYTES}`);
  if (gltf.extensionsUsed || gltf.extensionsRequired) fail("uses extensions");
  const interpolations = new Set();
  const paths = new Set();
  for (const anim of gltf.animations ?? []) {
    for (const ch of anim.channels) {
      const s = anim.samplers[ch.sampler];
      const input = gltf.accessors[s.input];
      const interpolation = s.interpolation ?? "LINEAR";
      interpolations.add(interpolation);
      paths.add(ch.target.path);
      const node = gltf.nodes[ch.target.node].name;
      console.log(`  animation ${anim.name}: ${node}.${ch.target.path} ${interpolation}, ${input.count} keys ${input.min}..${input.max}, output ${describe(gltf.accessors[s.output])}`);
    }
  }
  for (const skin of gltf.skins ?? []) {
    console.log(`  skin ${skin.name}: ${skin.joints.length} joints, inverseBindMatrices ${describe(gltf.accessors[skin.inverseBindMatrices])}`);
  }
  const sets = new Set();
  let sparse = 0;
  for (const mesh of gltf.meshes ?? []) {
    for (const prim of mesh.primitives) {
      const attributes = Object.entries(prim.attributes).map(([semantic, i]) => `${semantic} ${describe(gltf.accessors[i])}`);
      console.log(`  mesh ${mesh.name}: ${attributes.join(", ")}`);
      Object.keys(prim.attributes).filter((s) => s.startsWith("JOINTS_")).forEach((s) => sets.add(s));
      (prim.targets ?? []).forEach((target, t) => {
        const list = Object.entries(target).map(([semantic, i]) => `${semantic} ${describe(gltf.accessors[i])}`);
        console.log(`    target ${t}: ${list.join(", ")}`);
        sparse += Object.values(target).filter((i) => gltf.accessors[i].sparse).length;
      });
      if (mesh.weights) console.log(`    default weights ${JSON.stringify(mesh.weights)}`);
    }
  }
  const want = {
    "samplers.glb": () => {
      for (const i of ["STEP", "LINEAR", "CUBICSPLINE"]) if (!interpolations.has(i)) fail(`no ${i} sampler`);
      for (const p of ["translation", "rotation", "scale", "weights"]) if (!paths.has(p)) fail(`no ${p} channel`);
    },
    "skin8.glb": () => {
      if (!sets.has("JOINTS_0") || !sets.has("JOINTS_1")) fail("not 8 influences (JOINTS_0 and JOINTS_1)");
      if ((gltf.skins?.[0]?.joints.length ?? 0) < 8) fail("fewer than 8 joints");
    },
    "morph-sparse.glb": () => {
      if (sparse < 4) fail(`${sparse} sparse morph accessors, 4 expected`);
      if (!interpolations.has("LINEAR") || !interpolations.has("CUBICSPLINE")) fail("LINEAR and CUBICSPLINE weights expected");
    },
  }[name];
  if (want) want();
  else fail("not a file of models/anim/");
}
process.exit(ok ? 0 : 1);
