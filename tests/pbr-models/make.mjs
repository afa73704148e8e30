// Writes the physically based material test files of models/pbr/ (see models/README.md for
// what each holds and make.sh for the whole pipeline):
//
//   node make.mjs DIR
//
// writes into DIR: sphere-grid.glb, sphere-grid-white.glb, emissive-strength.glb, unlit.glb
// (and its texture, unlit-4x4.png), ior-specular.glb, unknown-extension.glb, no-material.glb
// lights-punctual.glb, variants.glb, pointer.glb, instanced.glb, clearcoat.glb,
// clearcoat-only.glb, sheen.glb, sheen-only.glb, layer-textures.glb, layer-factors.glb,
// coat-normal.glb, iridescence.glb, anisotropy.glb, anisotropy-texture.glb, translucency.glb,
// transmission-slab.glb, transmission.glb and dispersion.glb.
// Every piece of
// geometry and the PNG are built here; glTF-Transform only writes the files. Nothing depends
// on the clock or on randomness, so running it twice gives the same bytes.

import { writeFile } from "node:fs/promises";
import path from "node:path";
import { Document, NodeIO, TextureInfo, VERSION } from "@gltf-transform/core";
import {
  EXTMeshFeatures,
  EXTMeshGPUInstancing,
  KHRLightsPunctual,
  KHRMaterialsAnisotropy,
  KHRMaterialsClearcoat,
  KHRMaterialsDiffuseTransmission,
  KHRMaterialsDispersion,
  Light,
  KHRMaterialsEmissiveStrength,
  KHRMaterialsIOR,
  KHRMaterialsIridescence,
  KHRMaterialsSheen,
  KHRMaterialsSpecular,
  KHRMaterialsTransmission,
  KHRMaterialsUnlit,
  KHRMaterialsVolume,
  KHRMaterialsVariants,
} from "@gltf-transform/extensions";

const [dir] = process.argv.slice(2);
if (!dir || process.argv.length !== 3) {
  console.error("usage: node make.mjs DIR");
  process.exit(2);
}

const io = new NodeIO().registerExtensions([
  EXTMeshFeatures,
  EXTMeshGPUInstancing,
  KHRLightsPunctual,
  KHRMaterialsAnisotropy,
  KHRMaterialsClearcoat,
  KHRMaterialsDiffuseTransmission,
  KHRMaterialsDispersion,
  KHRMaterialsEmissiveStrength,
  KHRMaterialsIOR,
  KHRMaterialsIridescence,
  KHRMaterialsSheen,
  KHRMaterialsSpecular,
  KHRMaterialsTransmission,
  KHRMaterialsUnlit,
  KHRMaterialsVolume,
  KHRMaterialsVariants,
]);

/** A new document with one buffer and one scene, its asset naming this script. */
function newDocument() {
  const doc = new Document();
  doc.getRoot().getAsset().generator = `realist tests/pbr-models/make.mjs (glTF-Transform ${VERSION.replace(/^v/, "")})`;
  doc.createBuffer();
  doc.getRoot().setDefaultScene(doc.createScene("scene"));
  return doc;
}

const buffer = (doc) => doc.getRoot().listBuffers()[0];

function accessor(doc, type, values) {
  return doc.createAccessor().setType(type).setArray(new Float32Array(values)).setBuffer(buffer(doc));
}

function indices(doc, values) {
  return doc.createAccessor().setType("SCALAR").setArray(new Uint16Array(values)).setBuffer(buffer(doc));
}

/** Adds a node named `name` with `mesh` at `translation` to the document's scene. */
function place(doc, name, mesh, translation) {
  const node = doc.createNode(name).setMesh(mesh).setTranslation(translation);
  doc.getRoot().getDefaultScene().addChild(node);
  return node;
}

/** A mesh named `name` with one primitive: `prim` (shared accessors) with `material`. */
function meshWith(doc, name, prim, material) {
  return doc.createMesh(name).addPrimitive(prim.clone().setMaterial(material));
}

async function write(doc, name) {
  const file = path.join(dir, name);
  const bytes = await io.writeBinary(doc);
  await writeFile(file, bytes);
  console.log(`wrote ${file} (${bytes.length} bytes)`);
}

/** Formats a factor as in the material names: two decimals (0.25 -> "0.25", 1 -> "1.00"). */
const two = (x) => x.toFixed(2);

// ---------------------------------------------------------------------------------------
// Geometry.

export const SPHERE_RADIUS = 0.4;
export const SPHERE_SLICES = 48;
export const SPHERE_STACKS = 32;

/**
 * A latitude/longitude sphere of radius `radius` around the origin, poles on +-Y, as an
 * indexed primitive without material: per slice j a north pole vertex (u = (j + 0.5) /
 * slices, v = 0), rings i = 1 .. stacks - 1 of slices + 1 vertices (u = j / slices, v = i /
 * stacks; the u = 1 column has exactly u = 0's positions and normals), per slice a south pole
 * vertex (v = 1). Direction of (theta, phi) = (sin theta sin phi, cos theta, sin theta cos phi),
 * theta = pi v, phi = 2 pi u - pi: u = 0.5 faces +Z (the camera), u grows towards +X (to the
 * right seen from +Z), and the seam u = 0 / 1 is at the back (-Z). NORMAL = POSITION / radius
 * (computed from the same direction, unit length up to f32 rounding). Triangles
 * counter-clockwise seen from outside; u16 indices.
 */
function spherePrimitive(doc, radius = SPHERE_RADIUS, slices = SPHERE_SLICES, stacks = SPHERE_STACKS) {
  const pos = [], nor = [], uv = [], idx = [];
  const vertex = (n, u, v) => {
    pos.push(...n.map((c) => radius * c));
    nor.push(...n);
    uv.push(u, v);
    return pos.length / 3 - 1;
  };
  const direction = (theta, phi) => [Math.sin(theta) * Math.sin(phi), Math.cos(theta), Math.sin(theta) * Math.cos(phi)];
  const north = [], south = [], ring = [];
  for (let j = 0; j < slices; j++) {
    north.push(vertex([0, 1, 0], (j + 0.5) / slices, 0));
  }
  for (let i = 1; i < stacks; i++) {
    const row = [];
    for (let j = 0; j <= slices; j++) {
      const phi = (2 * Math.PI * (j % slices)) / slices - Math.PI;
      row.push(vertex(direction((Math.PI * i) / stacks, phi), j / slices, i / stacks));
    }
    ring.push(row);
  }
  for (let j = 0; j < slices; j++) {
    south.push(vertex([0, -1, 0], (j + 0.5) / slices, 1));
  }
  for (let j = 0; j < slices; j++) idx.push(north[j], ring[0][j], ring[0][j + 1]);
  for (let i = 0; i + 1 < ring.length; i++) {
    for (let j = 0; j < slices; j++) {
      const [a, b, c, d] = [ring[i][j], ring[i + 1][j], ring[i + 1][j + 1], ring[i][j + 1]];
      idx.push(a, b, c, a, c, d);
    }
  }
  const last = ring[ring.length - 1];
  for (let j = 0; j < slices; j++) idx.push(last[j], south[j], last[j + 1]);
  return doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", pos))
    .setAttribute("NORMAL", accessor(doc, "VEC3", nor))
    .setAttribute("TEXCOORD_0", accessor(doc, "VEC2", uv))
    .setIndices(indices(doc, idx));
}

