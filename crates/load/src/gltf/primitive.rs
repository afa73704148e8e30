//! One glTF primitive into one scene [`Mesh`]: attributes (POSITION, NORMAL, TANGENT,
//! TEXCOORD_0.. up to [`MAX_UV_SETS`], COLOR_0), indices (checked against the vertex count), and triangle strips and fans
//! turned into triangle lists with the winding the spec defines:
//!
//! - strip: triangle i is (v_i, v_i+1, v_i+2) for even i and (v_i, v_i+2, v_i+1) for odd i;
//! - fan: triangle i is (v_0, v_i+1, v_i+2).
//!
//! Triangles that repeat a vertex index (strip restarts, degenerate input) are dropped.
//!
//! POINTS, LINES, LINE_LOOP and LINE_STRIP primitives become meshes with no facets that
//! carry points or line segments ([`Mesh::points`], [`Mesh::lines`]; `strokes` lists them
//! as the specification defines the modes, with a warning for counts it does not allow).
//! Their vertices are not welded, keep NORMAL (which makes them lit), COLOR_0 and the UV
//! sets, and may be skinned and morphed like any mesh; the load report lists each one with
//! its count.

use glam::{Vec2, Vec3, Vec4};
use gltf::json::mesh::{Mode, Primitive, Semantic};
use gltf::json::validation::Checked;

use super::accessor::Format;
use super::{primitive_units, Builder, Doc, GltfError, QUANTIZATION};
use crate::mesh::{Channel, Mesh, MeshData, NormalPolicy};
use crate::{mesh_bytes, retain_facets, LoadError};

/// Texture coordinate sets read per primitive (`TEXCOORD_0` to `TEXCOORD_3`); further
/// sets are named in the load report and not read.
pub const MAX_UV_SETS: u32 = 4;

/// The vertex attributes of a primitive, read and checked to have one value per vertex.
struct Attributes {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    tangents: Option<Vec<Vec4>>,
    uvs: Vec<Vec<Vec2>>,
    colors: Option<Vec<Vec4>>,
}

/// Which primitive is being read, for messages.
struct Site<'a> {
    mesh: usize,
    primitive: usize,
    /// "mesh 0 ('name') primitive 1".
    label: &'a str,
}

