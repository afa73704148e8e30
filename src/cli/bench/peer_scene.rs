//! The llvmpipe peer harness's scene (`../shared/peer/meshes.py` and `bench_llvmpipe.py`),
//! rebuilt number for number so the two renderers draw the same triangles:
//!
//! - OBJ read as `meshes.py` reads it: `v`, `vt` and `f` lines only, faces fan-triangulated
//!   from their first corner, and with UVs (every face corner has a `vt`) each distinct
//!   `(v, vt)` pair one vertex, numbered in sorted pair order (`np.unique`); without UVs the
//!   file's vertices as they are, unused ones included (they count in the bounding box).
//! - `sphere:N`: `uv_sphere(stacks, 2 * stacks)` with `2 * stacks * slices` about `N`
//!   (`sphere1m` is `sphere:1000000` = 500 x 1000), poles and seam duplicated as there.
//! - Normalised: centre = midpoint of the bounding box, scaled so the farthest vertex is at
//!   distance 1 (in `f32`, as numpy does).
//! - Smooth normals: the normalised sum of the unnormalised face normals (area-weighted),
//!   per vertex of the re-indexed mesh (so a UV seam is a normal seam, as in the peer).
//!
//! realist's own loader is not used: it drops unused vertices, averages normals across UV
//! seams and splits quads along the better diagonal, each of which changes the picture.

use std::path::Path;

use anyhow::{bail, Context, Result};
use glam::{Mat4, Vec2, Vec3, Vec4};

use realist::mesh::{Channel, Mesh, MeshData, NormalPolicy};
use realist::scene::{Camera, Instance, Light, Material, Scene, Style, TextureSlot};
use realist::texture::Texture;

/// Largest `sphere:N` (20 million triangles: about 1.5 GB once prepared).
pub(super) const MAX_SPHERE_TRIANGLES: u64 = 20_000_000;
/// Smallest `sphere:N` (2 stacks x 4 slices).
pub(super) const MIN_SPHERE_TRIANGLES: u64 = 16;

/// The peer's light direction (towards the light), albedo and clear colour.
pub(super) const LIGHT: Vec3 = Vec3::new(0.5, 1.0, 0.8);
pub(super) const ALBEDO: Vec3 = Vec3::new(0.8, 0.7, 0.6);
pub(super) const CLEAR: Vec4 = Vec4::new(0.1, 0.1, 0.12, 1.0);

/// A triangle mesh as the peer holds it: positions, optional UVs, triangles.
pub(super) struct PeerMesh {
    pub positions: Vec<Vec3>,
    pub uvs: Option<Vec<Vec2>>,
    pub triangles: Vec<[u32; 3]>,
}

/// `sphere:N` or an OBJ path, normalised as the peer does. Returns the mesh's name too.
pub(super) fn peer_mesh(spec: &str) -> Result<(String, PeerMesh)> {
    let mut mesh = if let Some(n) = spec.strip_prefix("sphere:") {
        let stacks = sphere_stacks(n)?;
        uv_sphere(stacks, 2 * stacks)
    } else {
        let path = Path::new(spec);
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase());
        if ext.as_deref() != Some("obj") {
            bail!("{spec}: expected an .obj file (read as the peer harness reads it) or sphere:N");
        }
        load_obj(path)?
    };
    normalise(&mut mesh.positions);
    let name = if spec.starts_with("sphere:") {
        spec.to_string()
    } else {
        Path::new(spec)
            .file_name()
            .map_or(spec.into(), |f| f.to_string_lossy().into_owned())
    };
    Ok((name, mesh))
}

/// The stack count of `sphere:N`: `2 * s * 2s` triangles, `s = round(sqrt(N / 4))`.
fn sphere_stacks(n: &str) -> Result<u32> {
    let n: u64 = n.trim().parse().map_err(|_| {
        anyhow::anyhow!("sphere:{n}: expected a whole number of triangles, e.g. sphere:1000000")
    })?;
    if n < MIN_SPHERE_TRIANGLES {
        bail!("sphere:{n}: too few triangles (at least {MIN_SPHERE_TRIANGLES})");
    }
    if n > MAX_SPHERE_TRIANGLES {
        bail!("sphere:{n}: too many triangles (at most {MAX_SPHERE_TRIANGLES}, 20 million)");
    }
    Ok(((n as f64 / 4.0).sqrt().round() as u32).max(2))
}

