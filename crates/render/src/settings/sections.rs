//! Section planes: the world-space planes that cut the model away, and the cap colour
//! where a cut shows a closed mesh's inside.

use glam::{Mat4, Vec4};

/// Section planes: what lies on a plane's negative side is cut away, and where the inside
/// of a closed mesh shows through the cut it is filled with the cap colour. A cap is drawn
/// where a back face is seen, so an open surface seen from behind gets it too. The ground
/// plane is never cut; shadows are cast by the whole model.
#[derive(Clone, Debug, PartialEq)]
pub struct Sections {
    /// At most [`Sections::MAX`] world-space planes `(nx, ny, nz, d)` with unit normals:
    /// a point `p` is kept where `n·p + d >= 0` for every plane.
    pub planes: Vec<Vec4>,
    /// Linear RGB of the caps, or `None` to leave the cut open.
    pub cap: Option<glam::Vec3>,
}

impl Default for Sections {
    fn default() -> Self {
        Self {
            planes: Vec::new(),
            cap: Some(Self::CAP),
        }
    }
}

impl Sections {
    /// Most planes at once.
    pub const MAX: usize = crate::raster::MAX_SECTIONS;
    /// The default cap colour (linear RGB; sRGB #db6050), a red that stands apart from
    /// most materials.
    pub const CAP: glam::Vec3 = glam::Vec3::new(0.708, 0.117, 0.080);

    /// The plane `n·p + d = 0` scaled to a unit normal, keeping the side `n` points to.
    ///
    /// # Errors
    /// A zero or non-finite normal, or a non-finite offset.
    pub fn plane(n: glam::Vec3, d: f32) -> Result<Vec4, String> {
        let len = n.length();
        if !(n.is_finite() && d.is_finite()) || len < 1e-12 || !len.is_finite() {
            return Err(format!(
                "section plane {},{},{},{}: the normal must be finite and not zero, the offset finite",
                n.x, n.y, n.z, d
            ));
        }
        Ok((n / len).extend(d / len))
    }

    /// `NX,NY,NZ,D` (the command line's `--section`).
    ///
    /// # Errors
    /// Not four numbers, or not a plane ([`Sections::plane`]).
    pub fn parse_plane(s: &str) -> Result<Vec4, String> {
        let v: Vec<f32> = s
            .split(',')
            .map(|p| p.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("section plane '{s}': expected NX,NY,NZ,D (four numbers)"))?;
        match v[..] {
            [x, y, z, d] => Self::plane(glam::Vec3::new(x, y, z), d),
            _ => Err(format!(
                "section plane '{s}': expected NX,NY,NZ,D (four numbers)"
            )),
        }
    }

    /// Adds a plane.
    ///
    /// # Errors
    /// Already [`Sections::MAX`] planes.
    pub fn push(&mut self, plane: Vec4) -> Result<(), String> {
        if self.planes.len() >= Self::MAX {
            return Err(format!("at most {} section planes", Self::MAX));
        }
        self.planes.push(plane);
        Ok(())
    }

    /// No plane cuts.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.planes.is_empty()
    }

    /// The planes in the clip space of `view_projection` (world to clip), into `out`;
    /// returns how many. A world plane `P` becomes `(VP)^-T P`, computed in f64.
    pub fn to_clip(&self, view_projection: Mat4, out: &mut [Vec4; Self::MAX]) -> usize {
        let inv_t = view_projection.as_dmat4().inverse().transpose();
        let mut n = 0;
        for p in self.planes.iter().take(Self::MAX) {
            let c = (inv_t * p.as_dvec4()).as_vec4();
            if c.is_finite() {
                out[n] = c;
                n += 1;
            }
        }
        n
    }
}