impl Doc<'_> {
    fn primitive_error(&self, at: &Site, reason: String) -> LoadError {
        let (path, mesh, primitive) = (self.path.to_owned(), at.mesh, at.primitive);
        GltfError::Primitive {
            path,
            mesh,
            primitive,
            reason,
        }
        .into()
    }

    /// Reads POSITION (accessor `position`), NORMAL, TANGENT, the TEXCOORD_n sets and
    /// COLOR_0; sets beyond [`MAX_UV_SETS`] are reported in `warnings`.
    fn attributes(
        &self,
        prim: &Primitive,
        position: usize,
        at: &Site,
        warnings: &mut Vec<String>,
    ) -> Result<Attributes, LoadError> {
        let attr = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|i| i.value());
        let used = |what: &str| format!("mesh {} primitive {} {what}", at.mesh, at.primitive);
        let quantized = self.json.extensions_used.iter().any(|e| e == QUANTIZATION);
        let (exact, unorm) = match quantized {
            true => (Format::Quantized, Format::Quantized),
            false => (Format::Float, Format::FloatOrUnorm),
        };
        let read = |name: &str, accessor: Option<usize>, sizes: &[usize], format| match accessor {
            Some(a) => self.read_floats(a, &used(name), sizes, format).map(Some),
            None => Ok(None),
        };
        let (_, pos) = self.read_floats(position, &used("POSITION"), &[3], exact)?;
        let n = pos.len() / 3;
        let normals = read("NORMAL", attr(Semantic::Normals), &[3], exact)?;
        let tangents = read("TANGENT", attr(Semantic::Tangents), &[4], exact)?;
        let mut uvs = Vec::new();
        for set in 0..MAX_UV_SETS {
            let name = format!("TEXCOORD_{set}");
            match read(&name, attr(Semantic::TexCoords(set)), &[2], unorm)? {
                Some(found) => uvs.push((name, found)),
                None => break,
            }
        }
        let more = (MAX_UV_SETS..MAX_UV_SETS + 28)
            .filter(|&s| attr(Semantic::TexCoords(s)).is_some())
            .count();
        if more > 0 {
            warnings.push(format!(
                "{}: {more} texture coordinate set(s) beyond TEXCOORD_{} not read",
                at.label,
                MAX_UV_SETS - 1
            ));
        }
        let colors = read(
            "COLOR_0",
            attr(Semantic::Colors(0)),
            &[3, 4],
            Format::FloatOrUnorm,
        )?;
        let named = [
            ("NORMAL", normals.as_ref()),
            ("TANGENT", tangents.as_ref()),
            ("COLOR_0", colors.as_ref()),
        ];
        let sets = uvs.iter().map(|(name, found)| (name.as_str(), Some(found)));
        for (name, found) in named.into_iter().chain(sets) {
            if let Some((size, values)) = found {
                let len = values.len() / size;
                if len != n {
                    let reason = format!("{name} has {len} elements but POSITION has {n}");
                    return Err(self.primitive_error(at, reason));
                }
            }
        }
        let rgba = |(size, v): (usize, Vec<f32>)| -> Vec<Vec4> {
            let one = |x: &[f32]| match x {
                &[r, g, b] => Vec4::new(r, g, b, 1.0),
                _ => Vec4::from_slice(x),
            };
            v.chunks_exact(size).map(one).collect()
        };
        Ok(Attributes {
            positions: pos.chunks_exact(3).map(Vec3::from_slice).collect(),
            normals: normals.map(|(_, v)| v.chunks_exact(3).map(Vec3::from_slice).collect()),
            tangents: tangents.map(|(_, v)| v.chunks_exact(4).map(Vec4::from_slice).collect()),
            uvs: uvs
                .into_iter()
                .map(|(_, (_, v))| v.chunks_exact(2).map(Vec2::from_slice).collect())
                .collect(),
            colors: colors.map(rgba),
        })
    }

    /// The primitive's vertex indices (every one checked < `n`), or 0..n without indices.
    fn indices(&self, prim: &Primitive, n: usize, at: &Site) -> Result<Vec<u32>, LoadError> {
        let Some(a) = prim.indices else {
            let n32 = u32::try_from(n)
                .map_err(|_| self.primitive_error(at, format!("{n} vertices are too many")))?;
            return Ok((0..n32).collect());
        };
        let used = format!("mesh {} primitive {} indices", at.mesh, at.primitive);
        let ix = self.read_indices(a.value(), &used)?;
        if let Some((i, &v)) = ix.iter().enumerate().find(|(_, &v)| v as usize >= n) {
            let reason =
                format!("index {v} at position {i} is out of range: there are {n} vertices");
            return Err(self.primitive_error(at, reason));
        }
        Ok(ix)
    }
}