/// `meshes.uv_sphere(stacks, slices)`: a (stacks + 1) x (slices + 1) grid of vertices (poles
/// and seam repeated), two triangles per cell, the first of each cell degenerate at the
/// north pole, in the peer's order (every first triangle, then every second).
pub(super) fn uv_sphere(stacks: u32, slices: u32) -> PeerMesh {
    let (st, sl) = (stacks as usize, slices as usize);
    // np.linspace: start + i * step, the last value exactly `stop`.
    let linspace = |stop: f64, n: usize| -> Vec<f64> {
        let step = stop / n as f64;
        (0..=n)
            .map(|i| if i == n { stop } else { i as f64 * step })
            .collect()
    };
    let (th, ph) = (
        linspace(std::f64::consts::PI, st),
        linspace(2.0 * std::f64::consts::PI, sl),
    );
    let mut positions = Vec::with_capacity((st + 1) * (sl + 1));
    let mut uvs = Vec::with_capacity(positions.capacity());
    for &t in &th {
        for &p in &ph {
            let (s, c) = (libm::sin(t), libm::cos(t));
            positions.push(Vec3::new(
                (s * libm::cos(p)) as f32,
                c as f32,
                (s * libm::sin(p)) as f32,
            ));
            uvs.push(Vec2::new(
                (p / (2.0 * std::f64::consts::PI)) as f32,
                (t / std::f64::consts::PI) as f32,
            ));
        }
    }
    let mut triangles = Vec::with_capacity(2 * st * sl);
    let cell = |i: usize, j: usize| {
        let a = (i * (sl + 1) + j) as u32;
        (a, a + slices + 1)
    };
    for i in 0..st {
        for j in 0..sl {
            let (a, b) = cell(i, j);
            triangles.push([a, b, a + 1]);
        }
    }
    for i in 0..st {
        for j in 0..sl {
            let (a, b) = cell(i, j);
            triangles.push([a + 1, b, b + 1]);
        }
    }
    PeerMesh {
        positions,
        uvs: Some(uvs),
        triangles,
    }
}

/// `meshes.load_obj`: see the module doc.
fn load_obj(path: &Path) -> Result<PeerMesh> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("could not read {}", path.display()))?;
    let (mut vs, mut vts) = (Vec::<Vec3>::new(), Vec::<Vec2>::new());
    let (mut fv, mut ft) = (Vec::<[i64; 3]>::new(), Vec::<[i64; 3]>::new());
    for (k, line) in text.lines().enumerate() {
        let at = || format!("{} line {}", path.display(), k + 1);
        let it = line.split_whitespace();
        if line.starts_with("v ") {
            vs.push(Vec3::from(floats::<3>(&mut it.skip(1)).with_context(at)?));
        } else if line.starts_with("vt ") {
            vts.push(Vec2::from(floats::<2>(&mut it.skip(1)).with_context(at)?));
        } else if line.starts_with("f ") {
            let mut vi = Vec::new();
            let mut ti = Vec::new();
            for t in it.skip(1) {
                let mut parts = t.split('/');
                let v = parts.next().unwrap_or("");
                vi.push(
                    v.parse::<i64>()
                        .with_context(|| format!("{}: bad index '{t}'", at()))?,
                );
                ti.push(match parts.next() {
                    Some(s) if !s.is_empty() => s
                        .parse::<i64>()
                        .with_context(|| format!("{}: bad index '{t}'", at()))?,
                    _ => 0,
                });
            }
            for k in 1..vi.len().saturating_sub(1) {
                fv.push([vi[0], vi[k], vi[k + 1]]);
                ft.push([ti[0], ti[k], ti[k + 1]]);
            }
        }
    }
    if fv.is_empty() {
        bail!("{}: no faces", path.display());
    }
    let nv = vs.len() as i64;
    let mut tris = Vec::with_capacity(fv.len());
    for f in &fv {
        let mut t = [0u32; 3];
        for (o, &i) in t.iter_mut().zip(f) {
            let i = if i < 0 { i + nv + 1 } else { i } - 1;
            if !(0..nv).contains(&i) {
                bail!("{}: face vertex index out of range", path.display());
            }
            *o = i as u32;
        }
        tris.push(t);
    }
    let with_uvs = !vts.is_empty() && ft.iter().all(|t| t.iter().all(|&i| i > 0));
    if !with_uvs {
        return Ok(PeerMesh {
            positions: vs,
            uvs: None,
            triangles: tris,
        });
    }
    if ft.iter().flatten().any(|&i| i > vts.len() as i64) {
        bail!("{}: face texture index out of range", path.display());
    }
    // Every distinct (v, vt) pair one vertex, numbered in sorted order as np.unique does.
    let mut pairs: Vec<(u32, u32)> = tris
        .iter()
        .zip(&ft)
        .flat_map(|(v, t)| (0..3).map(move |k| (v[k], (t[k] - 1) as u32)))
        .collect();
    let corners = pairs.clone();
    pairs.sort_unstable();
    pairs.dedup();
    let index = |p: &(u32, u32)| pairs.binary_search(p).map_or(0, |i| i as u32);
    let triangles = corners
        .chunks_exact(3)
        .map(|c| [index(&c[0]), index(&c[1]), index(&c[2])])
        .collect();
    Ok(PeerMesh {
        positions: pairs.iter().map(|&(v, _)| vs[v as usize]).collect(),
        uvs: Some(pairs.iter().map(|&(_, t)| vts[t as usize]).collect()),
        triangles,
    })
}

