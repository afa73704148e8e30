//! UV generators, the textbook's §9.5: texture space taken from an auxiliary surface (a
//! plane, a cylinder or a sphere) or from a box, as per-point maps. Seams and poles need the
//! facets around a point; `mesh::uvgen` applies these maps to a mesh and handles them.
//!
//! # Frame
//!
//! A map works in a [`UvFrame`]: a centre, three orthonormal axes and a half extent per
//! axis, usually the model's bounding box ([`UvFrame::from_bounds`]), so every map covers the
//! model exactly once. Points are first taken into the frame: `rotated = axes^T (p -
//! centre)`; planar and box maps, and the height of a cylindrical map, divide by the half
//! extents (the box becomes `[-1, 1]^3`); angles (the longitude `u` of the cylinder and the
//! sphere, the sphere's latitude) are measured in the rotated frame at a uniform scale, so a
//! sphere maps to even longitude and latitude whatever its bounding box. Arithmetic is in
//! f64; a frame is always finite, its axes orthonormal and right-handed, its half extents
//! positive.
//!
//! # Maps (UV convention of glTF: origin top left, `v` downwards)
//!
//! | generator | `u` | `v` |
//! |---|---|---|
//! | `planar:a` | across the box face seen from `+a`, left to right | top to bottom |
//! | `cylindrical:a` | longitude around `a`, `[0, 1)` | `+a` end 0, `-a` end 1 |
//! | `spherical:a` | longitude around `a`, `[0, 1)` | polar angle from `+a` / pi |
//! | `box` | as `planar` on the face the normal points to most | same |
//!
//! Faces are upright seen from outside, as `Mesh::cube` maps them: `+x` has `u` along `-z`,
//! `+y` along `+x` with `-z` up, `+z` along `+x`; the opposite faces are their mirror images.
//! Longitude runs from the axis after `a` towards the one after that (cyclically: around `y`
//! from `+z` towards `+x`, as the primitive builders; around `z` from `+x` towards `+y`),
//! counter-clockwise seen from `+a`. Points within [`SINGULAR_EPS`] of the axis have no
//! longitude ([`MappedUv::on_axis`]; `u` is 0 there). A non-finite point maps to `(0, 0)`,
//! on the axis.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};

/// Distance from the axis of a cylindrical or spherical map, as a fraction of the frame's
/// largest half extent, below which a point has no longitude.
pub const SINGULAR_EPS: f64 = 1e-5;

/// Smallest half extent of a frame axis relative to the largest (a flat model's thin axis).
pub const MIN_EXTENT_RATIO: f64 = 1e-6;

mod names;

pub use names::ParseUvGeneratorError;

/// A coordinate axis of a [`UvFrame`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// All axes, in order.
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    /// 0, 1 or 2.
    #[must_use]
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }
}

/// How a point becomes a UV.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UvGenerator {
    /// Projection along `axis` onto the frame's face (an arbitrary plane: rotate the frame).
    Planar { axis: Axis },
    /// Longitude around `axis`, height along it.
    Cylindrical { axis: Axis },
    /// Longitude and latitude about `axis` (the poles on it).
    Spherical { axis: Axis },
    /// Cube projection: per facet, the planar map of the face its normal points to most.
    Box,
}

/// A mapped point before seam handling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MappedUv {
    /// Finite; `u` in `[0, 1)` for cylindrical and spherical maps.
    pub uv: Vec2,
    /// The point lies on the axis of a cylindrical or spherical map, where the longitude is
    /// undefined (poles, a cone's apex), or is not finite.
    pub on_axis: bool,
}

/// The space a UV map works in (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvFrame {
    centre: DVec3,
    /// Orthonormal, right-handed: `axes[2] = axes[0] x axes[1]`.
    axes: [DVec3; 3],
    /// Positive and finite.
    half: DVec3,
}

impl Default for UvFrame {
    fn default() -> Self {
        Self::UNIT
    }
}

impl UvFrame {
    /// The cube `[-1, 1]^3`, axis aligned.
    pub const UNIT: UvFrame = UvFrame {
        centre: DVec3::ZERO,
        axes: [DVec3::X, DVec3::Y, DVec3::Z],
        half: DVec3::ONE,
    };

    /// The axis-aligned box `[lo, hi]` (corners in any order; see [`UvFrame::new`] for
    /// non-finite or flat boxes).
    #[must_use]
    pub fn from_bounds(lo: Vec3, hi: Vec3) -> Self {
        let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
        Self::from_parts(
            0.5 * lo + 0.5 * hi,
            [DVec3::X, DVec3::Y, DVec3::Z],
            0.5 * (hi - lo),
        )
    }

