//! Primitive builders: the textbook's latitude/longitude sphere, cylinder, cone, torus and cube,
//! with exact (analytic) normals and UVs ([`NormalSource::Analytic`]).
//!
//! Conventions shared by all builders:
//! - centred on the origin, axis +Y; longitude `phi` runs from +Z towards +X, so that
//!   increasing `phi` is counter-clockwise seen from +Y;
//! - facets are counter-clockwise seen from outside, so Newell normals point outwards;
//! - UVs follow glTF: origin top-left, `v` downwards (`v = 0` at the top / north);
//! - vertices are shared wherever the surface is continuous, so the topology is closed
//!   (0 boundary edges, Euler characteristic 2, or 0 for the torus). Where an attribute is
//!   not continuous (the UV seam at `u = 0/1`, the poles, a crease between side and cap) the
//!   channel is indexed per corner instead of duplicating the vertex;
//! - radii, heights and sizes must be finite and `>= 0` ([`MeshError::Dimension`] otherwise;
//!   0 gives degenerate facets, which is legal); tessellation counts below [`MIN_SEGMENTS`]
//!   are raised to it, counts above [`MAX_SEGMENTS`] are refused ([`MeshError::Segments`]),
//!   which bounds every allocation (about a million facets at most).

use std::f64::consts::{PI, TAU};

use glam::{Vec2, Vec3};

use super::{Channel, Mesh, MeshData, MeshError, NormalPolicy, NormalSource};

/// Smallest tessellation count a builder uses.
pub const MIN_SEGMENTS: u32 = 3;
/// Largest tessellation count a builder uses (a 1024 x 1024 sphere has about a million
/// facets).
pub const MAX_SEGMENTS: u32 = 1024;

/// A tessellation count raised to [`MIN_SEGMENTS`], or an error above [`MAX_SEGMENTS`].
fn segments(
    primitive: &'static str,
    parameter: &'static str,
    count: u32,
) -> Result<u32, MeshError> {
    if count > MAX_SEGMENTS {
        return Err(MeshError::Segments {
            primitive,
            parameter,
            count,
            max: MAX_SEGMENTS,
        });
    }
    Ok(count.max(MIN_SEGMENTS))
}

/// A finite, non-negative dimension.
fn dimension(
    primitive: &'static str,
    parameter: &'static str,
    value: f32,
) -> Result<f32, MeshError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(MeshError::Dimension {
            primitive,
            parameter,
            value,
        })
    }
}

/// Unit direction at polar angle `theta` from +Y and longitude `phi`.
fn direction(theta: f64, phi: f64) -> Vec3 {
    let (st, ct) = libm::sincos(theta);
    let (sp, cp) = libm::sincos(phi);
    Vec3::new((st * sp) as f32, ct as f32, (st * cp) as f32)
}

/// Collects facets whose corners are `[vertex, normal index, uv index]`.
#[derive(Default)]
struct Builder {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    corners: Vec<u32>,
    normal_ix: Vec<u32>,
    uv_ix: Vec<u32>,
    sizes: Vec<u32>,
}

impl Builder {
    fn facet(&mut self, corners: impl IntoIterator<Item = [u32; 3]>) {
        let before = self.corners.len();
        for [v, n, t] in corners {
            self.corners.push(v);
            self.normal_ix.push(n);
            self.uv_ix.push(t);
        }
        self.sizes.push((self.corners.len() - before) as u32);
    }

    /// A channel is per vertex when its indices are the corners' vertices.
    fn channel<T>(
        values: Vec<T>,
        indices: Vec<u32>,
        corners: &[u32],
        vertices: usize,
    ) -> Channel<T> {
        if values.len() == vertices && indices == corners {
            Channel {
                values,
                indices: None,
            }
        } else {
            Channel {
                values,
                indices: Some(indices),
            }
        }
    }

    fn finish(self, name: &str) -> Mesh {
        let vertices = self.positions.len();
        let normals = Self::channel(self.normals, self.normal_ix, &self.corners, vertices);
        let uvs = Self::channel(self.uvs, self.uv_ix, &self.corners, vertices);
        let data = MeshData {
            name: name.to_owned(),
            positions: self.positions,
            corners: self.corners,
            facet_sizes: Some(self.sizes),
            normals: Some(normals),
            uvs: vec![uvs],
            colors: None,
            tangents: None,
            material: None,
        };
        debug_assert_eq!(super::build::validate(&data), Ok(()));
        let mut mesh = Mesh::from_valid(data, NormalPolicy::Flat);
        mesh.normal_source = NormalSource::Analytic;
        mesh
    }
}