/// `N` numbers parsed as Python's `float` does (f64), stored as f32 as numpy's `asarray`.
fn floats<const N: usize>(it: &mut impl Iterator<Item = impl AsRef<str>>) -> Result<[f32; N]> {
    let mut out = [0f32; N];
    for o in &mut out {
        let s = it.next().context("too few numbers")?;
        let s = s.as_ref();
        *o = s
            .parse::<f64>()
            .with_context(|| format!("bad number '{s}'"))? as f32;
    }
    Ok(out)
}

/// `meshes.normalize_to_unit_sphere`, in f32.
fn normalise(p: &mut [Vec3]) {
    let (lo, hi) = p.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &q| (lo.min(q), hi.max(q)),
    );
    let c = (lo + hi) / 2.0;
    let r = p.iter().map(|&q| (q - c).length()).fold(0f32, f32::max);
    let r = if r > 0.0 && r.is_finite() { r } else { 1.0 };
    for q in p {
        *q = (*q - c) / r;
    }
}

/// `meshes.vertex_normals`: the normalised sum of the unnormalised face normals (f32 sums
/// below 200,000 triangles, f64 sums per corner above, as numpy's two code paths).
fn vertex_normals(m: &PeerMesh) -> Vec<Vec3> {
    let p = &m.positions;
    let face: Vec<Vec3> = m
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            (b - a).cross(c - a)
        })
        .collect();
    let mut n = vec![Vec3::ZERO; p.len()];
    for k in 0..3 {
        if m.triangles.len() < 200_000 {
            for (t, f) in m.triangles.iter().zip(&face) {
                n[t[k] as usize] += *f;
            }
        } else {
            let mut sum = vec![glam::DVec3::ZERO; p.len()];
            for (t, f) in m.triangles.iter().zip(&face) {
                sum[t[k] as usize] += f.as_dvec3();
            }
            for (o, s) in n.iter_mut().zip(sum) {
                *o += s.as_vec3();
            }
        }
    }
    for v in &mut n {
        let l = v.length();
        *v /= if l == 0.0 { 1.0 } else { l };
    }
    n
}

/// `bench_llvmpipe.checker_texture`: 1024 x 1024, c = ((x div 64) + (y div 64)) mod 2,
/// (0.3 + 0.6c, 0.5 + 0.3x/1024, 0.8 - 0.5c) truncated to bytes (`astype(np.uint8)`), red and
/// blue computed in f32 and green in f64 as numpy does. Stored linear (not sRGB), row y at
/// v = (y + 0.5) / 1024 as GL's row order puts it, so sampling returns the peer's values.
pub(super) fn checker_texture() -> Result<Texture> {
    const N: u32 = 1024;
    let byte = |v: f64| (v * 255.0) as u8;
    let texels = (0..N * N)
        .map(|i| {
            let (x, y) = (i % N, i / N);
            let c = ((x / 64 + y / 64) % 2) as f32;
            [
                byte(f64::from(0.3f32 + 0.6f32 * c)),
                byte(0.5 + 0.3 * (f64::from(x) / f64::from(N))),
                byte(f64::from(0.8f32 - 0.5f32 * c)),
                255,
            ]
        })
        .collect();
    Ok(Texture::new("peer checker", N, N, texels, false)?)
}

