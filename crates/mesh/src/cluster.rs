//! Vertex clustering (Rossignac and Borrel 1993): a quick level of detail for a mesh far
//! too large to redraw at interactive rates. The bounding box is cut into cubic cells, every
//! vertex stands for the first vertex of its cell (so every attribute of a render vertex is
//! kept: no new vertex is made), and the triangles whose three corners fall in three
//! different cells remain, unless that turned them over. The cell size is searched so the count lands near the target; the
//! result depends on the data only (cells and representatives in vertex order).

use std::collections::HashMap;

use glam::Vec3;

/// The triangles of `triangles` (indices into `positions`) after clustering to about
/// `target` triangles, with the index of the input triangle each came from; `None` if the
/// mesh has no more than `target` triangles or no finite extent.
#[must_use]
pub fn cluster_triangles(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    target: usize,
) -> Option<(Vec<[u32; 3]>, Vec<u32>)> {
    if triangles.len() <= target || target == 0 {
        return None;
    }
    let (lo, hi) = positions
        .iter()
        .filter(|p| p.is_finite())
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let extent = (hi - lo).max_element();
    if !(extent.is_finite() && extent > 0.0) {
        return None;
    }
    // A closed surface keeps about two triangles per occupied cell, and the occupied cells
    // of a surface grow with the square of the cells along a side: start from that guess,
    // then halve the step towards the target a few times.
    let mut cells = ((target as f64 / 2.0).sqrt() as u32).clamp(4, 1 << 16);
    let mut best: Option<(Vec<[u32; 3]>, Vec<u32>)> = None;
    for _ in 0..6 {
        let (tris, from) = cluster(positions, triangles, lo, extent, cells);
        let n = tris.len();
        let fits = n <= target;
        if fits && best.as_ref().is_none_or(|b| n > b.0.len()) {
            best = Some((tris, from));
        }
        // Aim for 70 to 100 % of the target.
        if fits && n * 10 >= target * 7 {
            break;
        }
        let ratio = (target as f64 / n.max(1) as f64).sqrt().clamp(0.5, 2.0);
        let next =
            ((f64::from(cells) * ratio * if fits { 1.0 } else { 0.95 }) as u32).clamp(4, 1 << 16);
        if next == cells {
            break;
        }
        cells = next;
    }
    best.filter(|b| !b.0.is_empty())
}

/// One clustering with `cells` cells along the longest side of the box from `lo`.
fn cluster(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    lo: Vec3,
    extent: f32,
    cells: u32,
) -> (Vec<[u32; 3]>, Vec<u32>) {
    let scale = cells as f32 / extent;
    let last = i64::from(cells);
    let mut rep: HashMap<(i64, i64, i64), u32> = HashMap::new();
    let map: Vec<u32> = positions
        .iter()
        .enumerate()
        .map(|(v, p)| {
            if !p.is_finite() {
                return v as u32;
            }
            let c = ((*p - lo) * scale).floor();
            let key = (
                (c.x as i64).clamp(0, last),
                (c.y as i64).clamp(0, last),
                (c.z as i64).clamp(0, last),
            );
            *rep.entry(key).or_insert(v as u32)
        })
        .collect();
    let mut tris = Vec::new();
    let mut from = Vec::new();
    for (k, t) in triangles.iter().enumerate() {
        let Some(r) = t
            .iter()
            .map(|&i| map.get(i as usize).copied())
            .collect::<Option<Vec<u32>>>()
        else {
            continue;
        };
        if r[0] == r[1] || r[1] == r[2] || r[0] == r[2] {
            continue;
        }
        // A triangle the clustering turned over would show its back (culled: a hole): left
        // out, as are those that became degenerate.
        let normal = |v: [u32; 3]| {
            let [a, b, c] = v.map(|i| positions.get(i as usize).copied().unwrap_or(Vec3::ZERO));
            (b - a).cross(c - a)
        };
        if normal(*t).dot(normal([r[0], r[1], r[2]])) > 0.0 {
            tris.push([r[0], r[1], r[2]]);
            from.push(k as u32);
        }
    }
    (tris, from)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Mesh;

    #[test]
    fn a_dense_sphere_clusters_near_the_target_and_stays_a_sphere() {
        let tri = Mesh::sphere(1.0, 400, 200).unwrap().triangulate();
        assert!(tri.triangles.len() > 150_000);
        let (tris, from) =
            cluster_triangles(&tri.positions, &tri.triangles, 20_000).expect("clustered");
        assert!(
            (14_000..=20_000).contains(&tris.len()),
            "{} triangles",
            tris.len()
        );
        assert_eq!(tris.len(), from.len());
        // Every kept vertex is an input vertex on the sphere; no triangle faces inwards
        // (slivers may lean a few degrees past the tangent plane).
        for t in &tris {
            let [a, b, c] = t.map(|i| tri.positions[i as usize]);
            assert!((a.length() - 1.0).abs() < 1e-5);
            let n = (b - a).cross(c - a);
            let lean = n.normalize().dot((a + b + c).normalize());
            assert!(lean > -0.1, "turned inside out: {a} {b} {c} n {n}");
        }
        // Small enough meshes are left alone.
        assert!(cluster_triangles(&tri.positions, &tri.triangles, tri.triangles.len()).is_none());
    }
}