/**
 * A 1 x 1 quad in the XY plane facing +Z, centred on the origin, without material: vertices
 * top-left, bottom-left, bottom-right, top-right, NORMAL +Z, triangles 0 1 2 and 0 2 3 (u16).
 * With `uv`, TEXCOORD_0 (0, 0), (0, 1), (1, 1), (1, 0) (upright seen from +Z); with `colors`,
 * COLOR_0 (f32 VEC3) = those four colours.
 */
function quadPrimitive(doc, { uv = false, colors = null } = {}) {
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", [-0.5, 0.5, 0, -0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0]))
    .setAttribute("NORMAL", accessor(doc, "VEC3", [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1]))
    .setIndices(indices(doc, [0, 1, 2, 0, 2, 3]));
  if (uv) prim.setAttribute("TEXCOORD_0", accessor(doc, "VEC2", [0, 0, 0, 1, 1, 1, 1, 0]));
  if (colors) prim.setAttribute("COLOR_0", accessor(doc, "VEC3", colors.flat()));
  return prim;
}

// ---------------------------------------------------------------------------------------
// A minimal PNG writer: RGBA8, no colour metadata, zlib stream of stored (uncompressed)
// deflate blocks, so the bytes depend on nothing but the pixels (no zlib version involved).

const CRC_TABLE = Array.from({ length: 256 }, (_, n) => {
  let c = n;
  for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
  return c >>> 0;
});

function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) c = CRC_TABLE[(c ^ b) & 0xff] ^ (c >>> 8);
  return (c ^ 0xffffffff) >>> 0;
}

function adler32(bytes) {
  let a = 1, b = 0;
  for (const x of bytes) {
    a = (a + x) % 65521;
    b = (b + a) % 65521;
  }
  return ((b << 16) | a) >>> 0;
}

const u32be = (x) => [(x >>> 24) & 0xff, (x >>> 16) & 0xff, (x >>> 8) & 0xff, x & 0xff];

function chunk(type, data) {
  const body = [...Buffer.from(type, "ascii"), ...data];
  return [...u32be(data.length), ...body, ...u32be(crc32(body))];
}

/** `rgba(x, y)` -> [r, g, b, a] bytes for each texel of a width x height image, row 0 on top. */
function png(width, height, rgba) {
  const raw = [];
  for (let y = 0; y < height; y++) {
    raw.push(0); // filter type None
    for (let x = 0; x < width; x++) raw.push(...rgba(x, y));
  }
  const zlib = [0x78, 0x01];
  for (let start = 0; start < raw.length || start === 0; start += 65535) {
    const block = raw.slice(start, start + 65535);
    const final = start + 65535 >= raw.length ? 1 : 0;
    zlib.push(final, block.length & 0xff, block.length >> 8, ~block.length & 0xff, (~block.length >> 8) & 0xff, ...block);
  }
  zlib.push(...u32be(adler32(raw)));
  const ihdr = [...u32be(width), ...u32be(height), 8, 6, 0, 0, 0]; // 8 bits, RGBA, deflate, filter 0, no interlace
  const sig = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a];
  return new Uint8Array([...sig, ...chunk("IHDR", ihdr), ...chunk("IDAT", zlib), ...chunk("IEND", [])]);
}

/**
 * The 4 x 4 texture of unlit.glb (sRGB): texel (x, y) = (85 x, 85 y, B, 255) with B = 255 when
 * x + y is even, else 0; e.g. (0, 0) = (0, 0, 255), (3, 0) = (255, 0, 0), (3, 3) = (255, 255, 255).
 */
export const UNLIT_TEXEL = (x, y) => [85 * x, 85 * y, (x + y) % 2 === 0 ? 255 : 0, 255];

// ---------------------------------------------------------------------------------------
// sphere-grid.glb, sphere-grid-white.glb.

/**
 * 5 x 5 spheres, node k = 5 j + i (row j = 0 .. 4 from the top, column i = 0 .. 4 from the
 * left) at (i - 2, 2 - j, 0), metallicFactor i / 4, roughnessFactor j / 4. Each sphere has its
 * own mesh and material; every mesh's one primitive shares the same vertex and index accessors.
 */
async function sphereGrid(name, baseColor) {
  const doc = newDocument();
  const sphere = spherePrimitive(doc);
  for (let j = 0; j < 5; j++) {
    for (let i = 0; i < 5; i++) {
      const [metallic, roughness] = [i / 4, j / 4];
      const tag = `m${two(metallic)}-r${two(roughness)}`;
      const material = doc
        .createMaterial(tag)
        .setBaseColorFactor(baseColor)
        .setMetallicFactor(metallic)
        .setRoughnessFactor(roughness);
      place(doc, `sphere-${tag}`, meshWith(doc, `sphere-${tag}`, sphere, material), [i - 2, 2 - j, 0]);
    }
  }
  sphere.dispose(); // the template itself is in no mesh; its accessors are shared by the clones
  await write(doc, name);
}

// ---------------------------------------------------------------------------------------
// emissive-strength.glb.