/// The peer's camera: eye = normalize(1.6, 1.2, 2.0) * 2.8, looking at the origin, +Y up,
/// vertical FOV 45 degrees, near 0.5, far 10.
pub(super) fn camera() -> Camera {
    Camera {
        name: "peer".into(),
        eye: Vec3::new(1.6, 1.2, 2.0).normalize() * 2.8,
        target: Vec3::ZERO,
        up: Vec3::Y,
        yfov: 45f32.to_radians(),
        near: 0.5,
        far: 10.0,
        aspect: None,
        ortho: None,
        lens: Default::default(),
    }
}

/// The scene: the mesh with the peer's normals, one double-sided material and the peer's
/// light written as realist's Blinn-Phong equation (`shade/lighting.rs`):
/// `I = g_amb * K_a * K_d + I_L * (K_d * max(N.L, 0) + K_s * max(N.H, 0)^n)` with
/// `g_amb = 0.1`, `K_a = 1`, `I_L = 0.9`, `K_d = A` (or the texture), `K_s = 0.4 / 0.9`,
/// `n = 32`, which is `A * (0.1 + 0.9 * max(N.L, 0)) + 0.4 * max(N.H, 0)^32`, except that
/// realist adds no highlight where `N.L <= 0` (there `N.H <= cos 79 degrees` for this light
/// and view, so the peer's highlight is below 1e-22: no pixel differs).
pub(super) fn scene(name: &str, mesh: PeerMesh, textured: bool) -> Result<Scene> {
    let normals = vertex_normals(&mesh);
    let mut m = mesh;
    let mut normals = normals;
    if m.uvs.is_none() {
        drop_unused(&mut m, &mut normals);
    }
    let data = MeshData {
        name: name.into(),
        corners: m.triangles.iter().flatten().copied().collect(),
        positions: m.positions,
        facet_sizes: None,
        normals: Some(Channel::per_vertex(normals)),
        uvs: m.uvs.map(Channel::per_vertex).into_iter().collect(),
        colors: None,
        tangents: None,
        material: Some(0),
    };
    let mesh = Mesh::new(data, NormalPolicy::default()).context("building the mesh")?;
    let mut textures = Vec::new();
    let base = if textured {
        textures.push(std::sync::Arc::new(checker_texture()?));
        Vec4::ONE
    } else {
        ALBEDO.extend(1.0)
    };
    let material = Material {
        name: "peer".into(),
        base_color: base,
        base_color_texture: textured.then_some(TextureSlot::new(0)),
        ambient: Vec3::ONE,
        specular: Vec3::splat(0.4 / 0.9),
        shininess: 32.0,
        double_sided: true,
        ..Material::default()
    };
    Ok(Scene {
        meshes: vec![mesh],
        materials: vec![material],
        textures,
        instances: vec![Instance {
            mesh: 0,
            world: Mat4::IDENTITY,
            name: name.into(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        }],
        lights: vec![
            Light::ambient(Vec3::splat(0.1)),
            Light::directional(-LIGHT.normalize(), Vec3::splat(0.9)),
        ],
        cameras: vec![camera()],
        ..Scene::default()
    })
}

/// Removes vertices no triangle uses (after normalisation, where the peer counts them).
fn drop_unused(m: &mut PeerMesh, normals: &mut Vec<Vec3>) {
    let mut new = vec![u32::MAX; m.positions.len()];
    let mut next = 0u32;
    for t in &mut m.triangles {
        for i in t.iter_mut() {
            let slot = &mut new[*i as usize];
            if *slot == u32::MAX {
                *slot = next;
                next += 1;
            }
            *i = *slot;
        }
    }
    let keep = |v: &mut Vec<Vec3>| {
        let mut out = vec![Vec3::ZERO; next as usize];
        for (old, &n) in new.iter().enumerate() {
            if n != u32::MAX {
                out[n as usize] = v[old];
            }
        }
        *v = out;
    };
    keep(&mut m.positions);
    keep(normals);
}
