#!/usr/bin/env bash
# Renders the three.js references in tests/threejs/refs/ from a clean clone:
#
#   apt-get install chromium        # Debian's Chromium (software WebGL through SwiftShader)
#   bash tests/threejs/make-refs.sh
#
# three.js r187 and playwright-core are pinned in package-lock.json; render.mjs loads the
# model with three's GLTFLoader, lights it with the given directional lights (lux, three's
# physical units), renders one frame without tone mapping to sRGB and writes the canvas.
# tests/threejs.rs renders the same views with realist and compares. Rendering is
# deterministic (the same PNG bytes twice).
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund --silent
mkdir -p refs
# The specification's default material (white, metallic 1, roughness 1) on a unit sphere
# without a material, under a 1-lux directional light from the camera.
node render.mjs --quiet --model ../../models/pbr/no-material.glb --out refs/no-material-headon.png \
  --size 256x256 --eye 0,0,3 --target 0,0,0 --yfov 45 --light directional:0,0,-1:1 \
  --tone none --background 0,0,0
echo "wrote tests/threejs/refs/no-material-headon.png"
# The layers (KHR_materials_clearcoat, KHR_materials_sheen) on spheres of radius 0.4, head-on
# under a 1-lux directional light from the camera and a uniform surround of radiance 0.25.
for m in clearcoat sheen; do
  node render.mjs --quiet --model ../../models/pbr/$m.glb --out refs/$m-headon.png \
    --size 256x256 --eye 0,0,1.5 --target 0,0,0 --yfov 45 --light directional:0,0,-1:1 \
    --env uniform:0.25 --tone none --background 0,0,0
  echo "wrote tests/threejs/refs/$m-headon.png"
done
# The layers' textures (layer-textures.glb) and the same materials with the texels
# multiplied into the factors (layer-factors.glb): four spheres at x = -1.5 to 1.5 seen from
# (0, 0, 4) with a vertical field of view of 2 atan(1/8) (80 pixels to the unit), under the
# same light and surround.
for m in layer-textures layer-factors; do
  node render.mjs --quiet --model ../../models/pbr/$m.glb --out refs/$m-headon.png \
    --size 320x80 --eye 0,0,4 --target 0,0,0 --yfov 14.250032697803595 \
    --light directional:0,0,-1:1 --env uniform:0.25 --tone none --background 0,0,0
  echo "wrote tests/threejs/refs/$m-headon.png"
done
# A clear coat's own normal map on a quad seen from (0, 0, 1.5), 0.9 rad.
node render.mjs --quiet --model ../../models/pbr/coat-normal.glb --out refs/coat-normal-headon.png \
  --size 129x129 --eye 0,0,1.5 --target 0,0,0 --yfov 51.56620156177409 \
  --light directional:0,0,-1:1 --env uniform:0.25 --tone none --background 0,0,0
echo "wrote tests/threejs/refs/coat-normal-headon.png"
# A thin film (KHR_materials_iridescence) on a black sphere, as the layered spheres above.
node render.mjs --quiet --model ../../models/pbr/iridescence.glb --out refs/iridescence-headon.png \
  --size 256x256 --eye 0,0,1.5 --target 0,0,0 --yfov 45 --light directional:0,0,-1:1 \
  --env uniform:0.25 --tone none --background 0,0,0
echo "wrote tests/threejs/refs/iridescence-headon.png"
# KHR_materials_anisotropy on a 2 x 2 metal quad seen from (0, 0, 1.2), 1.4 rad.
for m in anisotropy anisotropy-texture; do
  node render.mjs --quiet --model ../../models/pbr/$m.glb --out refs/$m-headon.png \
    --size 129x129 --eye 0,0,1.2 --target 0,0,0 --yfov 80.21409131831524 \
    --light directional:0,0,-1:1 --env uniform:0.25 --tone none --background 0,0,0
  echo "wrote tests/threejs/refs/$m-headon.png"
done
# KHR_materials_transmission, KHR_materials_volume and KHR_materials_dispersion: a glass
# sphere in front of an opaque one on a grey background (0.3 in sRGB), from (0, 0, 2).
node render.mjs --quiet --model ../../models/pbr/transmission.glb --out refs/transmission-headon.png \
  --size 256x256 --eye 0,0,2 --target 0,0,0 --yfov 45 --light directional:0,0,-1:1 \
  --env uniform:0.25 --tone none --background 0.3,0.3,0.3
echo "wrote tests/threejs/refs/transmission-headon.png"
# A transmissive slab (Beer's law) and a dispersive one before a ramp, seen from aside:
# (1.2, 0.3, 2) towards the origin, 0.6 rad, on a background of (0.6, 0.5, 0.4) in sRGB.
for m in transmission-slab dispersion; do
  node render.mjs --quiet --model ../../models/pbr/$m.glb --out refs/$m-aside.png \
    --size 129x129 --eye 1.2,0.3,2 --target 0,0,0 --yfov 34.37746770784939 \
    --light directional:0,0,-1:1 --env uniform:0.25 --tone none --background 0.6,0.5,0.4
  echo "wrote tests/threejs/refs/$m-aside.png"
done