    /// A frame centred at `centre` with axes `x_axis`, `y_axis` (made orthonormal by
    /// Gram-Schmidt; the third is their cross product) and `half_extent` along each. Repairs
    /// rather than fails: a non-finite centre is the origin, a degenerate axis is replaced by
    /// a perpendicular one, half extents are taken absolute, and zero or non-finite ones
    /// become [`MIN_EXTENT_RATIO`] of the largest (all 1 if none is usable).
    #[must_use]
    pub fn new(centre: Vec3, x_axis: Vec3, y_axis: Vec3, half_extent: Vec3) -> Self {
        let x = x_axis.as_dvec3().try_normalize().unwrap_or(DVec3::X);
        let y = (y_axis.as_dvec3() - x * x.dot(y_axis.as_dvec3()))
            .try_normalize()
            .unwrap_or_else(|| x.any_orthonormal_vector());
        Self::from_parts(
            centre.as_dvec3(),
            [x, y, x.cross(y)],
            half_extent.as_dvec3(),
        )
    }

    fn from_parts(centre: DVec3, axes: [DVec3; 3], half: DVec3) -> Self {
        let centre = if centre.is_finite() {
            centre
        } else {
            DVec3::ZERO
        };
        let half =
            DVec3::from_array(
                half.abs()
                    .to_array()
                    .map(|h| if h.is_finite() { h } else { 0.0 }),
            );
        let largest = half.max_element();
        let half = if largest > 0.0 {
            half.max(DVec3::splat(largest * MIN_EXTENT_RATIO))
        } else {
            DVec3::ONE
        };
        Self { centre, axes, half }
    }

    #[must_use]
    pub fn centre(&self) -> Vec3 {
        self.centre.as_vec3()
    }

    #[must_use]
    pub fn axes(&self) -> [Vec3; 3] {
        self.axes.map(|a| a.as_vec3())
    }

    #[must_use]
    pub fn half_extent(&self) -> Vec3 {
        self.half.as_vec3()
    }

    /// `p` in the frame's rotated axes, relative to the centre, unscaled.
    fn rotated(&self, p: Vec3) -> DVec3 {
        let d = p.as_dvec3() - self.centre;
        DVec3::new(
            self.axes[0].dot(d),
            self.axes[1].dot(d),
            self.axes[2].dot(d),
        )
    }

    /// `p` in box coordinates: the frame's box is `[-1, 1]^3`.
    #[must_use]
    pub fn local(&self, p: Vec3) -> Vec3 {
        (self.rotated(p) / self.half).as_vec3()
    }

    /// A direction in the frame's axes (rotation only).
    #[must_use]
    pub fn direction(&self, n: Vec3) -> Vec3 {
        let n = n.as_dvec3();
        DVec3::new(
            self.axes[0].dot(n),
            self.axes[1].dot(n),
            self.axes[2].dot(n),
        )
        .as_vec3()
    }
}

/// `(u axis, up axis)` of the box face seen from outside along `axis` (`positive` or not),
/// as signed axis indices `(index, sign)`.
fn face_axes(axis: Axis, positive: bool) -> ((usize, f64), (usize, f64)) {
    match (axis, positive) {
        (Axis::X, true) => ((2, -1.0), (1, 1.0)),
        (Axis::X, false) => ((2, 1.0), (1, 1.0)),
        (Axis::Y, true) => ((0, 1.0), (2, -1.0)),
        (Axis::Y, false) => ((0, 1.0), (2, 1.0)),
        (Axis::Z, true) => ((0, 1.0), (1, 1.0)),
        (Axis::Z, false) => ((0, -1.0), (1, 1.0)),
    }
}

/// The face the direction `n` (frame axes) points to most; ties prefer x, then y; a zero or
/// non-finite direction gives `+z`.
fn dominant_face(n: DVec3) -> (Axis, bool) {
    let a = n.abs();
    if !n.is_finite() || a.max_element() == 0.0 {
        return (Axis::Z, true);
    }
    let axis = if a.x >= a.y && a.x >= a.z {
        Axis::X
    } else if a.y >= a.z {
        Axis::Y
    } else {
        Axis::Z
    };
    (axis, n[axis.index()] >= 0.0)
}

/// The planar map of box coordinates `q` on a face.
fn face_uv(q: DVec3, axis: Axis, positive: bool) -> DVec3 {
    let ((ui, us), (vi, vs)) = face_axes(axis, positive);
    DVec3::new(0.5 + 0.5 * us * q[ui], 0.5 - 0.5 * vs * q[vi], 0.0)
}

