// Writes the glTF-Transform test files of models/texture/ (see models/README.md for what each
// holds and make.sh for the whole pipeline):
//
//   node make.mjs DIR
//
// reads the PNGs that `cargo run --release --example make_models -- models/` wrote into DIR
// (uv-grid.png, grid-8.png, emissive-corner.png, normal-bumps.png) and writes into DIR:
// transform-quads.glb, multi-uv.glb, normal-plane.glb, normal-sphere.glb and
// sampler-quads.glb. The geometry is built here; tangents come from glTF-Transform's
// tangents() with the `mikktspace` package (MikkTSpace). Nothing depends on the clock or on
// randomness, so the same inputs give the same bytes.
//
// With --no-tangents-sphere FILE it also writes normal-sphere.glb less its TANGENT accessor
// to FILE. That file is not in models/texture/: a normal map without tangents is exactly
// what the Khronos validator warns about (MESH_PRIMITIVE_GENERATED_TANGENT_SPACE), and
// models/ holds warning-free files only (see models/README.md).

import { readFile, writeFile } from "node:fs/promises";
import path from "node:path";
import { Document, NodeIO, TextureInfo, VERSION } from "@gltf-transform/core";
import { KHRTextureTransform } from "@gltf-transform/extensions";
import { tangents, unweld, weld } from "@gltf-transform/functions";
import mikktspace from "mikktspace";

const { NEAREST, LINEAR, NEAREST_MIPMAP_NEAREST, LINEAR_MIPMAP_NEAREST } = TextureInfo.MinFilter;
const { NEAREST_MIPMAP_LINEAR, LINEAR_MIPMAP_LINEAR } = TextureInfo.MinFilter;
const { REPEAT, MIRRORED_REPEAT, CLAMP_TO_EDGE } = TextureInfo.WrapMode;
const FILTER_NAMES = new Map([
  [NEAREST, "NEAREST"], [LINEAR, "LINEAR"],
  [NEAREST_MIPMAP_NEAREST, "NEAREST_MIPMAP_NEAREST"], [LINEAR_MIPMAP_NEAREST, "LINEAR_MIPMAP_NEAREST"],
  [NEAREST_MIPMAP_LINEAR, "NEAREST_MIPMAP_LINEAR"], [LINEAR_MIPMAP_LINEAR, "LINEAR_MIPMAP_LINEAR"],
]);
const WRAP_NAMES = new Map([[REPEAT, "REPEAT"], [MIRRORED_REPEAT, "MIRRORED_REPEAT"], [CLAMP_TO_EDGE, "CLAMP_TO_EDGE"]]);

const [dir, flag, noTangentsSphere] = process.argv.slice(2);
if (!dir || (flag !== undefined && (flag !== "--no-tangents-sphere" || !noTangentsSphere))) {
  console.error("usage: node make.mjs DIR [--no-tangents-sphere FILE.glb]");
  process.exit(2);
}

const io = new NodeIO().registerExtensions([KHRTextureTransform]);

/** A new document with one buffer, its asset naming this script. */
function newDocument() {
  const doc = new Document();
  doc.getRoot().getAsset().generator = `glTF-Transform ${VERSION} (realist tests/texture-models/make.mjs)`;
  doc.createBuffer();
  return doc;
}

/** A texture holding the PNG file `name` of `dir`. */
async function png(doc, name) {
  const bytes = new Uint8Array(await readFile(path.join(dir, name)));
  return doc.createTexture(name.replace(/\.png$/, "")).setImage(bytes).setMimeType("image/png");
}

function accessor(doc, type, values) {
  return doc.createAccessor().setType(type).setArray(new Float32Array(values)).setBuffer(doc.getRoot().listBuffers()[0]);
}

/**
 * A `size` x `size` quad in the XY plane facing +Z, centred on the origin: vertices top-left,
 * bottom-left, bottom-right, top-right, two counter-clockwise triangles (0 1 2, 0 2 3).
 * `uvSets` lists, per TEXCOORD_n, the UVs of those four corners.
 */
