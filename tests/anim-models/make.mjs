// Writes the animation test files of models/anim/ (see models/README.md for what each holds
// and make.sh for the whole pipeline):
//
//   node make.mjs DIR
//
// writes samplers.glb, skin8.glb and morph-sparse.glb into DIR. Every number is computed here
// (no other input) and written with glTF-Transform; nothing depends on the clock or on
// randomness, so running it twice gives the same bytes. tests/anim_models.rs mirrors the
// constants below (keyframes, rest transforms, bind matrices, weights, morph deltas) and
// evaluates the animations directly: keep the two in step.

import { writeFile } from "node:fs/promises";
import path from "node:path";
import { Document, NodeIO, VERSION } from "@gltf-transform/core";

const [dir] = process.argv.slice(2);
if (!dir) {
  console.error("usage: node make.mjs DIR");
  process.exit(2);
}

const io = new NodeIO();

/** A new document with one buffer and one default scene, its asset naming this script. */
function newDocument() {
  const doc = new Document();
  doc.getRoot().getAsset().generator = `realist tests/anim-models/make.mjs (glTF-Transform ${VERSION})`;
  doc.createBuffer();
  doc.getRoot().setDefaultScene(doc.createScene("scene"));
  return doc;
}

const buffer = (doc) => doc.getRoot().listBuffers()[0];
const scene = (doc) => doc.getRoot().getDefaultScene();

/** An accessor of `type` holding `values` (a flat list) as `Array` (Float32Array by default). */
function accessor(doc, type, values, Array = Float32Array) {
  return doc.createAccessor().setType(type).setArray(new Array(values)).setBuffer(buffer(doc));
}

/** The unit quaternion (x, y, z, w) turning `deg` degrees about `axis` (normalised here). */
function quat(axis, deg) {
  const len = Math.hypot(...axis);
  const half = (deg * Math.PI) / 360;
  const s = Math.sin(half) / len;
  return [axis[0] * s, axis[1] * s, axis[2] * s, Math.cos(half)];
}

/**
 * A sampler of `anim`: keyframe `times`, `values` (one array of `width` numbers per key) and,
 * for CUBICSPLINE, `inTangents` and `outTangents` (the same shape), stored in glTF's order
 * (in-tangent, value, out-tangent per key). `type` is the output accessor's type; `Array` its
 * storage (a normalised integer array makes a normalised accessor).
 */
function sampler(doc, anim, { interpolation, times, values, inTangents, outTangents, type, Array = Float32Array }) {
  const flat = interpolation === "CUBICSPLINE"
    ? values.flatMap((v, k) => [...inTangents[k], ...v, ...outTangents[k]])
    : values.flat();
  const output = accessor(doc, type, flat, Array);
  if (Array !== Float32Array) output.setNormalized(true);
  const s = doc
    .createAnimationSampler()
    .setInput(accessor(doc, "SCALAR", times))
    .setOutput(output)
    .setInterpolation(interpolation);
  anim.addSampler(s);
  return s;
}

/** Drives `path` of `node` by a new sampler of `anim` (see `sampler`). */
function channel(doc, anim, node, path, spec) {
  const s = sampler(doc, anim, spec);
  anim.addChannel(doc.createAnimationChannel().setTargetNode(node).setTargetPath(path).setSampler(s));
}

async function write(doc, name) {
  const file = path.join(dir, name);
  await writeFile(file, await io.writeBinary(doc));
  console.log(`wrote ${file}`);
}

// ---------------------------------------------------------------------------------------
// samplers.glb: one animation per (property, interpolation), each one channel on one node.

/** Keyframe times of each property (non-uniform spacing, the first key after 0). */
const TIMES = {
  translation: [0.5, 0.75, 1.5, 2.5],
  rotation: [0.25, 1.0, 1.25, 3.0],
  scale: [0.4, 0.6, 1.6, 2.0],
  weights: [0.2, 0.7, 0.9, 2.2],
};

