#!/usr/bin/env bash
# Writes the physically based material test files of models/pbr/ from a clean clone, then
# checks them (see models/README.md for what each file holds):
#
#   bash tests/pbr-models/make.sh
#
# 1. make.mjs (glTF-Transform) writes sphere-grid.glb, sphere-grid-white.glb,
#    emissive-strength.glb, unlit.glb (with its texture unlit-4x4.png), ior-specular.glb,
#    unknown-extension.glb, no-material.glb, lights-punctual.glb, variants.glb, pointer.glb,
#    instanced.glb, clearcoat.glb, clearcoat-only.glb, sheen.glb, sheen-only.glb,
#    layer-textures.glb, layer-factors.glb, coat-normal.glb, iridescence.glb, anisotropy.glb
#    anisotropy-texture.glb, translucency.glb, transmission-slab.glb, transmission.glb and
#    dispersion.glb and cornell-box.glb; all
#    geometry and the PNGs are
#    computed in make.mjs itself (no
#    cargo build, no other input);
# 2. it writes them a second time into a temporary folder: the bytes must be identical;
# 3. report.mjs prints each file's extensions and materials and checks the extensions, the
#    sphere grids' layout and the sizes;
# 4. the Khronos glTF-Validator must find no error and no warning in any of them.
#
# The npm tools are pinned in package-lock.json (tests/pbr-models and tests/validate-gltf).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=models/pbr

echo "== npm ci (tests/pbr-models, tests/validate-gltf)"
(cd tests/pbr-models && npm ci --no-audit --no-fund --silent)
(cd tests/validate-gltf && npm ci --no-audit --no-fund --silent)

echo "== glTF-Transform: make.mjs"
mkdir -p "$out"
node tests/pbr-models/make.mjs "$out"

echo "== determinism: a second run into a temporary folder writes the same bytes"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
node tests/pbr-models/make.mjs "$tmp" >/dev/null
for f in "$tmp"/*; do
  cmp "$f" "$out/$(basename "$f")"
  echo "same: $(basename "$f")"
done

echo "== report"
node tests/pbr-models/report.mjs "$out"/*.glb

echo "== glTF-Validator"
node tests/validate-gltf/validate.mjs "$out"/*.glb