/// UV of a planar cap: `x, z` on the unit disc mapped to the unit square, seen from above
/// (`from_above`) or from below.
fn cap_uv(d: Vec3, from_above: bool) -> Vec2 {
    let v = if from_above { d.z } else { -d.z };
    Vec2::new(0.5 + 0.5 * d.x, 0.5 + 0.5 * v)
}

impl Mesh {
    /// The textbook's latitude/longitude sphere: vertex 0 is the north pole (+Y), then
    /// `stacks - 1` rings of `slices` vertices from north to south, the last vertex the south
    /// pole. Triangles at the poles, quads elsewhere. Normals per vertex; UVs per corner
    /// (`u = 0/1` seam, one UV per pole triangle).
    ///
    /// # Errors
    ///
    /// A negative or non-finite dimension, or a count above [`MAX_SEGMENTS`].
    pub fn sphere(radius: f32, slices: u32, stacks: u32) -> Result<Mesh, MeshError> {
        let (s, st) = (
            segments("sphere", "slices", slices)?,
            segments("sphere", "stacks", stacks)?,
        );
        let r = dimension("sphere", "radius", radius)?;
        let mut b = Builder::default();
        let ring = |i: u32, j: u32| 1 + (i - 1) * s + j % s;
        let grid = |i: u32, j: u32| (i - 1) * (s + 1) + j;
        let south = 1 + (st - 1) * s;
        b.normals.push(Vec3::Y);
        for i in 1..st {
            let theta = PI * f64::from(i) / f64::from(st);
            for j in 0..s {
                b.normals
                    .push(direction(theta, TAU * f64::from(j) / f64::from(s)));
            }
            for j in 0..=s {
                b.uvs
                    .push(Vec2::new(j as f32 / s as f32, i as f32 / st as f32));
            }
        }
        b.normals.push(-Vec3::Y);
        b.positions = b.normals.iter().map(|&n| r * n).collect();
        let poles = b.uvs.len() as u32;
        for v in [0.0, 1.0] {
            b.uvs
                .extend((0..s).map(|j| Vec2::new((j as f32 + 0.5) / s as f32, v)));
        }
        let corner = |i, j| [ring(i, j), ring(i, j), grid(i, j)];
        for j in 0..s {
            b.facet([[0, 0, poles + j], corner(1, j), corner(1, j + 1)]);
        }
        for i in 1..st - 1 {
            for j in 0..s {
                b.facet([
                    corner(i, j),
                    corner(i + 1, j),
                    corner(i + 1, j + 1),
                    corner(i, j + 1),
                ]);
            }
        }
        for j in 0..s {
            let pole = [south, south, poles + s + j];
            b.facet([corner(st - 1, j), pole, corner(st - 1, j + 1)]);
        }
        Ok(b.finish("sphere"))
    }

    /// A cylinder of `slices` sides around +Y, from `y = -height/2` to `height/2`, with
    /// `caps` as two `slices`-gons. Normals are creased: radial on the side, +-Y on the caps.
    /// Without caps the tube has two boundary loops.
    ///
    /// # Errors
    ///
    /// A negative or non-finite dimension, or a count above [`MAX_SEGMENTS`].
    pub fn cylinder(radius: f32, height: f32, slices: u32, caps: bool) -> Result<Mesh, MeshError> {
        let s = segments("cylinder", "slices", slices)?;
        let r = dimension("cylinder", "radius", radius)?;
        let h = 0.5 * dimension("cylinder", "height", height)?;
        let mut b = Builder::default();
        let dirs: Vec<Vec3> = (0..s)
            .map(|j| direction(PI / 2.0, TAU * f64::from(j) / f64::from(s)))
            .collect();
        b.positions
            .extend(dirs.iter().map(|&d| r * d - h * Vec3::Y));
        b.positions
            .extend(dirs.iter().map(|&d| r * d + h * Vec3::Y));
        b.normals.extend(&dirs);
        b.normals.extend([Vec3::Y, -Vec3::Y]);
        for v in [0.0, 1.0] {
            b.uvs
                .extend((0..=s).map(|j| Vec2::new(j as f32 / s as f32, v)));
        }
        let (top_uv, bottom_uv) = (b.uvs.len() as u32, b.uvs.len() as u32 + s);
        b.uvs.extend(dirs.iter().map(|&d| cap_uv(d, true)));
        b.uvs.extend(dirs.iter().map(|&d| cap_uv(d, false)));
        for j in 0..s {
            let k = (j + 1) % s;
            let (bottom_row, top_row) = (s + 1, 0);
            b.facet([
                [j, j, bottom_row + j],
                [k, k, bottom_row + j + 1],
                [s + k, k, top_row + j + 1],
                [s + j, j, top_row + j],
            ]);
        }
        if caps {
            b.facet((0..s).map(|j| [s + j, s, top_uv + j]));
            b.facet((0..s).rev().map(|j| [j, s + 1, bottom_uv + j]));
        }
        Ok(b.finish("cylinder"))
    }