/** STEP and LINEAR values. The LINEAR rotation keys 1 -> 2 and 2 -> 3 have negative dot
 * products (key 2 is written with the opposite sign): slerp must take the short way. */
const VALUES = {
  translation: [[0, 0, 0], [0.5, 0.25, 0], [0.25, -0.5, 0.5], [-0.5, 0, 0.25]],
  rotation: [quat([0, 0, 1], 0), quat([0, 1, 0], 90), quat([1, 1, 0], 120).map((x) => -x), quat([0, 0, 1], -45)],
  scale: [[1, 1, 1], [2, 0.5, 1], [0.5, 1.5, 2], [1, 2, 0.25]],
  weights: [[0, 0], [1, 0.25], [0.5, 1], [-0.25, 0.5]],
};

/** CUBICSPLINE values and tangents (every tangent non-zero, the unused first in-tangent and
 * last out-tangent included). The rotation keys are unit quaternions with positive dot
 * products between neighbours. */
const CUBIC = {
  translation: {
    values: [[0, 0, 0], [0.5, 0.25, 0], [0.25, -0.5, 0.5], [-0.5, 0, 0.25]],
    inTangents: [[0.3, 0, 0.1], [1, -1, 0.5], [-0.5, 0.25, 1], [0.2, 0.2, 0.2]],
    outTangents: [[0.5, 1, -0.5], [-1, 0.5, 0.25], [0.75, -0.25, 0], [0.1, 0, 0]],
  },
  rotation: {
    values: [quat([0, 0, 1], 0), quat([0, 1, 0], 60), quat([1, 0, 1], 90), quat([1, 0, 0], 30)],
    inTangents: [[0.1, 0, 0, 0], [0.2, -0.1, 0.3, 0.05], [-0.3, 0.2, 0.1, -0.1], [0.1, 0.1, 0, 0]],
    outTangents: [[0.3, 0.4, -0.2, 0], [0.25, 0.1, -0.3, 0.1], [0.2, -0.4, 0.1, 0.05], [0, 0, 0.1, 0]],
  },
  scale: {
    values: [[1, 1, 1], [2, 0.5, 1], [0.5, 1.5, 2], [1, 2, 0.25]],
    inTangents: [[0.5, 0, 0], [1, -1, 2], [-2, 1, 0.5], [0, 0.5, 1]],
    outTangents: [[1, 2, -1], [-0.5, 0.5, 1], [1.5, -1, 0], [0.25, 0, 0]],
  },
  weights: {
    values: [[0, 0], [1, 0.25], [0.5, 1], [-0.25, 0.5]],
    inTangents: [[0.5, 0.5], [2, -1], [-1.5, 0.5], [1, 1]],
    outTangents: [[1, 2], [-2, 1], [0.5, -1], [0.5, 0]],
  },
};

/** The rest TRS of every animated node (the animated property replaces one part). */
const REST = { translation: [0.1, 0.2, 0.3], rotation: quat([0, 0, 1], 30), scale: [1, 1.5, 0.75] };

/** Morph targets of the weights nodes' mesh (deltas of its three vertices) and its weights. */
const TRIANGLE = [[0.2, 0, 0], [0, 0.3, 0], [0, 0, 0.1]];
const MORPH_TARGETS = [
  [[0, 0.2, 0], [0.1, 0, 0], [0, 0, 0]],
  [[0, 0, 0.3], [0, -0.1, 0], [0.2, 0.2, 0]],
];
const MORPH_DEFAULT_WEIGHTS = [0.25, 0.5];

/** `rotation-LINEAR-short`: the LINEAR rotation keys stored as normalised i16 (round(32767 x)). */
const short = (q) => q.map((x) => Math.round(x * 32767));

