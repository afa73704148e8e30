#!/usr/bin/env bash
# Writes the texture-mapping test files of models/texture/ from a clean clone, then checks
# them (see models/README.md for what each file holds):
#
#   bash tests/texture-models/make.sh
#
# 1. make_models writes the inputs: grid-torus.obj + .mtl, uv-grid.png, grid-8.png,
#    emissive-corner.png, normal-bumps.png (it rewrites the rest of models/ with the same bytes);
# 2. obj2gltf converts the torus to grid-torus.glb (floats, no extensions);
# 3. gltfpack, with its default options, packs that into grid-torus-gltfpack.glb
#    (KHR_mesh_quantization, KHR_texture_transform);
# 4. make.mjs (glTF-Transform, mikktspace) writes transform-quads.glb, multi-uv.glb,
#    normal-plane.glb, normal-sphere.glb and sampler-quads.glb;
# 5. report.mjs prints each file's extensions and checks them and the sizes;
# 6. the Khronos glTF-Validator must find no error and no warning in any of them.
#
# The npm tools are pinned in package-lock.json. Every step is deterministic: running this
# twice gives byte-identical files.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=models/texture
bin=tests/texture-models/node_modules/.bin

echo "== make_models: the OBJ, MTL and PNG inputs"
cargo run --release --quiet --example make_models -- models/

echo "== npm ci (tests/texture-models, tests/validate-gltf)"
(cd tests/texture-models && npm ci --no-audit --no-fund --silent)
(cd tests/validate-gltf && npm ci --no-audit --no-fund --silent)

echo "== obj2gltf $("$bin/obj2gltf" --version): grid-torus.glb"
"$bin/obj2gltf" --binary --secure -i "$out/grid-torus.obj" -o "$out/grid-torus.glb"

echo "== $("$bin/gltfpack" -v 2>&1 | head -n 1), default options: grid-torus-gltfpack.glb"
"$bin/gltfpack" -i "$out/grid-torus.glb" -o "$out/grid-torus-gltfpack.glb"

echo "== glTF-Transform: make.mjs"
node tests/texture-models/make.mjs "$out"

echo "== report"
node tests/texture-models/report.mjs "$out"/*.glb

echo "== glTF-Validator"
node tests/validate-gltf/validate.mjs "$out"/*.glb