async function emissiveStrength() {
  const doc = newDocument();
  const ext = doc.createExtension(KHRMaterialsEmissiveStrength);
  const quad = quadPrimitive(doc);
  for (const [name, strength, x] of [["emissive-plain", null, -0.6], ["emissive-strength-4", 4, 0.6]]) {
    const material = doc
      .createMaterial(name)
      .setBaseColorFactor([0, 0, 0, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(1)
      .setEmissiveFactor([0.2, 0.1, 0.05]);
    if (strength !== null) material.setExtension("KHR_materials_emissive_strength", ext.createEmissiveStrength().setEmissiveStrength(strength));
    place(doc, name, meshWith(doc, name, quad, material), [x, 0, 0]);
  }
  quad.dispose();
  await write(doc, "emissive-strength.glb");
}

// ---------------------------------------------------------------------------------------
// unlit.glb (and unlit-4x4.png).

/** Vertex colours of the third quad: linear in x, so any triangulation interpolates them alike. */
export const UNLIT_COLORS_LEFT = [1, 0.5, 0];
export const UNLIT_COLORS_RIGHT = [0, 0.5, 1];

async function unlit() {
  const doc = newDocument();
  const ext = doc.createExtension(KHRMaterialsUnlit);
  const image = png(4, 4, UNLIT_TEXEL);
  await writeFile(path.join(dir, "unlit-4x4.png"), image);
  console.log(`wrote ${path.join(dir, "unlit-4x4.png")} (${image.length} bytes)`);
  const texture = doc.createTexture("unlit-4x4").setImage(image).setMimeType("image/png");
  const [L, R] = [UNLIT_COLORS_LEFT, UNLIT_COLORS_RIGHT];
  const quads = [
    ["unlit-factor", -0.6, quadPrimitive(doc), false],
    ["unlit-texture", 0.6, quadPrimitive(doc, { uv: true }), true],
    ["unlit-vertex-color", 1.8, quadPrimitive(doc, { colors: [L, L, R, R] }), false],
  ];
  for (const [name, x, prim, textured] of quads) {
    // metallic 0 and roughness 0.9: the fallback the KHR_materials_unlit README suggests for
    // readers without the extension.
    const material = doc
      .createMaterial(name)
      .setBaseColorFactor([0.25, 0.5, 0.75, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(0.9)
      .setExtension("KHR_materials_unlit", ext.createUnlit());
    if (textured) {
      material.setBaseColorTexture(texture);
      const info = material.getBaseColorTextureInfo();
      info.setMagFilter(TextureInfo.MagFilter.NEAREST).setMinFilter(TextureInfo.MinFilter.NEAREST);
      info.setWrapS(TextureInfo.WrapMode.CLAMP_TO_EDGE).setWrapT(TextureInfo.WrapMode.CLAMP_TO_EDGE);
    }
    prim.setMaterial(material);
    place(doc, name, doc.createMesh(name).addPrimitive(prim), [x, 0, 0]);
  }
  await write(doc, "unlit.glb");
}

// ---------------------------------------------------------------------------------------
// ior-specular.glb.

async function iorSpecular() {
  const doc = newDocument();
  const iorExt = doc.createExtension(KHRMaterialsIOR);
  const specularExt = doc.createExtension(KHRMaterialsSpecular);
  const sphere = spherePrimitive(doc);
  const spheres = [
    ["ior-default", -1.5, null],
    ["ior-1.0", -0.5, (m) => m.setExtension("KHR_materials_ior", iorExt.createIOR().setIOR(1.0))],
    ["ior-2.5", 0.5, (m) => m.setExtension("KHR_materials_ior", iorExt.createIOR().setIOR(2.5))],
    [
      "specular-0.5",
      1.5,
      (m) =>
        m.setExtension(
          "KHR_materials_specular",
          specularExt.createSpecular().setSpecularFactor(0.5).setSpecularColorFactor([1, 0.2, 0.2]),
        ),
    ],
  ];
  for (const [name, x, extend] of spheres) {
    const material = doc
      .createMaterial(name)
      .setBaseColorFactor([0.5, 0.5, 0.5, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(0.3);
    if (extend) extend(material);
    place(doc, name, meshWith(doc, name, sphere, material), [x, 0, 0]);
  }
  sphere.dispose();
  await write(doc, "ior-specular.glb");
}

// ---------------------------------------------------------------------------------------
// unknown-extension.glb: an extension realist does not read (its loader should report it):
// EXT_mesh_features (feature IDs, structural metadata for GIS and CAD tools; nothing to draw).

async function unknownExtension() {
  const doc = newDocument();
  const features = doc.createExtension(EXTMeshFeatures);
  const material = doc.createMaterial("plain-red").setBaseColorFactor([0.8, 0.1, 0.1, 1]).setMetallicFactor(0).setRoughnessFactor(0.5);
  const prim = spherePrimitive(doc).setMaterial(material);
  prim.setExtension("EXT_mesh_features", features.createFeatures().addFeatureID(features.createFeatureID().setFeatureCount(1)));
  place(doc, "plain-red", doc.createMesh("plain-red").addPrimitive(prim), [0, 0, 0]);
  await write(doc, "unknown-extension.glb");
}

// ---------------------------------------------------------------------------------------
// no-material.glb: a unit sphere whose primitive has no material (the specification's
// default material applies: white, metallic 1, roughness 1).

async function noMaterial() {
  const doc = newDocument();
  const prim = spherePrimitive(doc, 1.0, 64, 32);
  place(doc, "no-material", doc.createMesh("no-material").addPrimitive(prim), [0, 0, 0]);
  await write(doc, "no-material.glb");
}

// ---------------------------------------------------------------------------------------
// variants.glb: KHR_materials_variants. Two spheres, "left" at x = -0.5 and "right" at
// x = 0.5, both green by default (base colour (0.1, 0.7, 0.1)). Variant "red" maps both to a
// red material (0.8, 0.1, 0.1); variant "blue" maps only the left one to a blue material
// (0.1, 0.1, 0.8), so the right one keeps its default; variant "none" maps nothing. All
// dielectric, roughness 0.5.

async function variants() {
  const doc = newDocument();
  const ext = doc.createExtension(KHRMaterialsVariants);
  const mat = (name, color) => doc.createMaterial(name).setBaseColorFactor(color).setMetallicFactor(0).setRoughnessFactor(0.5);
  const green = mat("green", [0.1, 0.7, 0.1, 1]);
  const red = mat("red", [0.8, 0.1, 0.1, 1]);
  const blue = mat("blue", [0.1, 0.1, 0.8, 1]);
  const [vRed, vBlue] = [ext.createVariant("red"), ext.createVariant("blue")];
  ext.createVariant("none");
  const sphere = spherePrimitive(doc);
  for (const [name, x, mappings] of [
    ["left", -0.5, [[red, vRed], [blue, vBlue]]],
    ["right", 0.5, [[red, vRed]]],
  ]) {
    const prim = sphere.clone().setMaterial(green);
    const list = ext.createMappingList();
    for (const [material, variant] of mappings) {
      list.addMapping(ext.createMapping().setMaterial(material).addVariant(variant));
    }
    prim.setExtension("KHR_materials_variants", list);
    place(doc, name, doc.createMesh(name).addPrimitive(prim), [x, 0, 0]);
  }
  sphere.dispose();
  await write(doc, "variants.glb");
}

// ---------------------------------------------------------------------------------------
// The layers over a material, each file one sphere (radius 0.4 at the origin) with one
// material named as the file:
//   clearcoat.glb       base (0.8, 0.3, 0.1), metallic 0, roughness 0.6; clearcoat 1,
//                       clearcoatRoughness 0.3
//   clearcoat-only.glb  base black, KHR_materials_specular specularFactor 0 (the base reflects
//                       nothing); clearcoat 1, clearcoatRoughness 0.5
//   sheen.glb           base (0.1, 0.2, 0.6), metallic 0, roughness 0.8; sheenColor (1, 0.5,
//                       0.25), sheenRoughness 0.5
//   sheen-only.glb      base black, specularFactor 0; sheenColor (1, 0.5, 0.25),
//                       sheenRoughness 0.5

async function layers() {
  const files = [
    ["clearcoat", [0.8, 0.3, 0.1, 1], 0.6, false, (doc, m) =>
      m.setExtension("KHR_materials_clearcoat", doc.createExtension(KHRMaterialsClearcoat).createClearcoat().setClearcoatFactor(1).setClearcoatRoughnessFactor(0.3))],
    ["clearcoat-only", [0, 0, 0, 1], 0.5, true, (doc, m) =>
      m.setExtension("KHR_materials_clearcoat", doc.createExtension(KHRMaterialsClearcoat).createClearcoat().setClearcoatFactor(1).setClearcoatRoughnessFactor(0.5))],
    ["sheen", [0.1, 0.2, 0.6, 1], 0.8, false, (doc, m) =>
      m.setExtension("KHR_materials_sheen", doc.createExtension(KHRMaterialsSheen).createSheen().setSheenColorFactor([1, 0.5, 0.25]).setSheenRoughnessFactor(0.5))],
    ["sheen-only", [0, 0, 0, 1], 0.5, true, (doc, m) =>
      m.setExtension("KHR_materials_sheen", doc.createExtension(KHRMaterialsSheen).createSheen().setSheenColorFactor([1, 0.5, 0.25]).setSheenRoughnessFactor(0.5))],
  ];
  for (const [name, base, roughness, dark, extend] of files) {
    const doc = newDocument();
    const m = doc.createMaterial(name).setBaseColorFactor(base).setMetallicFactor(0).setRoughnessFactor(roughness);
    extend(doc, m);
    if (dark) {
      m.setExtension("KHR_materials_specular", doc.createExtension(KHRMaterialsSpecular).createSpecular().setSpecularFactor(0));
    }
    place(doc, name, doc.createMesh(name).addPrimitive(spherePrimitive(doc).setMaterial(m)), [0, 0, 0]);
    await write(doc, `${name}.glb`);
  }
}

// ---------------------------------------------------------------------------------------
// layer-textures.glb and layer-factors.glb: the layers' textures, and the same materials
// with each texture's value multiplied into its factor instead. Four spheres (radius 0.4)
// at x = -1.5, -0.5, 0.5, 1.5, each with its own material; every texture is a uniform 4 x 4
// PNG whose channels differ, so reading the wrong channel shows:
//   coat (x = -1.5)    base (0.8, 0.3, 0.1), roughness 0.6; clearcoat 1, roughness 0.8;
//                      clearcoatTexture and clearcoatRoughnessTexture = COAT_TEXEL (R 0.6,
//                      G 0.4): factors 0.6 and 0.32
//   sheen (x = -0.5)   base (0.1, 0.2, 0.6), roughness 0.8; sheenColor (1, 0.8, 0.6),
//                      sheenRoughness 0.9; sheenColorTexture (sRGB) and sheenRoughnessTexture
//                      = SHEEN_TEXEL: colour times the decoded RGB, roughness times A / 255
//   specular (x = 0.5) base (0.3, 0.3, 0.3), roughness 0.35; specularFactor 0.9,
//                      specularColorFactor (1, 2, 4); specularTexture and specularColorTexture
//                      (sRGB) = SPECULAR_TEXEL: factor times A / 255, colour times the decoded RGB
//   iridescence (1.5)  base (0.9, 0.9, 0.9), metallic 1, roughness 0.35; iridescence 1, IOR
//                      1.3, thickness 100 to 600 nm; iridescenceTexture and
//                      iridescenceThicknessTexture = IRIDESCENCE_TEXEL (R 0.8, G 128/255): factor
//                      0.8, thickness 100 + 500 G

export const COAT_TEXEL = [153, 102, 0, 255];
export const SHEEN_TEXEL = [200, 120, 60, 128];
export const SPECULAR_TEXEL = [230, 180, 90, 191];
export const IRIDESCENCE_TEXEL = [204, 128, 0, 255];

/** An 8-bit sRGB value decoded to linear (the sRGB transfer function). */
const srgbDecode = (b) => {
  const c = b / 255;
  return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
};

async function layerTextures(textured) {
  const doc = newDocument();
  const clearcoat = doc.createExtension(KHRMaterialsClearcoat);
  const sheen = doc.createExtension(KHRMaterialsSheen);
  const specular = doc.createExtension(KHRMaterialsSpecular);
  const iridescence = doc.createExtension(KHRMaterialsIridescence);
  const uniform = (name, texel) =>
    doc.createTexture(name).setImage(png(4, 4, () => texel)).setMimeType("image/png");
  const [C, S, P, I] = [COAT_TEXEL, SHEEN_TEXEL, SPECULAR_TEXEL, IRIDESCENCE_TEXEL];
  const coat = clearcoat.createClearcoat();
  const cloth = sheen.createSheen();
  const spec = specular.createSpecular();
  const film = iridescence.createIridescence().setIridescenceIOR(1.3).setIridescenceThicknessMinimum(100);
  if (textured) {
    const [ct, st, pt] = [uniform("coat", C), uniform("sheen", S), uniform("specular", P)];
    const it = uniform("iridescence", I);
    film.setIridescenceFactor(1).setIridescenceThicknessMaximum(600).setIridescenceTexture(it).setIridescenceThicknessTexture(it);
    coat.setClearcoatFactor(1).setClearcoatRoughnessFactor(0.8).setClearcoatTexture(ct).setClearcoatRoughnessTexture(ct);
    cloth.setSheenColorFactor([1, 0.8, 0.6]).setSheenRoughnessFactor(0.9).setSheenColorTexture(st).setSheenRoughnessTexture(st);
    spec.setSpecularFactor(0.9).setSpecularColorFactor([1, 2, 4]).setSpecularTexture(pt).setSpecularColorTexture(pt);
  } else {
    coat.setClearcoatFactor(C[0] / 255).setClearcoatRoughnessFactor((0.8 * C[1]) / 255);
    cloth
      .setSheenColorFactor([1, 0.8, 0.6].map((f, k) => f * srgbDecode(S[k])))
      .setSheenRoughnessFactor((0.9 * S[3]) / 255);
    spec.setSpecularFactor((0.9 * P[3]) / 255).setSpecularColorFactor([1, 2, 4].map((f, k) => f * srgbDecode(P[k])));
    film.setIridescenceFactor(I[0] / 255).setIridescenceThicknessMaximum(100 + (500 * I[1]) / 255);
  }
  const materials = [
    ["coat", [0.8, 0.3, 0.1, 1], 0.6, "KHR_materials_clearcoat", coat],
    ["sheen", [0.1, 0.2, 0.6, 1], 0.8, "KHR_materials_sheen", cloth],
    ["specular", [0.3, 0.3, 0.3, 1], 0.35, "KHR_materials_specular", spec],
    ["iridescence", [0.9, 0.9, 0.9, 1], 0.35, "KHR_materials_iridescence", film],
  ];
  const sphere = spherePrimitive(doc);
  materials.forEach(([name, base, roughness, ext, property], i) => {
    const metal = name === "iridescence" ? 1 : 0;
    const m = doc.createMaterial(name).setBaseColorFactor(base).setMetallicFactor(metal).setRoughnessFactor(roughness);
    m.setExtension(ext, property);
    place(doc, name, meshWith(doc, name, sphere, m), [i - 1.5, 0, 0]);
  });
  sphere.dispose();
  await write(doc, textured ? "layer-textures.glb" : "layer-factors.glb");
}

// ---------------------------------------------------------------------------------------
// coat-normal.glb: a clear coat with its own normal map over a flat quad. The 1 x 1 quad of
// quadPrimitive (facing +Z, TEXCOORD_0) with TANGENT (1, 0, 0, 1); material "coat-normal":
// base black, specularFactor 0 (the base reflects nothing), clearcoat 1, clearcoatRoughness
// 0.3, clearcoatNormalTexture a uniform 4 x 4 PNG of COAT_NORMAL_TEXEL: the normal tilted
// about 8 degrees towards +X (tangent space (0.137, 0.004, 0.992) once decoded).

export const COAT_NORMAL_TEXEL = [145, 128, 254, 255];

async function coatNormal() {
  const doc = newDocument();
  const prim = quadPrimitive(doc, { uv: true });
  prim.setAttribute("TANGENT", doc.createAccessor().setType("VEC4").setArray(new Float32Array([1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1])).setBuffer(buffer(doc)));
  const normal = doc.createTexture("coat-normal").setImage(png(4, 4, () => COAT_NORMAL_TEXEL)).setMimeType("image/png");
  const m = doc
    .createMaterial("coat-normal")
    .setBaseColorFactor([0, 0, 0, 1])
    .setMetallicFactor(0)
    .setRoughnessFactor(0.5)
    .setExtension("KHR_materials_specular", doc.createExtension(KHRMaterialsSpecular).createSpecular().setSpecularFactor(0))
    .setExtension(
      "KHR_materials_clearcoat",
      doc.createExtension(KHRMaterialsClearcoat).createClearcoat().setClearcoatFactor(1).setClearcoatRoughnessFactor(0.3).setClearcoatNormalTexture(normal),
    );
  place(doc, "coat-normal", doc.createMesh("coat-normal").addPrimitive(prim.setMaterial(m)), [0, 0, 0]);
  await write(doc, "coat-normal.glb");
}

// ---------------------------------------------------------------------------------------
// iridescence.glb: KHR_materials_iridescence on a sphere (radius 0.4 at the origin), material
// "film": base black, metallic 0, roughness 0.3 (so the dielectric's F0 is 0.04 and only the
// film's reflection shows); iridescence 1, IOR 1.8, thickness 100 to 450 nm (450 without a
// texture).

async function iridescenceFile() {
  const doc = newDocument();
  const film = doc
    .createExtension(KHRMaterialsIridescence)
    .createIridescence()
    .setIridescenceFactor(1)
    .setIridescenceIOR(1.8)
    .setIridescenceThicknessMinimum(100)
    .setIridescenceThicknessMaximum(450);
  const m = doc.createMaterial("film").setBaseColorFactor([0, 0, 0, 1]).setMetallicFactor(0).setRoughnessFactor(0.3);
  m.setExtension("KHR_materials_iridescence", film);
  place(doc, "film", doc.createMesh("film").addPrimitive(spherePrimitive(doc).setMaterial(m)), [0, 0, 0]);
  await write(doc, "iridescence.glb");
}

// ---------------------------------------------------------------------------------------
// anisotropy.glb and anisotropy-texture.glb: KHR_materials_anisotropy on a 2 x 2 quad in the
// XY plane facing +Z (vertices (-1, 1), (-1, -1), (1, -1), (1, 1), NORMAL +Z, TEXCOORD_0 (0, 0)
// top-left to (1, 1) bottom-right, TANGENT (1, 0, 0, 1): the tangent +X, the bitangent +Y).
// Material "brushed": base (0.9, 0.9, 0.9), metallic 1, roughness 0.2, and
//   anisotropy.glb          anisotropyStrength 0.5, anisotropyRotation π/6: the highlight
//                           stretches along 30° from +X towards +Y;
//   anisotropy-texture.glb  strength 1, rotation π/6, anisotropyTexture a uniform 4 x 4 PNG
//                           of ANISOTROPY_TEXEL: direction (128, 255) -> (0.004, 1), about
//                           90°, strength B 128 -> 0.502: in all 120° and 0.5.

export const ANISOTROPY_TEXEL = [128, 255, 128, 255];

async function anisotropy(textured) {
  const doc = newDocument();
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", [-1, 1, 0, -1, -1, 0, 1, -1, 0, 1, 1, 0]))
    .setAttribute("NORMAL", accessor(doc, "VEC3", [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1]))
    .setAttribute("TANGENT", doc.createAccessor().setType("VEC4").setArray(new Float32Array([1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1])).setBuffer(buffer(doc)))
    .setAttribute("TEXCOORD_0", accessor(doc, "VEC2", [0, 0, 0, 1, 1, 1, 1, 0]))
    .setIndices(indices(doc, [0, 1, 2, 0, 2, 3]));
  const a = doc.createExtension(KHRMaterialsAnisotropy).createAnisotropy().setAnisotropyRotation(Math.PI / 6);
  if (textured) {
    const t = doc.createTexture("direction").setImage(png(4, 4, () => ANISOTROPY_TEXEL)).setMimeType("image/png");
    a.setAnisotropyStrength(1).setAnisotropyTexture(t);
  } else {
    a.setAnisotropyStrength(0.5);
  }
  const m = doc.createMaterial("brushed").setBaseColorFactor([0.9, 0.9, 0.9, 1]).setMetallicFactor(1).setRoughnessFactor(0.2);
  m.setExtension("KHR_materials_anisotropy", a);
  place(doc, "brushed", doc.createMesh("brushed").addPrimitive(prim.setMaterial(m)), [0, 0, 0]);
  await write(doc, textured ? "anisotropy-texture.glb" : "anisotropy.glb");
}

// ---------------------------------------------------------------------------------------
// translucency.glb: KHR_materials_diffuse_transmission on the 1 x 1 quad of unlit.glb (facing
// +Z, TEXCOORD_0), material "leaf": base (0.2, 0.6, 0.2), metallic 0, roughness 0.5,
// specularFactor 0 (Fresnel 0: the base's diffuse terms alone), diffuseTransmissionFactor 0.6,
// diffuseTransmissionColorFactor (1, 0.8, 0.3).

async function translucency() {
  const doc = newDocument();
  const dt = doc
    .createExtension(KHRMaterialsDiffuseTransmission)
    .createDiffuseTransmission()
    .setDiffuseTransmissionFactor(0.6)
    .setDiffuseTransmissionColorFactor([1, 0.8, 0.3]);
  const m = doc
    .createMaterial("leaf")
    .setBaseColorFactor([0.2, 0.6, 0.2, 1])
    .setMetallicFactor(0)
    .setRoughnessFactor(0.5)
    .setExtension("KHR_materials_specular", doc.createExtension(KHRMaterialsSpecular).createSpecular().setSpecularFactor(0))
    .setExtension("KHR_materials_diffuse_transmission", dt);
  place(doc, "leaf", doc.createMesh("leaf").addPrimitive(quadPrimitive(doc, { uv: true }).setMaterial(m)), [0, 0, 0]);
  await write(doc, "translucency.glb");
}

// ---------------------------------------------------------------------------------------
// transmission-slab.glb: KHR_materials_transmission and KHR_materials_volume on the 1 x 1
// quad of unlit.glb (facing +Z), material "slab": base white, metallic 0, roughness 0,
// transmission 1, KHR_materials_ior 1 and specularFactor 0 (no refraction and no Fresnel:
// the light through it is all there is), thickness 0.5, attenuationColor (0.5, 0.7, 0.9),
// attenuationDistance 1: what lies behind is seen times attenuationColor^0.5.
//
// transmission.glb: a glass sphere (radius 0.4 at the origin), material "glass": base white,
// roughness 0.1, transmission 1, IOR 1.5 (the default), thickness 0.8 (its diameter),
// attenuationColor (0.9, 0.6, 0.3), attenuationDistance 0.5, KHR_materials_dispersion 2 (the
// channels refract at IOR 1.5 -+ 0.025); behind it an opaque sphere
// "behind" (radius 0.4 at (0.3, 0.2, -1.2), base (0.2, 0.4, 0.8), roughness 0.5).

async function transmissionFiles() {
  {
    const doc = newDocument();
    const m = doc
      .createMaterial("slab")
      .setBaseColorFactor([1, 1, 1, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(0)
      .setExtension("KHR_materials_transmission", doc.createExtension(KHRMaterialsTransmission).createTransmission().setTransmissionFactor(1))
      .setExtension("KHR_materials_ior", doc.createExtension(KHRMaterialsIOR).createIOR().setIOR(1))
      .setExtension("KHR_materials_specular", doc.createExtension(KHRMaterialsSpecular).createSpecular().setSpecularFactor(0))
      .setExtension(
        "KHR_materials_volume",
        doc.createExtension(KHRMaterialsVolume).createVolume().setThicknessFactor(0.5).setAttenuationColor([0.5, 0.7, 0.9]).setAttenuationDistance(1),
      );
    place(doc, "slab", doc.createMesh("slab").addPrimitive(quadPrimitive(doc, { uv: true }).setMaterial(m)), [0, 0, 0]);
    await write(doc, "transmission-slab.glb");
  }
  {
    const doc = newDocument();
    const glass = doc
      .createMaterial("glass")
      .setBaseColorFactor([1, 1, 1, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(0.1)
      .setExtension("KHR_materials_transmission", doc.createExtension(KHRMaterialsTransmission).createTransmission().setTransmissionFactor(1))
      .setExtension(
        "KHR_materials_volume",
        doc.createExtension(KHRMaterialsVolume).createVolume().setThicknessFactor(0.8).setAttenuationColor([0.9, 0.6, 0.3]).setAttenuationDistance(0.5),
      )
      .setExtension("KHR_materials_dispersion", doc.createExtension(KHRMaterialsDispersion).createDispersion().setDispersion(2));
    const behind = doc.createMaterial("behind").setBaseColorFactor([0.2, 0.4, 0.8, 1]).setMetallicFactor(0).setRoughnessFactor(0.5);
    const sphere = spherePrimitive(doc);
    place(doc, "glass", meshWith(doc, "glass", sphere, glass), [0, 0, 0]);
    place(doc, "behind", meshWith(doc, "behind", sphere, behind), [0.3, 0.2, -1.2]);
    sphere.dispose();
    await write(doc, "transmission.glb");
  }
  {
    // dispersion.glb: a dispersive slab before a ramp. "ramp": the 1 x 1 quad of unlit.glb
    // with COLOR_0 black on the left and white on the right, KHR_materials_unlit (its
    // colour is the vertex colour), scaled (4, 2, 1) and moved to z = -1: linear from 0 at
    // x = -2 to 1 at x = 2. "prism": the 1 x 1 quad at the origin, white, roughness 0,
    // transmission 1, IOR 1.5, specularFactor 0 (no Fresnel), thickness 0.5,
    // KHR_materials_dispersion 10 (the channels refract at 1.375, 1.5, 1.625).
    const doc = newDocument();
    const ramp = doc
      .createMaterial("ramp")
      .setBaseColorFactor([1, 1, 1, 1])
      .setExtension("KHR_materials_unlit", doc.createExtension(KHRMaterialsUnlit).createUnlit());
    const [L, R] = [[0, 0, 0], [1, 1, 1]];
    const rampNode = place(doc, "ramp", doc.createMesh("ramp").addPrimitive(quadPrimitive(doc, { colors: [L, L, R, R] }).setMaterial(ramp)), [0, 0, -1]);
    rampNode.setScale([4, 2, 1]);
    const prism = doc
      .createMaterial("prism")
      .setBaseColorFactor([1, 1, 1, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(0)
      .setExtension("KHR_materials_transmission", doc.createExtension(KHRMaterialsTransmission).createTransmission().setTransmissionFactor(1))
      .setExtension("KHR_materials_specular", doc.createExtension(KHRMaterialsSpecular).createSpecular().setSpecularFactor(0))
      .setExtension("KHR_materials_volume", doc.createExtension(KHRMaterialsVolume).createVolume().setThicknessFactor(0.5))
      .setExtension("KHR_materials_dispersion", doc.createExtension(KHRMaterialsDispersion).createDispersion().setDispersion(10));
    place(doc, "prism", doc.createMesh("prism").addPrimitive(quadPrimitive(doc, { uv: true }).setMaterial(prism)), [0, 0, 0]);
    await write(doc, "dispersion.glb");
  }
}

// ---------------------------------------------------------------------------------------
// instanced.glb: EXT_mesh_gpu_instancing, required. One node "forest" at (0, -0.5, 0) whose
// mesh "box" (a cube of side 0.4 around the origin: 24 vertices with face normals, 12
// triangles, material "bark", base colour (0.8, 0.5, 0.2), roughness 0.6) is drawn 12
// times, copy i = 4 r + c (r = 0..2, c = 0..3) with
//   TRANSLATION (c - 1.5, 0, -r)  ROTATION about +Y by 0.3 i radians
//   SCALE (s, s, s), s = 0.5 + 0.1 i, except copy 5 whose scale is (-0.9, 0.9, 0.9) (a
//   mirrored copy: its front faces are clockwise).
// The node has no other transform than its translation.

export const INSTANCED = Array.from({ length: 12 }, (_, i) => {
  const [r, c] = [Math.floor(i / 4), i % 4];
  const s = 0.5 + 0.1 * i;
  return {
    translation: [c - 1.5, 0, -r],
    rotation: [0, Math.sin(0.15 * i), 0, Math.cos(0.15 * i)],
    scale: i === 5 ? [-0.9, 0.9, 0.9] : [s, s, s],
  };
});

/** A cube of side `side` around the origin: four vertices per face with its normal. */
function cubePrimitive(doc, side) {
  const h = side / 2;
  const pos = [];
  const nrm = [];
  const idx = [];
  // Per face: normal n and two in-face axes u, v with u x v = n (counter-clockwise seen
  // from outside).
  const faces = [
    [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
    [[-1, 0, 0], [0, 0, 1], [0, 1, 0]],
    [[0, 1, 0], [0, 0, 1], [1, 0, 0]],
    [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
    [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
    [[0, 0, -1], [0, 1, 0], [1, 0, 0]],
  ];
  for (const [n, u, v] of faces) {
    const base = pos.length / 3;
    for (const [a, b] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
      for (let k = 0; k < 3; k++) pos.push(h * (n[k] + a * u[k] + b * v[k]));
      nrm.push(...n);
    }
    idx.push(base, base + 1, base + 2, base, base + 2, base + 3);
  }
  return doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", pos))
    .setAttribute("NORMAL", accessor(doc, "VEC3", nrm))
    .setIndices(indices(doc, idx));
}

async function instanced() {
  const doc = newDocument();
  const ext = doc.createExtension(EXTMeshGPUInstancing).setRequired(true);
  const bark = doc.createMaterial("bark").setBaseColorFactor([0.8, 0.5, 0.2, 1]).setMetallicFactor(0).setRoughnessFactor(0.6);
  const box = doc.createMesh("box").addPrimitive(cubePrimitive(doc, 0.4).setMaterial(bark));
  const node = place(doc, "forest", box, [0, -0.5, 0]);
  const batch = ext
    .createInstancedMesh()
    .setAttribute("TRANSLATION", accessor(doc, "VEC3", INSTANCED.flatMap((c) => c.translation)))
    .setAttribute("ROTATION", accessor(doc, "VEC4", INSTANCED.flatMap((c) => c.rotation)))
    .setAttribute("SCALE", accessor(doc, "VEC3", INSTANCED.flatMap((c) => c.scale)));
  node.setExtension("EXT_mesh_gpu_instancing", batch);
  await write(doc, "instanced.glb");
}

// ---------------------------------------------------------------------------------------
// pointer.glb: KHR_animation_pointer. One sphere ("ball", material "pulse", dielectric) and
// one animation "pulse" whose four channels are pointers:
//   /materials/0/pbrMetallicRoughness/baseColorFactor  LINEAR  t 0, 1, 2: red (0.8, 0.1, 0.1, 1),
//                                                               blue (0.1, 0.1, 0.8, 1), red
//   /materials/0/emissiveFactor                         STEP    t 0, 1: (0, 0, 0), (0.2, 0.2, 0)
//   /materials/0/pbrMetallicRoughness/roughnessFactor   LINEAR  t 0, 2: 0.2, 0.8
//   /nodes/0/translation                                LINEAR  t 0, 2: (0, 0, 0), (0.5, 0, 0)
//   /materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength  LINEAR t 0, 2: 1, 3
//   /extensions/KHR_lights_punctual/lights/0/intensity  LINEAR  t 0, 2: 10, 30 (candela)
//   /extensions/KHR_lights_punctual/lights/0/color      STEP    t 0, 1: white, (1, 0.5, 0.25)
//   /extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle  LINEAR t 0, 2: 0.5, 0.7
//   /cameras/0/perspective/yfov                         LINEAR  t 0, 2: 0.6, 0.9
// The spot light "lamp" (intensity 10, inner cone 0.2, outer 0.5) hangs at (0, 2, 1) pointing
// down; the camera "view" (yfov 0.6, near 0.1, far 100) stands at (0, 0, 3) looking at -Z.
// glTF-Transform 4.5 has no KHR_animation_pointer: it writes the document with ordinary
// channels on the node, and this script turns their targets into pointers in the JSON and
// packs the GLB (12-byte header, JSON and BIN chunks, as the GLB container specifies).

const POINTERS = [
  ["/materials/0/pbrMetallicRoughness/baseColorFactor", "VEC4", [0, 1, 2], [0.8, 0.1, 0.1, 1, 0.1, 0.1, 0.8, 1, 0.8, 0.1, 0.1, 1], "LINEAR"],
  ["/materials/0/emissiveFactor", "VEC3", [0, 1], [0, 0, 0, 0.2, 0.2, 0], "STEP"],
  ["/materials/0/pbrMetallicRoughness/roughnessFactor", "SCALAR", [0, 2], [0.2, 0.8], "LINEAR"],
  ["/nodes/0/translation", "VEC3", [0, 2], [0, 0, 0, 0.5, 0, 0], "LINEAR"],
  ["/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength", "SCALAR", [0, 2], [1, 3], "LINEAR"],
  ["/extensions/KHR_lights_punctual/lights/0/intensity", "SCALAR", [0, 2], [10, 30], "LINEAR"],
  ["/extensions/KHR_lights_punctual/lights/0/color", "VEC3", [0, 1], [1, 1, 1, 1, 0.5, 0.25], "STEP"],
  ["/extensions/KHR_lights_punctual/lights/0/spot/outerConeAngle", "SCALAR", [0, 2], [0.5, 0.7], "LINEAR"],
  ["/cameras/0/perspective/yfov", "SCALAR", [0, 2], [0.6, 0.9], "LINEAR"],
];

async function pointer() {
  const doc = newDocument();
  const strength = doc.createExtension(KHRMaterialsEmissiveStrength).createEmissiveStrength().setEmissiveStrength(1);
  const pulse = doc
    .createMaterial("pulse")
    .setBaseColorFactor([0.8, 0.1, 0.1, 1])
    .setMetallicFactor(0)
    .setRoughnessFactor(0.2)
    .setExtension("KHR_materials_emissive_strength", strength);
  const ball = place(doc, "ball", meshWith(doc, "ball", spherePrimitive(doc), pulse), [0, 0, 0]);
  const lamp = doc
    .createExtension(KHRLightsPunctual)
    .createLight("lamp")
    .setType(Light.Type.SPOT)
    .setIntensity(10)
    .setInnerConeAngle(0.2)
    .setOuterConeAngle(0.5);
  const down = [-Math.SQRT1_2, 0, 0, Math.SQRT1_2];
  doc.getRoot().getDefaultScene().addChild(doc.createNode("lamp").setTranslation([0, 2, 1]).setRotation(down).setExtension("KHR_lights_punctual", lamp));
  const camera = doc.createCamera("view").setType("perspective").setYFov(0.6).setZNear(0.1).setZFar(100);
  doc.getRoot().getDefaultScene().addChild(doc.createNode("view").setTranslation([0, 0, 3]).setCamera(camera));
  const anim = doc.createAnimation("pulse");
  for (const [, type, times, values, interpolation] of POINTERS) {
    const sampler = doc
      .createAnimationSampler()
      .setInput(accessor(doc, "SCALAR", times))
      .setOutput(accessor(doc, type, values))
      .setInterpolation(interpolation);
    anim.addSampler(sampler).addChannel(doc.createAnimationChannel().setTargetNode(ball).setTargetPath("translation").setSampler(sampler));
  }
  const { json, resources } = await io.writeJSON(doc, { format: "glb" });
  json.animations[0].channels.forEach((channel, i) => {
    channel.target = { path: "pointer", extensions: { KHR_animation_pointer: { pointer: POINTERS[i][0] } } };
  });
  json.extensionsUsed = [...(json.extensionsUsed ?? []), "KHR_animation_pointer"];
  // The GLB's binary chunk is the buffer: it has no URI.
  delete json.buffers[0].uri;
  const bin = Object.values(resources)[0];
  const pad = (bytes, fill) => {
    const out = new Uint8Array(Math.ceil(bytes.length / 4) * 4).fill(fill);
    out.set(bytes);
    return out;
  };
  const jsonChunk = pad(new TextEncoder().encode(JSON.stringify(json)), 0x20);
  const binChunk = pad(bin, 0);
  const total = 12 + 8 + jsonChunk.length + 8 + binChunk.length;
  const glb = new Uint8Array(total);
  const view = new DataView(glb.buffer);
  view.setUint32(0, 0x46546c67, true);
  view.setUint32(4, 2, true);
  view.setUint32(8, total, true);
  view.setUint32(12, jsonChunk.length, true);
  view.setUint32(16, 0x4e4f534a, true);
  glb.set(jsonChunk, 20);
  view.setUint32(20 + jsonChunk.length, binChunk.length, true);
  view.setUint32(24 + jsonChunk.length, 0x004e4942, true);
  glb.set(binChunk, 28 + jsonChunk.length);
  const file = path.join(dir, "pointer.glb");
  await writeFile(file, glb);
  console.log(`wrote ${file} (${glb.length} bytes)`);
}

// ---------------------------------------------------------------------------------------
// lights-punctual.glb: a stage with its own KHR_lights_punctual lights, in the spirit of the
// glTF sample "LightsPunctualLamp" and three.js's gt_lights_punctual_camera: three coloured
// dielectric spheres and a grey floor under a point light (candela), a spot light and a
// directional light (lux), intensities of the order such files use.

/** Rotation about +X by `deg` degrees, as a glTF quaternion. */
const aboutX = (deg) => [Math.sin((deg * Math.PI) / 360), 0, 0, Math.cos((deg * Math.PI) / 360)];

async function lightsPunctual() {
  const doc = newDocument();
  const ext = doc.createExtension(KHRLightsPunctual);
  const floor = doc.createMaterial("floor").setBaseColorFactor([0.5, 0.5, 0.5, 1]).setMetallicFactor(0).setRoughnessFactor(0.8);
  const ground = place(doc, "floor", doc.createMesh("floor").addPrimitive(quadPrimitive(doc).setMaterial(floor)), [0, -0.4, 0]);
  ground.setRotation(aboutX(-90)).setScale([6, 6, 1]);
  const sphere = spherePrimitive(doc);
  for (const [name, color, x] of [
    ["red", [0.8, 0.1, 0.1, 1], -1],
    ["green", [0.1, 0.8, 0.1, 1], 0],
    ["blue", [0.1, 0.1, 0.8, 1], 1],
  ]) {
    const material = doc.createMaterial(name).setBaseColorFactor(color).setMetallicFactor(0).setRoughnessFactor(0.4);
    place(doc, `sphere-${name}`, meshWith(doc, `sphere-${name}`, sphere, material), [x, 0, 0]);
  }
  sphere.dispose();
  const lamp = (name, light, translation, rotation) => {
    const node = doc.createNode(name).setTranslation(translation).setExtension("KHR_lights_punctual", light);
    if (rotation) node.setRotation(rotation);
    doc.getRoot().getDefaultScene().addChild(node);
  };
  lamp("point", ext.createLight("point").setType(Light.Type.POINT).setIntensity(15).setColor([1, 0.9, 0.8]), [0, 1.6, 1.2]);
  lamp(
    "spot",
    ext.createLight("spot").setType(Light.Type.SPOT).setIntensity(40).setColor([0.8, 0.9, 1]).setInnerConeAngle(0.3).setOuterConeAngle(0.6),
    [-1, 2.5, 0],
    aboutX(-90),
  );
  lamp("sun", ext.createLight("sun").setType(Light.Type.DIRECTIONAL).setIntensity(3), [0, 3, 3], aboutX(-45));
  await write(doc, "lights-punctual.glb");
}

// ---------------------------------------------------------------------------------------
// cornell-box.glb: the Cornell box (Cornell University's Program of Computer Graphics,
// its measured colours), axis-aligned and 5.5 units a side: a red left wall, a green right
// one, white floor, ceiling and back, a short and a tall white block, and a light panel
// under the ceiling (emissive, KHR_materials_emissive_strength). Every surface is a pure
// Lambertian reflector (KHR_materials_specular 0), so radiosity and the path tracer solve
// the same problem (the textbook's §9.6).

/** A quad primitive with corners `c` (counter-clockwise seen from the side it faces). */
function panel(doc, c) {
  const [a, b, , d] = c;
  const u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
  const v = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
  const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  const len = Math.hypot(...n);
  const nn = n.map((x) => x / len);
  return doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", c.flat()))
    .setAttribute("NORMAL", accessor(doc, "VEC3", [nn, nn, nn, nn].flat()))
    .setIndices(indices(doc, [0, 1, 2, 0, 2, 3]));
}

async function cornellBox() {
  const doc = newDocument();
  const specular = doc.createExtension(KHRMaterialsSpecular);
  const strength = doc.createExtension(KHRMaterialsEmissiveStrength);
  const lambert = (name, color) =>
    doc
      .createMaterial(name)
      .setBaseColorFactor([...color, 1])
      .setMetallicFactor(0)
      .setRoughnessFactor(1)
      .setExtension("KHR_materials_specular", specular.createSpecular().setSpecularFactor(0));
  const white = lambert("white", [0.725, 0.71, 0.68]);
  const red = lambert("red", [0.63, 0.065, 0.05]);
  const green = lambert("green", [0.14, 0.45, 0.091]);
  const light = lambert("light", [0.78, 0.78, 0.78])
    .setEmissiveFactor([1, 0.71, 0.24])
    .setExtension("KHR_materials_emissive_strength", strength.createEmissiveStrength().setEmissiveStrength(17));
  const h = 2.75;
  const top = 5.5;
  const wall = (name, corners, material) =>
    place(doc, name, doc.createMesh(name).addPrimitive(panel(doc, corners).setMaterial(material)), [0, 0, 0]);
  wall("floor", [[-h, 0, -h], [-h, 0, h], [h, 0, h], [h, 0, -h]], white);
  wall("ceiling", [[-h, top, -h], [h, top, -h], [h, top, h], [-h, top, h]], white);
  wall("back", [[-h, 0, -h], [h, 0, -h], [h, top, -h], [-h, top, -h]], white);
  wall("left", [[-h, 0, -h], [-h, top, -h], [-h, top, h], [-h, 0, h]], red);
  wall("right", [[h, 0, -h], [h, 0, h], [h, top, h], [h, top, -h]], green);
  const lx = 0.65;
  const lz = 0.525;
  wall("light", [[-lx, top - 0.01, -lz], [lx, top - 0.01, -lz], [lx, top - 0.01, lz], [-lx, top - 0.01, lz]], light);
  const block = cubePrimitive(doc, 1);
  const yaw = (deg) => [0, Math.sin((deg * Math.PI) / 360), 0, Math.cos((deg * Math.PI) / 360)];
  place(doc, "short-block", meshWith(doc, "short-block", block, white), [0.9, 0.825, 0.75])
    .setRotation(yaw(-17))
    .setScale([1.65, 1.65, 1.65]);
  place(doc, "tall-block", meshWith(doc, "tall-block", block, white), [-0.9, 1.65, -0.9])
    .setRotation(yaw(17))
    .setScale([1.65, 3.3, 1.65]);
  block.dispose();
  await write(doc, "cornell-box.glb");
}

await sphereGrid("sphere-grid.glb", [0.9, 0.55, 0.2, 1]);
await sphereGrid("sphere-grid-white.glb", [1, 1, 1, 1]);
await emissiveStrength();
await unlit();
await iorSpecular();
await unknownExtension();
await noMaterial();
await lightsPunctual();
await variants();
await pointer();
await instanced();
await layers();
await layerTextures(true);
await layerTextures(false);
await coatNormal();
await iridescenceFile();
await anisotropy(false);
await anisotropy(true);
await translucency();
await transmissionFiles();
await cornellBox();