async function samplers() {
  const doc = newDocument();
  const triangle = () =>
    doc
      .createPrimitive()
      .setAttribute("POSITION", accessor(doc, "VEC3", TRIANGLE.flat()))
      .setIndices(accessor(doc, "SCALAR", [0, 1, 2], Uint16Array));
  const plain = doc.createMesh("triangle").addPrimitive(triangle());
  const morphPrim = triangle();
  MORPH_TARGETS.forEach((deltas, t) => {
    morphPrim.addTarget(doc.createPrimitiveTarget(`target-${t}`).setAttribute("POSITION", accessor(doc, "VEC3", deltas.flat())));
  });
  const morphed = doc.createMesh("morph-triangle").addPrimitive(morphPrim).setWeights(MORPH_DEFAULT_WEIGHTS);

  const animations = [];
  for (const property of ["translation", "rotation", "scale", "weights"]) {
    for (const interpolation of ["STEP", "LINEAR", "CUBICSPLINE"]) {
      animations.push({ name: `${property}-${interpolation}`, property, interpolation });
    }
  }
  animations.push({ name: "rotation-LINEAR-short", property: "rotation", interpolation: "LINEAR", short: true });

  animations.forEach(({ name, property, interpolation, short: isShort }, k) => {
    // slot-k: a static parent placing the animated node on a 4-wide grid.
    const slot = doc.createNode(`slot-${k}`).setTranslation([1.5 * (k % 4), -1.5 * Math.floor(k / 4), 0]);
    scene(doc).addChild(slot);
    const node = doc
      .createNode(name)
      .setTranslation(REST.translation)
      .setRotation(REST.rotation)
      .setScale(REST.scale)
      .setMesh(property === "weights" ? morphed : plain);
    slot.addChild(node);
    const anim = doc.createAnimation(name);
    const type = { translation: "VEC3", rotation: "VEC4", scale: "VEC3", weights: "SCALAR" }[property];
    const times = TIMES[property];
    if (interpolation === "CUBICSPLINE") {
      channel(doc, anim, node, property, { interpolation, times, type, ...CUBIC[property] });
    } else if (isShort) {
      channel(doc, anim, node, property, { interpolation, times, type, values: VALUES.rotation.map(short), Array: Int16Array });
    } else {
      channel(doc, anim, node, property, { interpolation, times, type, values: VALUES[property] });
    }
  });
  await write(doc, "samplers.glb");
}

// ---------------------------------------------------------------------------------------
// skin8.glb: a bar skinned to a chain of 8 joints, 8 influences per vertex.

const RINGS = 15; // y = 0, 0.25, ..., 3.5
const RING_STEP = 0.25;
const CORNERS = [[-0.15, -0.15], [0.15, -0.15], [0.15, 0.15], [-0.15, 0.15]];
const JOINTS = 8;
const JOINT_STEP = 0.5; // bind position of joint j: (0, 0.5 j, 0)
const ARMATURE = { translation: [0.25, 0, 0], rotation: quat([0, 1, 0], 30) };
const JOINT_REST_ROTATION = quat([0, 0, 1], 8); // every joint's rest rotation
const BEND_TIMES = [0, 1, 2.5, 4];
const BEND_DEGREES = [0, 20, -15, 10]; // joint j turns by these x (1 + j/8), about Z (even j) or X (odd j)
const ROOT_TRANSLATIONS = [[0, 0, 0], [0.3, 0, 0], [0.3, 0.2, -0.1], [0, 0, 0]]; // joint 0, LINEAR
const J3_SCALES = [[1, 1, 1], [1.5, 1, 0.75], [0.8, 1.2, 1], [1, 1, 1]]; // joint 3, STEP

/** The 8 weights (summing to 1) of the vertex at ring `r`, corner `c`, per joint 0..7. */
function skinWeights(r, c) {
  const y = r * RING_STEP;
  const raw = [];
  for (let j = 0; j < JOINTS; j++) {
    const d = (y - j * JOINT_STEP) / 0.6;
    raw.push(Math.exp(-d * d) + 0.02 + 0.03 * ((j + c) % 4));
  }
  const sum = raw.reduce((a, b) => a + b, 0);
  return raw.map((w) => w / sum);
}