function quad(doc, name, material, uvSets, size = 1) {
  const h = size / 2;
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", [-h, h, 0, -h, -h, 0, h, -h, 0, h, h, 0]))
    .setAttribute("NORMAL", accessor(doc, "VEC3", [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1]))
    .setIndices(doc.createAccessor().setType("SCALAR").setArray(new Uint16Array([0, 1, 2, 0, 2, 3])).setBuffer(doc.getRoot().listBuffers()[0]))
    .setMaterial(material);
  uvSets.forEach((uvs, n) => prim.setAttribute(`TEXCOORD_${n}`, accessor(doc, "VEC2", uvs.flat())));
  return doc.createMesh(name).addPrimitive(prim);
}

/** UVs of the quad corners (top-left, bottom-left, bottom-right, top-right) spanning [lo, hi]. */
const span = (lo, hi) => [[lo, lo], [lo, hi], [hi, hi], [hi, lo]];

/** Adds a node named `name` with `mesh` at `translation` to the document's one scene. */
function place(doc, name, mesh, translation) {
  const root = doc.getRoot();
  if (!root.getDefaultScene()) root.setDefaultScene(doc.createScene("scene"));
  const node = doc.createNode(name).setMesh(mesh).setTranslation(translation);
  root.getDefaultScene().addChild(node);
  return node;
}

/** Sets the sampler state of a texture info. */
function sampler(info, { mag, min, wrapS = REPEAT, wrapT = REPEAT }) {
  info.setMagFilter(mag ?? null).setMinFilter(min ?? null).setWrapS(wrapS).setWrapT(wrapT);
}

async function write(doc, name) {
  const file = path.join(dir, name);
  await writeFile(file, await io.writeBinary(doc));
  console.log(`wrote ${file}`);
}

// ---------------------------------------------------------------------------------------
// transform-quads.glb: KHR_texture_transform on the base colour texture.

/** The quads of transform-quads.glb, left to right; `transform` as in KHR_texture_transform. */
const TRANSFORMS = [
  { name: "0-none" },
  { name: "1-offset", transform: { offset: [0.5, 0.25] } },
  { name: "2-scale", transform: { scale: [2, 0.5] } },
  { name: "3-rotation", transform: { rotation: Math.PI / 2 } },
  { name: "4-readme-example", transform: { offset: [0, 1], rotation: Math.PI / 2, scale: [0.5, 0.5] } },
  { name: "5-combined", transform: { offset: [0.25, 0.75], rotation: Math.PI / 6, scale: [1.5, 0.75] } },
  { name: "6-texcoord-override", transform: { offset: [0.5, 0.5], scale: [0.5, 0.5], texCoord: 1 } },
];

async function transformQuads() {
  const doc = newDocument();
  const ext = doc.createExtension(KHRTextureTransform);
  const grid = await png(doc, "uv-grid.png");
  TRANSFORMS.forEach(({ name, transform }, k) => {
    const material = doc.createMaterial(name).setMetallicFactor(0).setRoughnessFactor(1).setBaseColorTexture(grid);
    const info = material.getBaseColorTextureInfo();
    sampler(info, { mag: NEAREST, min: NEAREST });
    if (transform) {
      const t = ext.createTransform();
      if (transform.offset) t.setOffset(transform.offset);
      if (transform.rotation) t.setRotation(transform.rotation);
      if (transform.scale) t.setScale(transform.scale);
      if (transform.texCoord !== undefined) t.setTexCoord(transform.texCoord);
      info.setExtension("KHR_texture_transform", t);
    }
    // The override quad's TEXCOORD_0 covers only the grid's first cell (A1): a reader that
    // ignores the transform's texCoord shows that cell (or, with the transform, part of E5).
    const uvSets = transform?.texCoord === 1 ? [span(0, 0.125), span(0, 1)] : [span(0, 1)];
    place(doc, name, quad(doc, name, material, uvSets), [1.25 * (k - 3), 0, 0]);
  });
  await write(doc, "transform-quads.glb");
}

// ---------------------------------------------------------------------------------------
// multi-uv.glb: base colour on TEXCOORD_1, emissive on TEXCOORD_0.