impl Builder<'_> {
    /// The scene mesh for primitive `p` of glTF mesh `m` (which must exist), built on first
    /// use; `None` when the primitive is not drawn (reason in the report).
    pub fn primitive_mesh(&mut self, m: usize, p: usize) -> Result<Option<usize>, LoadError> {
        if let Some(&cached) = self.meshes.get(&(m, p)) {
            return Ok(cached);
        }
        // Progress: the primitive's units, a share at each step of building it (on a
        // 2M-triangle grid: reading accessors and listing triangles 20%, Mesh::new 80%).
        let (tracker, base) = (self.doc.tracker, self.doc.tracker.done());
        let units = primitive_units(&self.doc.json, m, p);
        let step = |percent: u64| {
            let part = u128::from(units) * u128::from(percent) / 100;
            tracker.advance(base.saturating_add(part as u64))
        };
        let built = self.build_primitive(m, p, &step)?;
        self.meshes.insert((m, p), built);
        tracker.advance(base + units)?;
        Ok(built)
    }

    /// Builds primitive `p` of mesh `m`, calling `step(k)` (a checkpoint, and progress to
    /// k percent of the primitive) between the steps that take time on a big one.
    fn build_primitive(
        &mut self,
        m: usize,
        p: usize,
        step: &dyn Fn(u64) -> Result<(), LoadError>,
    ) -> Result<Option<usize>, LoadError> {
        let doc = &self.doc;
        let mesh = doc.json.meshes.get(m);
        let Some(prim) = mesh.and_then(|mesh| mesh.primitives.get(p)) else {
            return Ok(None);
        };
        let name = mesh.and_then(|x| x.name.clone());
        let label = match &name {
            Some(n) => format!("mesh {m} ('{n}') primitive {p}"),
            None => format!("mesh {m} primitive {p}"),
        };
        let report = &mut self.scene.report;
        let mode = match prim.mode {
            Checked::Valid(mode) => mode,
            Checked::Invalid => {
                report
                    .skipped
                    .push(format!("{label}: unknown primitive mode"));
                return Ok(None);
            }
        };
        let Some(position) = prim.attributes.get(&Checked::Valid(Semantic::Positions)) else {
            report
                .skipped
                .push(format!("{label}: no POSITION attribute"));
            return Ok(None);
        };
        let at = Site {
            mesh: m,
            primitive: p,
            label: &label,
        };
        // A Draco-compressed primitive is decoded first; its accessors are then read from
        // the decoded mesh until `draco` is dropped (after the last accessor is read, or at
        // the first error).
        doc.draco_prepare(prim, m, p)?;
        let draco = ClearDraco(doc);
        let attrs = doc.attributes(prim, position.value(), &at, &mut report.warnings)?;
        step(5)?;
        let n = attrs.positions.len();
        let indices = doc.indices(prim, n, &at)?;
        step(10)?;
        let variant_pairs = super::variants::mappings(
            prim.extensions.as_ref().map(|e| &e.others),
            self.scene.variants.len(),
            doc.json.materials.len(),
            &label,
            &mut report.warnings,
        );
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            let deform = doc.deform(prim, n, &label, &mut report.warnings)?;
            let material = prim.material.map(|i| i.value());
            drop(draco);
            let source = Strokes {
                mode,
                name,
                attrs,
                indices,
                deform,
                material,
                variants: variant_pairs,
            };
            return self.build_strokes(m, p, source, &label);
        }
        let corners = triangle_list(mode, &indices, &at, &mut report.warnings);
        step(15)?;
        let deform = doc.deform(prim, n, &label, &mut report.warnings)?;
        drop(draco);
        let facets = corners.len() as u64 / 3;
        doc.budget
            .charge(mesh_bytes(n as u64, corners.len() as u64, facets), || {
                format!("{label} ({n} vertices, {facets} triangles)")
            })?;
        let material = match prim.material {
            Some(i) => self.material(i.value(), &label)?,
            None => Some(self.default_material()),
        };
        let has_normals = attrs.normals.is_some();
        // Without NORMAL the normals are flat and tangents given for them MUST be ignored
        // (the specification, Meshes).
        let tangents = attrs.tangents.filter(|_| has_normals);
        let mut data = MeshData {
            name: name.unwrap_or_else(|| format!("mesh {m}")),
            positions: attrs.positions,
            corners,
            facet_sizes: None,
            normals: attrs.normals.map(Channel::per_vertex),
            uvs: attrs.uvs.into_iter().map(Channel::per_vertex).collect(),
            colors: attrs.colors.map(Channel::per_vertex),
            tangents: tangents.map(Channel::per_vertex),
            material,
        };
        let report = &mut self.scene.report;
        report
            .warnings
            .extend(retain_facets(&mut data).warnings(&label));
        step(20)?;
        if data.corners.is_empty() {
            report.skipped.push(format!("{label}: no triangles"));
            return Ok(None);
        }
        if !has_normals {
            report
                .generated
                .push(format!("{label}: flat normals (no NORMAL attribute)"));
        }
        // A deformable primitive keeps its vertices as they are: welding would merge
        // vertices at one position whose joints, weights or morph deltas differ.
        let data = if deform.is_some() {
            data
        } else {
            data.weld_positions()
        };
        let mut mesh = Mesh::new(data, NormalPolicy::Flat).map_err(|source| {
            let path = self.doc.path.to_owned();
            GltfError::Mesh {
                path,
                mesh: m,
                primitive: p,
                source,
            }
        })?;
        mesh.deform = deform.map(Box::new);
        for (v, i) in variant_pairs {
            if let Some(k) = self.material(i, &label)? {
                mesh.variants.push((v, k));
            }
        }
        self.scene.meshes.push(mesh);
        Ok(Some(self.scene.meshes.len() - 1))
    }
}