    /// A cone of `slices` sides around +Y: apex (vertex 0) at `y = height/2`, base ring at
    /// `-height/2`, closed by a `slices`-gon. Side normals are the exact cone normals, at the
    /// apex the one along each side facet's middle line; the base is creased (-Y).
    ///
    /// # Errors
    ///
    /// A negative or non-finite dimension, or a count above [`MAX_SEGMENTS`].
    pub fn cone(radius: f32, height: f32, slices: u32) -> Result<Mesh, MeshError> {
        let s = segments("cone", "slices", slices)?;
        let r = dimension("cone", "radius", radius)?;
        let full = dimension("cone", "height", height)?;
        let mut b = Builder::default();
        let phi = |j: f64| TAU * j / f64::from(s);
        let dirs: Vec<Vec3> = (0..s)
            .map(|j| direction(PI / 2.0, phi(f64::from(j))))
            .collect();
        // Slope normal: (height * radial + radius * Y) / |...|.
        let side = |d: Vec3| {
            let n = full * d + r * Vec3::Y;
            super::normals::unit(n).unwrap_or(Vec3::Y)
        };
        b.positions.push(0.5 * full * Vec3::Y);
        b.positions
            .extend(dirs.iter().map(|&d| r * d - 0.5 * full * Vec3::Y));
        b.normals.extend(dirs.iter().map(|&d| side(d)));
        let apex_normals = b.normals.len() as u32;
        b.normals
            .extend((0..s).map(|j| side(direction(PI / 2.0, phi(f64::from(j) + 0.5)))));
        b.normals.push(-Vec3::Y);
        b.uvs
            .extend((0..=s).map(|j| Vec2::new(j as f32 / s as f32, 1.0)));
        let apex_uv = b.uvs.len() as u32;
        b.uvs
            .extend((0..s).map(|j| Vec2::new((j as f32 + 0.5) / s as f32, 0.0)));
        let base_uv = b.uvs.len() as u32;
        b.uvs.extend(dirs.iter().map(|&d| cap_uv(d, false)));
        for j in 0..s {
            let k = (j + 1) % s;
            b.facet([
                [0, apex_normals + j, apex_uv + j],
                [1 + j, j, j],
                [1 + k, k, j + 1],
            ]);
        }
        b.facet((0..s).rev().map(|j| [1 + j, 2 * s, base_uv + j]));
        Ok(b.finish("cone"))
    }

    /// A torus around +Y: `rings` rings of `slices` vertices. Ring `i` is the circle around Y
    /// at tube angle `psi = 2 pi i / rings` (0 = outer equator, increasing upwards), so
    /// `slices` counts segments around the Y axis (as for the sphere) and `rings` segments
    /// around the tube. `major` is the distance from the axis to the tube centre, `minor` the
    /// tube radius. UVs: `u` along `slices`, `v` along `rings`, seams in both.
    ///
    /// # Errors
    ///
    /// A negative or non-finite dimension, or a count above [`MAX_SEGMENTS`].
    pub fn torus(major: f32, minor: f32, slices: u32, rings: u32) -> Result<Mesh, MeshError> {
        let s = segments("torus", "slices", slices)?;
        let n = segments("torus", "rings", rings)?;
        let big = dimension("torus", "major", major)?;
        let small = dimension("torus", "minor", minor)?;
        let mut b = Builder::default();
        for i in 0..n {
            let psi = TAU * f64::from(i) / f64::from(n);
            // The tube normal: polar angle measured from +Y is pi/2 - psi.
            for j in 0..s {
                let phi = TAU * f64::from(j) / f64::from(s);
                let normal = direction(PI / 2.0 - psi, phi);
                let radial = direction(PI / 2.0, phi);
                b.normals.push(normal);
                b.positions.push(big * radial + small * normal);
            }
        }
        for i in 0..=n {
            b.uvs
                .extend((0..=s).map(|j| Vec2::new(j as f32 / s as f32, i as f32 / n as f32)));
        }
        let vertex = |i: u32, j: u32| (i % n) * s + j % s;
        let corner = |i: u32, j: u32| [vertex(i, j), vertex(i, j), i * (s + 1) + j];
        for i in 0..n {
            for j in 0..s {
                b.facet([
                    corner(i, j),
                    corner(i, j + 1),
                    corner(i + 1, j + 1),
                    corner(i + 1, j),
                ]);
            }
        }
        Ok(b.finish("torus"))
    }

