//! Joining the chunks parsed in parallel: relative indices resolved, each model's elements numbered in first use, and the tobj models built.

use super::*;

/// Joins the chunks in order and resolves relative indices; `None` for a file the
/// sequential path must read.
pub(super) fn join(text_len: usize, parts: Vec<Part<'_>>) -> Option<Joined<'_>> {
    let mut colors = None;
    for p in &parts {
        match (colors, p.has_color) {
            (_, None) => {}
            (None, c) => colors = c,
            (Some(a), Some(b)) if a != b => return None,
            _ => {}
        }
    }
    let sum = |f: &dyn Fn(&Part) -> usize| parts.iter().map(f).sum::<usize>();
    let mut e = Elements {
        positions: Vec::with_capacity(sum(&|p| p.positions.len())),
        colors: Vec::with_capacity(sum(&|p| p.colors.len())),
        texcoords: Vec::with_capacity(sum(&|p| p.texcoords.len())),
        normals: Vec::with_capacity(sum(&|p| p.normals.len())),
        corners: Vec::with_capacity(sum(&|p| p.corners.len())),
        arities: Vec::with_capacity(sum(&|p| p.arities.len())),
    };
    let mut scan = Scan::default();
    let mut events = Vec::new();
    let mut lines = 0usize;
    let mut rewritten: Option<i64> = None;
    for mut p in parts {
        let base = [
            e.positions.len() / 3,
            e.texcoords.len() / 2,
            e.normals.len() / 3,
        ];
        if (0..3).any(|k| p.need[k] > base[k] as i64) {
            return None;
        }
        let corner_base = e.corners.len();
        for &(corner, kind, rel) in &p.relative {
            let index = u32::try_from(base[kind as usize] as i64 + rel)
                .ok()
                .filter(|&i| i != MISSING)?;
            p.corners[corner as usize][kind as usize] = index;
        }
        for mut ev in p.events.drain(..) {
            ev.faces += e.arities.len();
            ev.corners += corner_base;
            ev.texcoords += base[1];
            ev.normals += base[2];
            ev.line += lines;
            events.push(ev);
        }
        lines += p.newlines;
        e.positions.append(&mut p.positions);
        e.colors.append(&mut p.colors);
        e.texcoords.append(&mut p.texcoords);
        e.normals.append(&mut p.normals);
        e.corners.append(&mut p.corners);
        e.arities.append(&mut p.arities);
        scan.objects += p.objects;
        scan.line_elements += p.line_elements;
        scan.point_elements += p.point_elements;
        if p.rewritten {
            rewritten = Some(rewritten.unwrap_or(0) + p.rewrite_delta);
        }
    }
    scan.rewritten_len = rewritten.map(|d| (text_len as i64 + d).max(0) as u64);
    scan.positions = (e.positions.len() / 3) as u64;
    scan.texcoords = (e.texcoords.len() / 2) as u64;
    scan.normals = (e.normals.len() / 3) as u64;
    scan.faces = e.arities.len() as u64;
    scan.corners = e.corners.len() as u64;
    if u32::try_from(e.corners.len()).is_err() {
        return None;
    }
    Some(Joined {
        scan,
        elements: e,
        events,
        lines,
    })
}

impl<'a> Joined<'a> {
    /// The models as `tobj` builds them, and the materials of the libraries (loaded
    /// through `load_mtl`, in file order); the pre-scan's list of used materials is added
    /// to the returned scan.
    pub(in crate::obj) fn assemble(
        self,
        load_mtl: impl Fn(&Path) -> tobj::MTLLoadResult,
    ) -> (Vec<tobj::Model>, Vec<tobj::Material>, Scan<'a>) {
        let Joined {
            mut scan,
            elements: e,
            events,
            lines,
        } = self;

        // `tobj`'s state machine over the named lines, in file order.
        let mut materials: Vec<tobj::Material> = Vec::new();
        let mut names: HashMap<String, usize> = HashMap::new();
        let mut used = HashSet::new();
        let mut specs = Specs::default();
        let mut name = "unnamed_object";
        let mut material = None;
        for ev in &events {
            let pending = ev.faces > specs.first_face;
            match ev.kind {
                EventKind::Group(n) => {
                    if pending {
                        specs.pop(name, material, ev);
                    }
                    name = match n {
                        "" => "unnamed_object",
                        n => n,
                    };
                }
                EventKind::Mtllib(file) => {
                    // The loader turns every failure into a warning and an empty library.
                    if let Ok((mut mats, map)) = load_mtl(Path::new(file)) {
                        let offset = materials.len();
                        materials.append(&mut mats);
                        names.extend(map.into_iter().map(|(k, v)| (k, v + offset)));
                    }
                }
                EventKind::Usemtl(n) => {
                    if used.insert(n) {
                        scan.materials_used.push((ev.line + 1, n.to_owned()));
                    }
                    let new = names.get(n).copied();
                    if material != new && pending {
                        specs.pop(name, material, ev);
                    }
                    material = new;
                }
            }
        }
        let end = Event {
            faces: e.arities.len(),
            corners: e.corners.len(),
            texcoords: e.texcoords.len() / 2,
            normals: e.normals.len() / 3,
            line: lines,
            kind: EventKind::Group(""),
        };
        specs.pop(name, material, &end);
        let specs = specs.specs;
        let models = specs.par_iter().map(|s| build(&e, s)).collect();
        (models, materials, scan)
    }
}

/// First-use numbering of one index kind within a model: dense for a model that uses a
/// good share of the file's elements, hashed for a small one.
pub(super) enum Remap {
    Dense(Vec<u32>),
    Sparse(HashMap<u32, u32>),
}

impl Remap {
    pub(super) fn new(model_corners: usize, elements: usize) -> Self {
        match model_corners.saturating_mul(16) >= elements {
            true => Remap::Dense(vec![0; elements]),
            false => Remap::Sparse(HashMap::new()),
        }
    }

    /// The model's number for file element `i`, given `next` if it is new (then `true`).
    #[inline]
    pub(super) fn get_or_insert(&mut self, i: u32, next: u32) -> (u32, bool) {
        match self {
            Remap::Dense(v) => match v[i as usize] {
                0 => {
                    v[i as usize] = next + 1;
                    (next, true)
                }
                n => (n - 1, false),
            },
            Remap::Sparse(m) => match m.get(&i) {
                Some(&n) => (n, false),
                None => {
                    m.insert(i, next);
                    (next, true)
                }
            },
        }
    }
}

/// One model as `tobj::export_faces_multi_index` builds it (without triangulation).
pub(super) fn build(e: &Elements, s: &Spec) -> tobj::Model {
    let corners = &e.corners[s.corners.clone()];
    let arities = &e.arities[s.faces.clone()];
    let mut m = tobj::Mesh {
        material_id: s.material,
        ..Default::default()
    };
    m.indices.reserve_exact(corners.len());
    let mut pos = Remap::new(corners.len(), e.positions.len() / 3);
    let mut tex = s
        .texcoords
        .then(|| Remap::new(corners.len(), e.texcoords.len() / 2));
    let mut nor = s
        .normals
        .then(|| Remap::new(corners.len(), e.normals.len() / 3));
    if tex.is_some() {
        m.texcoord_indices.reserve_exact(corners.len());
    }
    if nor.is_some() {
        m.normal_indices.reserve_exact(corners.len());
    }
    for c in corners {
        let next = (m.positions.len() / 3) as u32;
        let (i, new) = pos.get_or_insert(c[0], next);
        if new {
            let v = c[0] as usize * 3;
            m.positions.extend_from_slice(&e.positions[v..v + 3]);
            if !e.colors.is_empty() {
                m.vertex_color.extend_from_slice(&e.colors[v..v + 3]);
            }
        }
        m.indices.push(i);
        if let Some(tex) = &mut tex {
            attribute(
                tex,
                c[1],
                &e.texcoords,
                2,
                &mut m.texcoords,
                &mut m.texcoord_indices,
            );
        }
        if let Some(nor) = &mut nor {
            attribute(
                nor,
                c[2],
                &e.normals,
                3,
                &mut m.normals,
                &mut m.normal_indices,
            );
        }
    }
    if arities.iter().any(|&a| a != 3) {
        m.face_arities = arities.to_vec();
    }
    tobj::Model {
        mesh: m,
        name: s.name.clone(),
    }
}

/// A corner's texture coordinate or normal (`n` floats each), with `tobj`'s fallbacks for
/// a missing index: the file's first element for the model's first corner, else the
/// previous corner's.
#[inline]
pub(super) fn attribute(
    remap: &mut Remap,
    index: u32,
    file: &[f32],
    n: usize,
    values: &mut Vec<f32>,
    indices: &mut Vec<u32>,
) {
    let index = match (index, indices.last()) {
        (MISSING, Some(&last)) => {
            indices.push(last);
            return;
        }
        (MISSING, None) => 0,
        (i, _) => i,
    };
    let (i, new) = remap.get_or_insert(index, (values.len() / n) as u32);
    if new {
        let at = index as usize * n;
        values.extend_from_slice(&file[at..at + n]);
    }
    indices.push(i);
}