/// What a points or lines primitive was read into.
struct Strokes {
    mode: Mode,
    name: Option<String>,
    attrs: Attributes,
    indices: Vec<u32>,
    deform: Option<crate::mesh::Deform>,
    /// The glTF material index.
    material: Option<usize>,
    /// `KHR_materials_variants` (variant, glTF material index) pairs.
    variants: Vec<(u32, usize)>,
}

impl Builder<'_> {
    /// The scene mesh of a POINTS, LINES, LINE_LOOP or LINE_STRIP primitive: its vertices
    /// (not welded), no facets, and its points or line segments ([`strokes`]).
    fn build_strokes(
        &mut self,
        m: usize,
        p: usize,
        source: Strokes,
        label: &str,
    ) -> Result<Option<usize>, LoadError> {
        let Strokes {
            mode,
            name,
            attrs,
            indices,
            deform,
            material,
            variants,
        } = source;
        let doc = &self.doc;
        let report = &mut self.scene.report;
        let n = attrs.positions.len();
        let (points, lines) = strokes(mode, &indices, label, &mut report.warnings);
        if points.is_empty() && lines.is_empty() {
            report
                .skipped
                .push(format!("{label}: no {}", mode_name(mode).1));
            return Ok(None);
        }
        let items = (points.len() + 2 * lines.len()) as u64;
        doc.budget.charge(mesh_bytes(n as u64, items, 0), || {
            format!("{label} ({n} vertices, {items} point and line indices)")
        })?;
        let material = match material {
            Some(i) => self.material(i, label)?,
            None => Some(self.default_material()),
        };
        let has_normals = attrs.normals.is_some();
        let data = MeshData {
            name: name.unwrap_or_else(|| format!("mesh {m}")),
            positions: attrs.positions,
            corners: Vec::new(),
            facet_sizes: None,
            normals: attrs.normals.map(Channel::per_vertex),
            uvs: attrs.uvs.into_iter().map(Channel::per_vertex).collect(),
            colors: attrs.colors.map(Channel::per_vertex),
            // Tangents serve normal maps, which points and lines do not read.
            tangents: None,
            material,
        };
        let mesh_error = |source| {
            LoadError::from(GltfError::Mesh {
                path: self.doc.path.to_owned(),
                mesh: m,
                primitive: p,
                source,
            })
        };
        let mut mesh = Mesh::new(data, NormalPolicy::Flat).map_err(mesh_error)?;
        let (point_count, line_count) = (points.len(), lines.len());
        mesh.set_strokes(points, lines).map_err(mesh_error)?;
        mesh.deform = deform.map(Box::new);
        for (v, i) in variants {
            if let Some(k) = self.material(i, label)? {
                mesh.variants.push((v, k));
            }
        }
        let (mode_label, _) = mode_name(mode);
        let lighting = if has_normals {
            "lit (NORMAL)"
        } else {
            "unlit (no NORMAL)"
        };
        let what = if mode == Mode::Points {
            format!("{point_count} points")
        } else {
            format!("{line_count} line segments")
        };
        self.scene
            .report
            .loaded
            .push(format!("{label}: {what} ({mode_label}), {lighting}"));
        self.scene.meshes.push(mesh);
        Ok(Some(self.scene.meshes.len() - 1))
    }
}

