//! The serial facet geometry (copy of `build.rs` before it went parallel).

use glam::{DVec3, Vec3};

use crate::{Facet, DEGENERATE_ASPECT};

/// The facets of validated data, with normals and areas.
pub(crate) fn facets(positions: &[Vec3], corners: &[u32], sizes: Option<&[u32]>) -> Vec<Facet> {
    let facet = |first: usize, len: usize| {
        let (normal, area) = newell(positions, &corners[first..first + len]);
        // Validation keeps corners.len() < u32::MAX: the casts are lossless.
        Facet {
            first: first as u32,
            len: len as u32,
            normal,
            area,
        }
    };
    match sizes {
        None => (0..corners.len() / 3).map(|f| facet(3 * f, 3)).collect(),
        Some(sizes) => {
            let mut first = 0usize;
            sizes
                .iter()
                .map(|&len| {
                    let f = facet(first, len as usize);
                    first += len as usize;
                    f
                })
                .collect()
        }
    }
}

/// Unit normal and area of the polygon through `positions[ring[..]]`, or `(ZERO, 0)` if it is
/// degenerate (see [`DEGENERATE_ASPECT`]).
pub(crate) fn newell(positions: &[Vec3], ring: &[u32]) -> (Vec3, f32) {
    let at = |i: usize| positions[ring[i] as usize].as_dvec3();
    let p0 = at(0);
    let mut prev = at(1) - p0;
    let mut spread = prev.length_squared();
    let mut sum = DVec3::ZERO;
    for i in 2..ring.len() {
        let d = at(i) - p0;
        sum += prev.cross(d);
        spread += d.length_squared();
        prev = d;
    }
    let twice_area = sum.length();
    // Written so that NaN anywhere lands in the degenerate branch.
    let ok = twice_area.is_finite() && twice_area > DEGENERATE_ASPECT * spread;
    if !ok {
        return (Vec3::ZERO, 0.0);
    }
    let normal = (sum / twice_area).as_vec3();
    let area = (0.5 * twice_area).min(f64::from(f32::MAX)) as f32;
    (normal, area)
}
