#!/usr/bin/env bash
# Writes the animation test files of models/anim/ from a clean clone, then checks them (see
# models/README.md for what each file holds; tests/anim_models.rs poses them and compares
# with a direct evaluation of the same constants):
#
#   bash tests/anim-models/make.sh
#
# 1. make.mjs (glTF-Transform) writes samplers.glb, skin8.glb and morph-sparse.glb; every
#    number is computed in make.mjs itself (no cargo build, no other input);
# 2. it writes them a second time into a temporary folder: the bytes must be identical;
# 3. report.mjs prints each file's animations, skins and morph targets and checks that each
#    covers what it is made for and stays small;
# 4. the Khronos glTF-Validator must find no error and no warning in any of them.
#
# The npm tools are pinned in package-lock.json (tests/anim-models and tests/validate-gltf).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=models/anim

echo "== npm ci (tests/anim-models, tests/validate-gltf)"
(cd tests/anim-models && npm ci --no-audit --no-fund --silent)
(cd tests/validate-gltf && npm ci --no-audit --no-fund --silent)

echo "== glTF-Transform: make.mjs"
mkdir -p "$out"
node tests/anim-models/make.mjs "$out"

echo "== determinism: a second run into a temporary folder writes the same bytes"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
node tests/anim-models/make.mjs "$tmp" >/dev/null
for f in "$tmp"/*; do
  cmp "$f" "$out/$(basename "$f")"
  echo "same: $(basename "$f")"
done

echo "== report"
node tests/anim-models/report.mjs "$out"/*.glb

echo "== glTF-Validator"
node tests/validate-gltf/validate.mjs "$out"/*.glb