/// The specification's name of a points or lines mode, and what it draws.
fn mode_name(mode: Mode) -> (&'static str, &'static str) {
    match mode {
        Mode::Points => ("POINTS", "points"),
        Mode::Lines => ("LINES", "lines"),
        Mode::LineLoop => ("LINE_LOOP", "lines"),
        Mode::LineStrip => ("LINE_STRIP", "lines"),
        Mode::Triangles => ("TRIANGLES", "triangles"),
        Mode::TriangleStrip => ("TRIANGLE_STRIP", "triangles"),
        Mode::TriangleFan => ("TRIANGLE_FAN", "triangles"),
    }
}

/// The points (POINTS) or line segments (LINES, LINE_LOOP, LINE_STRIP) of `indices` drawn
/// in `mode`, as the specification defines them: LINES pairs consecutive indices, a
/// LINE_STRIP joins each index to the next, a LINE_LOOP also joins the last to the first.
/// Counts the specification does not allow (no points, an odd LINES count, a strip or loop
/// of fewer than 2) are warned about in `warnings`, naming `label`; what can be drawn is.
fn strokes(
    mode: Mode,
    indices: &[u32],
    label: &str,
    warnings: &mut Vec<String>,
) -> (Vec<u32>, Vec<[u32; 2]>) {
    let n = indices.len();
    let (name, _) = mode_name(mode);
    match mode {
        Mode::Points => {
            if n == 0 {
                warnings.push(format!("{label}: POINTS with no vertices"));
            }
            (indices.to_vec(), Vec::new())
        }
        Mode::Lines => {
            if !n.is_multiple_of(2) {
                warnings.push(format!(
                    "{label}: LINES has an odd number of indices ({n}); the last one is ignored"
                ));
            }
            let lines = indices.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
            (Vec::new(), lines)
        }
        _ => {
            if n < 2 {
                warnings.push(format!(
                    "{label}: {name} needs at least 2 indices, has {n}; nothing drawn"
                ));
                return (Vec::new(), Vec::new());
            }
            let mut lines: Vec<[u32; 2]> = indices.windows(2).map(|w| [w[0], w[1]]).collect();
            if mode == Mode::LineLoop {
                lines.push([indices[n - 1], indices[0]]);
            }
            (Vec::new(), lines)
        }
    }
}

/// Clears [`Doc::draco_accessors`] when dropped, so a Draco primitive's decoded accessors
/// are never read for another primitive.
struct ClearDraco<'d, 'a>(&'d Doc<'a>);

impl Drop for ClearDraco<'_, '_> {
    fn drop(&mut self) {
        self.0.draco_accessors.borrow_mut().clear();
    }
}

/// [`triangles`] for a primitive, with warnings for what a triangle list should not have.
fn triangle_list(mode: Mode, indices: &[u32], at: &Site, warnings: &mut Vec<String>) -> Vec<u32> {
    let (corners, degenerate) = triangles(mode, indices);
    let label = at.label;
    if mode == Mode::Triangles && !indices.len().is_multiple_of(3) {
        let extra = indices.len() % 3;
        warnings.push(format!(
            "{label}: {extra} trailing indices ignored (not a whole triangle)"
        ));
    }
    if mode == Mode::Triangles && degenerate > 0 {
        warnings.push(format!(
            "{label}: dropped {degenerate} triangle(s) that repeat a vertex"
        ));
    }
    corners
}