async function multiUv() {
  const doc = newDocument();
  const grid = await png(doc, "uv-grid.png");
  const corner = await png(doc, "emissive-corner.png");
  const material = doc
    .createMaterial("multi-uv")
    .setMetallicFactor(0)
    .setRoughnessFactor(1)
    .setBaseColorTexture(grid)
    .setEmissiveTexture(corner)
    .setEmissiveFactor([1, 1, 1]);
  material.getBaseColorTextureInfo().setTexCoord(1);
  sampler(material.getBaseColorTextureInfo(), { mag: NEAREST, min: NEAREST });
  sampler(material.getEmissiveTextureInfo(), { mag: NEAREST, min: NEAREST });
  // TEXCOORD_0: the plain mapping. TEXCOORD_1 = (2 v0, 2 (1 - u0)): the grid 2 x 2 times,
  // its u running down the quad and its v from right to left.
  const uv0 = span(0, 1);
  const uv1 = uv0.map(([u, v]) => [2 * v, 2 * (1 - u)]);
  place(doc, "multi-uv", quad(doc, "multi-uv", material, [uv0, uv1], 2), [0, 0, 0]);
  await write(doc, "multi-uv.glb");
}

// ---------------------------------------------------------------------------------------
// normal-plane.glb, normal-sphere.glb, normal-sphere-no-tangents.glb.

function normalMaterial(doc, name, bumps, scale) {
  const material = doc
    .createMaterial(name)
    .setBaseColorFactor([0.8, 0.8, 0.8, 1])
    .setMetallicFactor(0)
    .setRoughnessFactor(0.4)
    .setNormalTexture(bumps)
    .setNormalScale(scale);
  sampler(material.getNormalTextureInfo(), { mag: LINEAR, min: LINEAR_MIPMAP_LINEAR });
  return material;
}

/**
 * The latitude/longitude sphere of realist's `Mesh::sphere(radius, slices, stacks)`, as an
 * indexed glTF primitive: per slice j a north pole vertex (u = (j + 0.5) / slices, v = 0),
 * rings i = 1 .. stacks - 1 of slices + 1 vertices (u = j / slices, v = i / stacks; the u = 1
 * column repeats u = 0's positions), per slice a south pole vertex (v = 1). Direction of
 * (theta, phi) = (sin theta sin phi, cos theta, sin theta cos phi), theta = pi i / stacks,
 * phi = 2 pi u: u = 0 faces +Z, u grows towards +X. Normals exact; triangles counter-clockwise.
 */
function sphere(doc, name, material, radius, slices, stacks) {
  const pos = [], nor = [], uv = [], idx = [];
  const vertex = (theta, phi, u, v) => {
    const n = [Math.sin(theta) * Math.sin(phi), Math.cos(theta), Math.sin(theta) * Math.cos(phi)];
    pos.push(...n.map((c) => radius * c));
    nor.push(...n);
    uv.push(u, v);
    return pos.length / 3 - 1;
  };
  const north = [], south = [], ring = [];
  for (let j = 0; j < slices; j++) north.push(vertex(0, (2 * Math.PI * (j + 0.5)) / slices, (j + 0.5) / slices, 0));
  for (let i = 1; i < stacks; i++) {
    const row = [];
    for (let j = 0; j <= slices; j++) {
      row.push(vertex((Math.PI * i) / stacks, (2 * Math.PI * j) / slices, j / slices, i / stacks));
    }
    ring.push(row);
  }
  for (let j = 0; j < slices; j++) south.push(vertex(Math.PI, (2 * Math.PI * (j + 0.5)) / slices, (j + 0.5) / slices, 1));
  for (let j = 0; j < slices; j++) idx.push(north[j], ring[0][j], ring[0][j + 1]);
  for (let i = 0; i + 1 < ring.length; i++) {
    for (let j = 0; j < slices; j++) {
      const [a, b, c, d] = [ring[i][j], ring[i + 1][j], ring[i + 1][j + 1], ring[i][j + 1]];
      idx.push(a, b, c, a, c, d);
    }
  }
  const last = ring[ring.length - 1];
  for (let j = 0; j < slices; j++) idx.push(last[j], south[j], last[j + 1]);
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", pos))
    .setAttribute("NORMAL", accessor(doc, "VEC3", nor))
    .setAttribute("TEXCOORD_0", accessor(doc, "VEC2", uv))
    .setIndices(doc.createAccessor().setType("SCALAR").setArray(new Uint16Array(idx)).setBuffer(doc.getRoot().listBuffers()[0]))
    .setMaterial(material);
  return doc.createMesh(name).addPrimitive(prim);
}

