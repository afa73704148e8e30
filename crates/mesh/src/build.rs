//! Validation of [`MeshData`] and the facet geometry every [`Mesh`](super::Mesh) carries:
//! normals and areas.
//!
//! Facet normals use Newell's method, written as the sum of the fan cross products about the
//! facet's first corner (the same vector area, with less cancellation far from the origin),
//! in `f64` so that neither huge nor tiny `f32` coordinates overflow or underflow. A facet is
//! degenerate (normal `Vec3::ZERO`, area 0) when that vector is non-finite or shorter than
//! [`DEGENERATE_ASPECT`] times the squared spread of its corners.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::par::MIN_ITEMS;
use super::{Channel, Facet, MeshData, MeshError};

/// Below this ratio of `|vector area| / sum |p_i - p_0|^2` a facet counts as degenerate. For a
/// triangle the ratio is about half the sine of its sharpest angle, or its height over its
/// length: at 1e-7 the height is below the resolution of `f32` coordinates of that size, so
/// the computed normal would be rounding noise (and, with angle weighting, the sliver's
/// almost-180-degree corner would give that noise a large weight).
pub const DEGENERATE_ASPECT: f64 = 1e-7;

/// Checks every size and index of `data`; on success nothing derived from it can fail.
pub(super) fn validate(data: &MeshData) -> Result<(), MeshError> {
    let vertex_count = data.positions.len();
    let corner_count = data.corners.len();
    // Derived indices (edges, render vertices = vertices + extra corners) must fit in u32,
    // and u32::MAX itself is reserved for NO_FACET and "unset" markers.
    if vertex_count
        .checked_add(corner_count)
        .is_none_or(|n| n >= u32::MAX as usize)
    {
        return Err(MeshError::TooLarge(
            "vertices + corners must stay below 2^32 - 1",
        ));
    }
    match &data.facet_sizes {
        None if !corner_count.is_multiple_of(3) => {
            return Err(MeshError::NotTriangles(corner_count))
        }
        None => {}
        Some(sizes) => {
            let mut sum = 0u64;
            for (facet, &len) in sizes.iter().enumerate() {
                if len < 3 {
                    return Err(MeshError::FacetTooSmall { facet, len });
                }
                sum = sum.saturating_add(u64::from(len));
            }
            if sum != corner_count as u64 {
                return Err(MeshError::FacetSizes {
                    sum,
                    corners: corner_count,
                });
            }
        }
    }
    if let Some(corner) = data
        .corners
        .iter()
        .position(|&v| v as usize >= vertex_count)
    {
        let index = data.corners[corner];
        return Err(MeshError::VertexIndex {
            corner,
            index,
            count: vertex_count,
        });
    }
    let vertices = vertex_count;
    validate_channel("normals", data.normals.as_ref(), vertices, corner_count)?;
    for uv in &data.uvs {
        validate_channel("uvs", Some(uv), vertices, corner_count)?;
    }
    validate_channel("tangents", data.tangents.as_ref(), vertices, corner_count)?;
    validate_channel("colors", data.colors.as_ref(), vertices, corner_count)
}

/// A per-vertex channel needs one value per vertex; a per-corner channel one in-range index
/// per corner.
fn validate_channel<T>(
    channel: &'static str,
    ch: Option<&Channel<T>>,
    vertices: usize,
    corners: usize,
) -> Result<(), MeshError> {
    let Some(ch) = ch else { return Ok(()) };
    let count = ch.values.len();
    match &ch.indices {
        None if count != vertices => Err(MeshError::ChannelLength {
            channel,
            got: count,
            expected: vertices,
        }),
        None => Ok(()),
        Some(ix) if ix.len() != corners => Err(MeshError::ChannelLength {
            channel,
            got: ix.len(),
            expected: corners,
        }),
        Some(ix) => match ix.iter().position(|&i| i as usize >= count) {
            Some(corner) => Err(MeshError::ChannelIndex {
                channel,
                corner,
                index: ix[corner],
                count,
            }),
            None => Ok(()),
        },
    }
}

/// The facets of validated data, with normals and areas (in parallel over facets).
pub(super) fn facets(positions: &[Vec3], corners: &[u32], sizes: Option<&[u32]>) -> Vec<Facet> {
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
        None => (0..corners.len() / 3)
            .into_par_iter()
            .with_min_len(MIN_ITEMS)
            .map(|f| facet(3 * f, 3))
            .collect(),
        Some(sizes) => {
            // The first corners (a prefix sum) are cheap; the normals are not.
            let mut first = 0u32;
            let firsts: Vec<u32> = sizes
                .iter()
                .map(|&len| {
                    let f = first;
                    first += len;
                    f
                })
                .collect();
            firsts
                .par_iter()
                .zip(sizes)
                .with_min_len(MIN_ITEMS)
                .map(|(&first, &len)| facet(first as usize, len as usize))
                .collect()
        }
    }
}

/// Unit normal and area of the polygon through `positions[ring[..]]`, or `(ZERO, 0)` if it is
/// degenerate (see [`DEGENERATE_ASPECT`]).
pub(super) fn newell(positions: &[Vec3], ring: &[u32]) -> (Vec3, f32) {
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