/// Triangle-list corners for `indices` drawn in `mode`, and how many triangles were
/// dropped because they repeat a vertex.
fn triangles(mode: Mode, indices: &[u32]) -> (Vec<u32>, usize) {
    let tris: Vec<[u32; 3]> = match mode {
        Mode::TriangleStrip => indices
            .windows(3)
            .enumerate()
            .map(|(i, w)| {
                if i % 2 == 0 {
                    [w[0], w[1], w[2]]
                } else {
                    [w[0], w[2], w[1]]
                }
            })
            .collect(),
        Mode::TriangleFan => match indices.split_first() {
            Some((&first, rest)) => rest.windows(2).map(|w| [first, w[0], w[1]]).collect(),
            None => Vec::new(),
        },
        _ => indices
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect(),
    };
    let total = tris.len();
    let corners: Vec<u32> = tris
        .into_iter()
        .filter(|[a, b, c]| a != b && b != c && a != c)
        .flatten()
        .collect();
    let dropped = total - corners.len() / 3;
    (corners, dropped)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_the_winding() {
        let (s, d) = triangles(Mode::TriangleStrip, &[0, 1, 2, 3, 4]);
        assert_eq!((s, d), (vec![0, 1, 2, 1, 3, 2, 2, 3, 4], 0));
        let (f, _) = triangles(Mode::TriangleFan, &[0, 1, 2, 3]);
        assert_eq!(f, vec![0, 1, 2, 0, 2, 3]);
        let (t, d) = triangles(Mode::Triangles, &[0, 1, 2, 3, 3, 4, 5]);
        assert_eq!((t, d), (vec![0, 1, 2], 1));
        assert_eq!(triangles(Mode::TriangleFan, &[]).0, Vec::<u32>::new());
        assert_eq!(triangles(Mode::TriangleStrip, &[0, 1]).0, Vec::<u32>::new());
    }

    #[test]
    fn line_modes_follow_the_specification() {
        let mut w = Vec::new();
        let (p, l) = strokes(Mode::Points, &[3, 1, 2], "m", &mut w);
        assert_eq!((p, l, w.len()), (vec![3, 1, 2], vec![], 0));
        let (_, l) = strokes(Mode::Lines, &[0, 1, 2, 3], "m", &mut w);
        assert_eq!((l, w.len()), (vec![[0, 1], [2, 3]], 0));
        let (_, l) = strokes(Mode::LineStrip, &[0, 1, 2], "m", &mut w);
        assert_eq!((l, w.len()), (vec![[0, 1], [1, 2]], 0));
        // A loop closes: the last index joins the first.
        let (_, l) = strokes(Mode::LineLoop, &[0, 1, 2], "m", &mut w);
        assert_eq!((l, w.len()), (vec![[0, 1], [1, 2], [2, 0]], 0));
    }

    #[test]
    fn wrong_counts_warn_and_do_not_panic() {
        let mut w = Vec::new();
        let (_, l) = strokes(Mode::Lines, &[0, 1, 2], "mesh 4 primitive 1", &mut w);
        assert_eq!(l, vec![[0, 1]]);
        assert!(
            w[0].starts_with("mesh 4 primitive 1: LINES has an odd number of indices (3)"),
            "{w:?}"
        );
        for mode in [Mode::LineLoop, Mode::LineStrip] {
            for ix in [&[][..], &[7][..]] {
                w.clear();
                let (p, l) = strokes(mode, ix, "mesh 0 primitive 0", &mut w);
                assert!(p.is_empty() && l.is_empty());
                assert!(w[0].contains("needs at least 2 indices"), "{w:?}");
            }
        }
        w.clear();
        let (p, _) = strokes(Mode::Points, &[], "m", &mut w);
        assert!(p.is_empty() && w[0].contains("POINTS with no vertices"));
        w.clear();
        let (_, l) = strokes(Mode::Lines, &[], "m", &mut w);
        assert!(l.is_empty() && w.is_empty());
    }
}