async function skin8() {
  const doc = newDocument();
  const positions = [];
  const joints0 = [];
  const joints1 = [];
  const weights0 = [];
  const weights1 = [];
  for (let r = 0; r < RINGS; r++) {
    for (let c = 0; c < 4; c++) {
      positions.push(CORNERS[c][0], r * RING_STEP, CORNERS[c][1]);
      // Joints by decreasing weight: the 4 heaviest in set 0, the other 4 in set 1.
      const w = skinWeights(r, c);
      const order = [...w.keys()].sort((a, b) => w[b] - w[a] || a - b);
      joints0.push(...order.slice(0, 4));
      joints1.push(...order.slice(4));
      weights0.push(...order.slice(0, 4).map((j) => w[j]));
      weights1.push(...order.slice(4).map((j) => w[j]));
    }
  }
  const indices = [];
  for (let r = 0; r + 1 < RINGS; r++) {
    for (let c = 0; c < 4; c++) {
      const [a, b] = [4 * r + c, 4 * r + ((c + 1) % 4)];
      const [d, e] = [a + 4, b + 4];
      indices.push(a, d, b, b, d, e);
    }
  }
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", positions))
    .setAttribute("JOINTS_0", accessor(doc, "VEC4", joints0, Uint8Array))
    .setAttribute("WEIGHTS_0", accessor(doc, "VEC4", weights0))
    .setAttribute("JOINTS_1", accessor(doc, "VEC4", joints1, Uint16Array))
    .setAttribute("WEIGHTS_1", accessor(doc, "VEC4", weights1))
    .setIndices(accessor(doc, "SCALAR", indices, Uint16Array));
  const mesh = doc.createMesh("bar").addPrimitive(prim);

  const armature = doc.createNode("armature").setTranslation(ARMATURE.translation).setRotation(ARMATURE.rotation);
  const chain = [];
  for (let j = 0; j < JOINTS; j++) {
    const node = doc
      .createNode(`joint-${j}`)
      .setTranslation([0, j === 0 ? 0 : JOINT_STEP, 0])
      .setRotation(JOINT_REST_ROTATION);
    (j === 0 ? armature : chain[j - 1]).addChild(node);
    chain.push(node);
  }
  // Inverse bind matrices: the inverse of the straight bind pose, translate(0, 0.5 j, 0).
  const ibm = [];
  for (let j = 0; j < JOINTS; j++) ibm.push(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -j * JOINT_STEP, 0, 1);
  const skin = doc.createSkin("chain").setSkeleton(chain[0]).setInverseBindMatrices(accessor(doc, "MAT4", ibm));
  chain.forEach((j) => skin.addJoint(j));
  const bar = doc.createNode("bar").setMesh(mesh).setSkin(skin);
  scene(doc).addChild(bar).addChild(armature);

  const anim = doc.createAnimation("bend");
  chain.forEach((node, j) => {
    const axis = j % 2 === 0 ? [0, 0, 1] : [1, 0, 0];
    const values = BEND_DEGREES.map((deg) => quat(axis, deg * (1 + j / 8)));
    channel(doc, anim, node, "rotation", { interpolation: "LINEAR", times: BEND_TIMES, values, type: "VEC4" });
  });
  channel(doc, anim, chain[0], "translation", { interpolation: "LINEAR", times: BEND_TIMES, values: ROOT_TRANSLATIONS, type: "VEC3" });
  channel(doc, anim, chain[3], "scale", { interpolation: "STEP", times: BEND_TIMES, values: J3_SCALES, type: "VEC3" });
  await write(doc, "skin8.glb");
}

// ---------------------------------------------------------------------------------------
// morph-sparse.glb: a 16 x 16 grid with three morph targets stored as sparse accessors.

const GRID = 16;
const CELL = 0.1;
/** Vertex v = 16 j + i at ((i - 7.5) 0.1, 0, (j - 7.5) 0.1). */
const gridPosition = (v) => [((v % GRID) - 7.5) * CELL, 0, (Math.floor(v / GRID) - 7.5) * CELL];