/** MikkTSpace tangents for every primitive: unweld, generate, weld again (exact matches only). */
async function withTangents(doc) {
  await doc.transform(unweld(), tangents({ generateTangents: mikktspace.generateTangents }), weld());
}

async function normalPlane() {
  const doc = newDocument();
  const bumps = await png(doc, "normal-bumps.png");
  for (const [name, scale, x] of [["plane-scale-1", 1, -1.1], ["plane-scale-0.5", 0.5, 1.1]]) {
    place(doc, name, quad(doc, name, normalMaterial(doc, name, bumps, scale), [span(0, 1)], 2), [x, 0, 0]);
  }
  await withTangents(doc);
  await write(doc, "normal-plane.glb");
}

async function normalSpheres() {
  const doc = newDocument();
  const bumps = await png(doc, "normal-bumps.png");
  const material = normalMaterial(doc, "normal-sphere", bumps, 1);
  place(doc, "normal-sphere", sphere(doc, "normal-sphere", material, 1, 32, 16), [0, 0, 0]);
  await withTangents(doc);
  await write(doc, "normal-sphere.glb");
  if (!noTangentsSphere) return;
  // The same document less its tangents: every other accessor keeps its values and order.
  for (const prim of doc.getRoot().listMeshes().flatMap((m) => m.listPrimitives())) {
    const tangent = prim.getAttribute("TANGENT");
    prim.setAttribute("TANGENT", null);
    tangent.dispose();
  }
  const bytes = await io.writeBinary(doc);
  await writeFile(noTangentsSphere, bytes);
  console.log(`wrote ${noTangentsSphere}`);
}

// ---------------------------------------------------------------------------------------
// sampler-quads.glb: filters and wrap modes on the 8 x 8 grid.

async function samplerQuads() {
  const doc = newDocument();
  const grid = await png(doc, "grid-8.png");
  const rows = [
    // Wrap modes (S, T), NEAREST filters, UVs -1 .. 2.
    [REPEAT, REPEAT], [MIRRORED_REPEAT, MIRRORED_REPEAT], [CLAMP_TO_EDGE, CLAMP_TO_EDGE],
    [REPEAT, CLAMP_TO_EDGE], [CLAMP_TO_EDGE, MIRRORED_REPEAT], [MIRRORED_REPEAT, REPEAT],
  ].map(([wrapS, wrapT]) => ({
    name: `wrap-${WRAP_NAMES.get(wrapS)}-${WRAP_NAMES.get(wrapT)}`, mag: NEAREST, min: NEAREST, wrapS, wrapT, uvs: [-1, 2],
  }));
  const mag = [[NEAREST, NEAREST], [LINEAR, LINEAR], [null, null]].map(([mag, min]) => ({
    name: mag === null ? "filter-automatic" : `filter-${FILTER_NAMES.get(mag)}`, mag, min, uvs: [-1, 2],
  }));
  const min = [NEAREST, LINEAR, NEAREST_MIPMAP_NEAREST, LINEAR_MIPMAP_NEAREST, NEAREST_MIPMAP_LINEAR, LINEAR_MIPMAP_LINEAR].map(
    (min) => ({ name: `min-${FILTER_NAMES.get(min)}`, mag: LINEAR, min, uvs: [0, 64] }),
  );
  const meshes = new Map();
  [rows, mag, min].forEach((row, r) =>
    row.forEach(({ name, uvs, ...state }, k) => {
      const material = doc.createMaterial(name).setMetallicFactor(0).setRoughnessFactor(1).setBaseColorTexture(grid);
      sampler(material.getBaseColorTextureInfo(), state);
      // One mesh per material; the quads of one UV span share their vertex accessors.
      const key = uvs.join(",");
      let mesh;
      if (meshes.has(key)) {
        const prim = meshes.get(key).listPrimitives()[0].clone().setMaterial(material);
        mesh = doc.createMesh(name).addPrimitive(prim);
      } else {
        mesh = quad(doc, name, material, [span(...uvs)]);
        meshes.set(key, mesh);
      }
      place(doc, name, mesh, [1.25 * k - 3.125, 1.25 * (1 - r), 0]);
    }),
  );
  await write(doc, "sampler-quads.glb");
}

await transformQuads();
await multiUv();
await normalPlane();
await normalSpheres();
await samplerQuads();