    /// An axis-aligned cube of edge `size` centred on the origin: 8 vertices, 6 quads, one
    /// normal per face (per corner), each face mapped to the whole texture, upright when
    /// seen from outside (+-Y faces: with -Z resp. +Z up).
    ///
    /// # Errors
    ///
    /// A negative or non-finite `size`.
    pub fn cube(size: f32) -> Result<Mesh, MeshError> {
        let h = 0.5 * dimension("cube", "size", size)?;
        let mut b = Builder {
            // Vertex index bits: x > 0, y > 0, z > 0.
            positions: (0..8u32)
                .map(|i| {
                    let sign = |bit: u32| if i & bit != 0 { h } else { -h };
                    Vec3::new(sign(1), sign(2), sign(4))
                })
                .collect(),
            uvs: vec![Vec2::new(0.0, 1.0), Vec2::ONE, Vec2::X, Vec2::ZERO],
            ..Builder::default()
        };
        // (outward normal, u axis, up axis) with u x up = normal.
        let faces = [
            (Vec3::X, -Vec3::Z, Vec3::Y),
            (-Vec3::X, Vec3::Z, Vec3::Y),
            (Vec3::Y, Vec3::X, -Vec3::Z),
            (-Vec3::Y, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y),
            (-Vec3::Z, -Vec3::X, Vec3::Y),
        ];
        for (f, &(normal, u, up)) in faces.iter().enumerate() {
            b.normals.push(normal);
            let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
            b.facet(corners.iter().enumerate().map(|(k, &(a, c))| {
                let d = normal + a * u + c * up;
                let v =
                    u32::from(d.x > 0.0) | u32::from(d.y > 0.0) << 1 | u32::from(d.z > 0.0) << 2;
                [v, f as u32, k as u32]
            }));
        }
        Ok(b.finish("cube"))
    }

    /// A flat grid in the XZ plane at y = 0 facing +Y, `2 half_x` by `2 half_z`, cut into
    /// `nx` x `nz` quads (so per-vertex lighting can show a spotlight's pool on it), UVs
    /// from (0, 0) at (-x, -z) to (1, 1).
    ///
    /// # Errors
    ///
    /// A negative or non-finite size, or a count above [`MAX_SEGMENTS`] (0 is raised to 1).
    pub fn grid(half_x: f32, half_z: f32, nx: u32, nz: u32) -> Result<Mesh, MeshError> {
        let hx = dimension("grid", "half_x", half_x)?;
        let hz = dimension("grid", "half_z", half_z)?;
        let nx = segments("grid", "nx", nx)?.min(nx.max(1));
        let nz = segments("grid", "nz", nz)?.min(nz.max(1));
        let mut b = Builder {
            normals: vec![Vec3::Y],
            ..Builder::default()
        };
        for j in 0..=nz {
            for i in 0..=nx {
                let (u, v) = (i as f32 / nx as f32, j as f32 / nz as f32);
                b.positions
                    .push(Vec3::new((2.0 * u - 1.0) * hx, 0.0, (2.0 * v - 1.0) * hz));
                b.uvs.push(Vec2::new(u, v));
            }
        }
        let at = |i: u32, j: u32| j * (nx + 1) + i;
        for j in 0..nz {
            for i in 0..nx {
                // Counter-clockwise seen from +Y: (i, j+1), (i+1, j+1), (i+1, j), (i, j).
                let quad = [at(i, j + 1), at(i + 1, j + 1), at(i + 1, j), at(i, j)];
                b.facet(quad.map(|v| [v, 0, v]));
            }
        }
        Ok(b.finish("grid"))
    }
}