/** Target 0 ("bump"): vertices within 3 cells of (i, j) = (6, 5) rise, their normals tilt. */
function bump(v) {
  const [i, j] = [v % GRID, Math.floor(v / GRID)];
  const d = Math.hypot(i - 6, j - 5);
  if (d > 3) return { dp: [0, 0, 0], dn: [0, 0, 0] };
  return { dp: [0, 0.3 * (1 - d / 3.5), 0], dn: [0.1 * (i - 6), 0, 0.1 * (j - 5)] };
}
/** Target 1 ("edge"): the last row (j = 15, vertices 240..255) slides along +X and +Z. */
const edge = (v) => (v >= GRID * (GRID - 1) ? [0.02 * (v % GRID), 0, 0.2] : [0, 0, 0]);
/** Target 2 ("scatter"): every vertex with v mod 7 = 3 drops and moves along +Z. */
const scatter = (v) => (v % 7 === 3 ? [0, -0.1 - 0.01 * (v % 5), 0.05] : [0, 0, 0]);
const SPARSE_DEFAULT_WEIGHTS = [0.5, 0.25, 0.75];
const SPARSE_LINEAR = { times: [0.5, 1.0, 2.25], values: [[0, 0, 0], [1, 0.5, 0.25], [0.25, 1, -0.5]] };
const SPARSE_CUBIC = {
  times: [0.0, 0.75, 1.0, 2.0],
  values: [[0, 0, 0], [1, 0.5, 0.25], [0.25, 1, -0.5], [0.5, 0, 1]],
  inTangents: [[1, 0, 0], [2, -1, 1], [-1, 0.5, 2], [0.5, 1, -1]],
  outTangents: [[0.5, 1, -0.5], [-1, 2, 0.5], [1, -0.5, 1], [0, 0, 0.5]],
};

async function morphSparse() {
  const doc = newDocument();
  const count = GRID * GRID;
  const vertices = [...Array(count).keys()];
  const indices = [];
  for (let j = 0; j + 1 < GRID; j++) {
    for (let i = 0; i + 1 < GRID; i++) {
      const a = j * GRID + i;
      indices.push(a, a + GRID, a + 1, a + 1, a + GRID, a + GRID + 1);
    }
  }
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", accessor(doc, "VEC3", vertices.flatMap(gridPosition)))
    .setAttribute("NORMAL", accessor(doc, "VEC3", vertices.flatMap(() => [0, 1, 0])))
    .setIndices(accessor(doc, "SCALAR", indices, Uint16Array));
  const sparse = (values) => accessor(doc, "VEC3", values).setSparse(true);
  prim.addTarget(
    doc
      .createPrimitiveTarget("bump")
      .setAttribute("POSITION", sparse(vertices.flatMap((v) => bump(v).dp)))
      .setAttribute("NORMAL", sparse(vertices.flatMap((v) => bump(v).dn))),
  );
  prim.addTarget(doc.createPrimitiveTarget("edge").setAttribute("POSITION", sparse(vertices.flatMap(edge))));
  prim.addTarget(doc.createPrimitiveTarget("scatter").setAttribute("POSITION", sparse(vertices.flatMap(scatter))));
  const mesh = doc.createMesh("grid").addPrimitive(prim).setWeights(SPARSE_DEFAULT_WEIGHTS);
  const node = doc.createNode("grid").setMesh(mesh);
  scene(doc).addChild(node);

  const linear = doc.createAnimation("weights-LINEAR");
  channel(doc, linear, node, "weights", { interpolation: "LINEAR", type: "SCALAR", ...SPARSE_LINEAR });
  const cubic = doc.createAnimation("weights-CUBICSPLINE");
  channel(doc, cubic, node, "weights", { interpolation: "CUBICSPLINE", type: "SCALAR", ...SPARSE_CUBIC });
  await write(doc, "morph-sparse.glb");
}

await samplers();
await skin8();
await morphSparse();
