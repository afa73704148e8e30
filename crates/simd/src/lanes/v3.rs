//! [`V3`]: one 3-vector per lane, as three [`F8`].

use super::*;

/// Three [`F8`]: one 3-vector per lane.
pub struct V3<L: Level> {
    pub x: F8<L>,
    pub y: F8<L>,
    pub z: F8<L>,
}

impl<L: Level> Clone for V3<L> {
    #[inline(always)]
    fn clone(&self) -> Self {
        *self
    }
}

impl<L: Level> Copy for V3<L> {}

impl<L: Level> std::fmt::Debug for V3<L> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("V3")
            .field("x", &self.x)
            .field("y", &self.y)
            .field("z", &self.z)
            .finish()
    }
}

impl<L: Level> Default for V3<L> {
    #[inline(always)]
    fn default() -> Self {
        Self::new(F8::ZERO, F8::ZERO, F8::ZERO)
    }
}

impl<L: Level> V3<L> {
    #[inline(always)]
    #[must_use]
    pub fn new(x: F8<L>, y: F8<L>, z: F8<L>) -> Self {
        Self { x, y, z }
    }

    /// The same vector in every lane.
    #[inline(always)]
    #[must_use]
    pub fn splat(v: glam::Vec3) -> Self {
        Self::new(F8::splat(v.x), F8::splat(v.y), F8::splat(v.z))
    }

    /// The vector of three stored lanes.
    #[inline(always)]
    #[must_use]
    pub fn get(v: &[Lane; 3]) -> Self {
        Self::new(v[0].get(), v[1].get(), v[2].get())
    }

    /// Stores the vector into three lanes.
    #[inline(always)]
    pub fn set(self, v: &mut [Lane; 3]) {
        v[0].set(self.x);
        v[1].set(self.y);
        v[2].set(self.z);
    }

    /// Lane `i` as a vector.
    #[inline(always)]
    #[must_use]
    pub fn lane(self, i: usize) -> glam::Vec3 {
        glam::Vec3::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }

    #[inline(always)]
    #[must_use]
    pub fn dot(self, o: Self) -> F8<L> {
        mad(self.x, o.x, mad(self.y, o.y, self.z * o.z))
    }

    #[inline(always)]
    #[must_use]
    pub fn scale(self, s: F8<L>) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }

    /// The cross product `self × o`.
    #[inline(always)]
    #[must_use]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            mad(self.y, o.z, -(self.z * o.y)),
            mad(self.z, o.x, -(self.x * o.z)),
            mad(self.x, o.y, -(self.y * o.x)),
        )
    }

    /// Unit length, or zero where the length is zero or not finite.
    #[inline(always)]
    #[must_use]
    pub fn normalize_or_zero(self) -> Self {
        let len2 = self.dot(self);
        let inv = len2.sqrt().recip();
        let ok = len2.gt(F8::ZERO) & inv.lt(F8::splat(f32::INFINITY));
        self.scale(F8::select(ok, inv, F8::ZERO))
    }
}

/// Component-wise product with the same vector in every lane.
impl<L: Level> Mul<glam::Vec3> for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: glam::Vec3) -> Self {
        Self::new(self.x * c.x, self.y * c.y, self.z * c.z)
    }
}

/// Component-wise product.
impl<L: Level> Mul for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
}

/// A vector scaled per lane.
impl<L: Level> Mul<F8<L>> for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, s: F8<L>) -> Self {
        self.scale(s)
    }
}

impl<L: Level> Add for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<L: Level> Sub for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<L: Level> Neg for V3<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}