/// The two axes after `axis`, cyclically: longitude runs from the first towards the second.
fn around(axis: Axis) -> (usize, usize) {
    ((axis.index() + 1) % 3, (axis.index() + 2) % 3)
}

/// A UV from f64 parts, `(0, 0)` if not finite; `u` folded into `[0, 1)` if `wrap`.
fn finish(u: f64, v: f64, wrap: bool) -> Vec2 {
    let mut uv = Vec2::new(u as f32, v as f32);
    if wrap {
        uv.x = uv.x.rem_euclid(1.0);
        if uv.x >= 1.0 {
            uv.x = 0.0;
        }
    }
    if uv.is_finite() {
        uv
    } else {
        Vec2::ZERO
    }
}

impl UvGenerator {
    /// The generators the command line and the viewer offer.
    pub const PRESETS: [UvGenerator; 6] = [
        UvGenerator::Planar { axis: Axis::X },
        UvGenerator::Planar { axis: Axis::Y },
        UvGenerator::Planar { axis: Axis::Z },
        UvGenerator::Cylindrical { axis: Axis::Y },
        UvGenerator::Spherical { axis: Axis::Y },
        UvGenerator::Box,
    ];

    /// True for maps whose `u` is a longitude (it wraps from 1 back to 0).
    #[must_use]
    pub fn wraps_u(&self) -> bool {
        match self {
            UvGenerator::Cylindrical { .. } | UvGenerator::Spherical { .. } => true,
            UvGenerator::Planar { .. } | UvGenerator::Box => false,
        }
    }

    /// The UV of `p` with normal `n` (only [`UvGenerator::Box`] reads `n`), in `frame`.
    #[must_use]
    pub fn map(&self, frame: &UvFrame, p: Vec3, n: Vec3) -> Vec2 {
        self.map_point(frame, p, n).uv
    }

    /// [`map`](Self::map), also saying whether the point is on the axis.
    #[must_use]
    pub fn map_point(&self, frame: &UvFrame, p: Vec3, n: Vec3) -> MappedUv {
        let r = frame.rotated(p);
        if !r.is_finite() {
            return MappedUv {
                uv: Vec2::ZERO,
                on_axis: true,
            };
        }
        let q = r / frame.half;
        let plain = |uv: DVec3| MappedUv {
            uv: finish(uv.x, uv.y, false),
            on_axis: false,
        };
        match *self {
            UvGenerator::Planar { axis } => plain(face_uv(q, axis, true)),
            UvGenerator::Box => {
                let (axis, positive) = dominant_face(frame.direction(n).as_dvec3());
                plain(face_uv(q, axis, positive))
            }
            UvGenerator::Cylindrical { axis } | UvGenerator::Spherical { axis } => {
                let s = r / frame.half.max_element();
                let (a, b) = around(axis);
                let radial = libm::hypot(s[a], s[b]);
                let on_axis = radial <= SINGULAR_EPS;
                let u = if on_axis {
                    0.0
                } else {
                    libm::atan2(s[b], s[a]) / TAU
                };
                let v = match self {
                    UvGenerator::Spherical { .. } => libm::atan2(radial, s[axis.index()]) / PI,
                    _ => 0.5 - 0.5 * q[axis.index()],
                };
                MappedUv {
                    uv: finish(u, v, true),
                    on_axis,
                }
            }
        }
    }

    /// The map of a point of a facet with normal `n` that surrounds the axis of a
    /// cylindrical or spherical map (a cap, which no longitude can map without a smear):
    /// planar along the axis, seen from the side `n` faces (from `+axis` if `n` has no
    /// component along it), as the primitive builders map their caps. For planar and box
    /// maps, [`map`](Self::map).
    #[must_use]
    pub fn cap(&self, frame: &UvFrame, p: Vec3, n: Vec3) -> Vec2 {
        match *self {
            UvGenerator::Cylindrical { axis } | UvGenerator::Spherical { axis } => {
                let r = frame.rotated(p);
                if !r.is_finite() {
                    return Vec2::ZERO;
                }
                let facing = frame.direction(n)[axis.index()];
                let uv = face_uv(r / frame.half, axis, facing >= 0.0 || facing.is_nan());
                finish(uv.x, uv.y, false)
            }
            UvGenerator::Planar { .. } | UvGenerator::Box => self.map(frame, p, n),
        }
    }
}

#[cfg(test)]
mod tests;
