//! Shadow rays eight at a time: a packet of rays walks the hierarchy together, each node's
//! boxes tested against all of its live rays at once, so rays from neighbouring pixels
//! (which visit nearly the same nodes) fetch and test each node once instead of eight
//! times. The answers are [`Scene::occluded`]'s, ray for ray: the same box test (its
//! operations and its NaN rule, lane by lane), the same triangle test, and an any-hit query
//! does not depend on the order leaves are visited in.

use realist_simd::kernel::{dispatch, KernelJob};
use realist_simd::{KernelKind, Level};

use crate::bvh::{Bvh, Slabs, LEAF};
use crate::scene::{Ray, Scene};
use crate::triangle::Sheared;

/// Rays in a packet.
pub const PACKET: usize = 8;

/// `a < b ? a : b`: SSE's `minps`, which takes the second operand when either is NaN, as
/// the one-ray traversal's `Vec4::min` does.
#[inline(always)]
fn min_ps(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

/// `a > b ? a : b` (`maxps`).
#[inline(always)]
fn max_ps(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// A packet's rays in one space (the world's, or an instance's own): origins, reciprocal
/// directions and ranges as lanes.
struct Lanes {
    o: [[f32; PACKET]; 3],
    inv: [[f32; PACKET]; 3],
    tmin: [f32; PACKET],
    tmax: [f32; PACKET],
}

impl Lanes {
    /// No live lane: an empty range never passes a box.
    fn empty() -> Self {
        Self {
            o: [[0.0; PACKET]; 3],
            inv: [[0.0; PACKET]; 3],
            tmin: [0.0; PACKET],
            tmax: [f32::NEG_INFINITY; PACKET],
        }
    }

    /// Lane `i` is the ray of `slabs` over `(tmin, tmax)`.
    fn set(&mut self, i: usize, slabs: &Slabs, tmin: f32, tmax: f32) {
        for k in 0..3 {
            self.o[k][i] = slabs.origin[k];
            self.inv[k][i] = slabs.inv[k];
        }
        (self.tmin[i], self.tmax[i]) = (tmin, tmax);
    }

    /// The lanes whose ray meets the box `(lo, hi)` within its range: the one-ray test
    /// ([`crate::bvh::Slabs::enter`] and the wide traversal's), lane by lane.
    #[inline(always)]
    fn meets(&self, lo: [f32; 3], hi: [f32; 3]) -> u32 {
        let mut bits = 0;
        for i in 0..PACKET {
            let t0x = (lo[0] - self.o[0][i]) * self.inv[0][i];
            let t1x = (hi[0] - self.o[0][i]) * self.inv[0][i];
            let t0y = (lo[1] - self.o[1][i]) * self.inv[1][i];
            let t1y = (hi[1] - self.o[1][i]) * self.inv[1][i];
            let t0z = (lo[2] - self.o[2][i]) * self.inv[2][i];
            let t1z = (hi[2] - self.o[2][i]) * self.inv[2][i];
            let enter = max_ps(
                max_ps(min_ps(t0x, t1x), min_ps(t0y, t1y)),
                max_ps(min_ps(t0z, t1z), self.tmin[i]),
            );
            let leave = min_ps(
                min_ps(max_ps(t0x, t1x), max_ps(t0y, t1y)),
                min_ps(max_ps(t0z, t1z), self.tmax[i]),
            );
            bits |= u32::from(enter <= leave) << i;
        }
        bits
    }
}

/// What a packet's walk does at a leaf: `test(first, count, rays, stack)` tests leaf slots
/// `first..first + count` against the live rays `rays` (bits) and returns those blocked;
/// it may use `stack` above its current length (a second level of hierarchy). A trait,
/// not a closure: a closure is compiled on its own, without the kernel's instructions.
trait Leaves {
    fn test(&mut self, first: u32, count: u32, rays: u32, stack: &mut Vec<(u32, u32)>) -> u32;
}

impl Bvh {
    /// The rays of `mask` (of `lanes`) that `leaves` finds blocked, walking the wide tree
    /// once for the packet; a blocked ray leaves the walk.
    #[inline(always)]
    fn any_packet(
        &self,
        lanes: &Lanes,
        mask: u32,
        stack: &mut Vec<(u32, u32)>,
        leaves: &mut impl Leaves,
    ) -> u32 {
        if self.wide.is_empty() || mask == 0 {
            return 0;
        }
        let base = stack.len();
        let mut live = mask;
        stack.push((0, mask));
        while stack.len() > base {
            let Some((code, m)) = stack.pop() else {
                break;
            };
            let m = m & live;
            if m == 0 {
                continue;
            }
            if code & LEAF != 0 {
                let [first, count] = self.leaves[(code & !LEAF) as usize];
                live &= !leaves.test(first, count, m, stack);
                if live == 0 {
                    break;
                }
                continue;
            }
            let n = &self.wide[code as usize];
            for j in (0..4).rev() {
                if n.used >> j & 1 == 0 {
                    continue;
                }
                let lo = [n.lo[0][j], n.lo[1][j], n.lo[2][j]];
                let hi = [n.hi[0][j], n.hi[1][j], n.hi[2][j]];
                let met = lanes.meets(lo, hi) & m;
                if met != 0 {
                    stack.push((n.child[j], met));
                }
            }
        }
        stack.truncate(base);
        mask & !live
    }
}

/// A packet query, compiled per kernel.
struct Job<'a> {
    scene: &'a Scene,
    rays: &'a [Ray],
}

impl KernelJob for Job<'_> {
    type Output = u32;
    #[inline(always)]
    fn run<L: Level>(self) -> u32 {
        let rays = &self.rays[..self.rays.len().min(PACKET)];
        let mut top = Instances {
            scene: self.scene,
            rays,
            world: [None; PACKET],
        };
        let mut valid = 0u32;
        let mut lanes = Lanes::empty();
        for (i, r) in rays.iter().enumerate() {
            if r.is_valid() {
                let s = Slabs::new(r.origin, r.dir);
                lanes.set(i, &s, r.tmin, r.tmax);
                top.world[i] = Some(s);
                valid |= 1 << i;
            }
        }
        if valid == 0 {
            return 0;
        }
        let mut stack = STACK.take();
        stack.clear();
        let blocked = self
            .scene
            .tlas
            .any_packet(&lanes, valid, &mut stack, &mut top);
        STACK.set(stack);
        blocked
    }
}

thread_local! {
    /// Each thread's packet stack (the two levels share it, the meshes' above the
    /// instances'), taken for a query and put back.
    static STACK: std::cell::Cell<Vec<(u32, u32)>> = const { std::cell::Cell::new(Vec::new()) };
}

impl Scene {
    /// [`Scene::occluded`] for up to [`PACKET`] rays at once (more are not looked at): bit
    /// `i` is set if ray `i` is blocked. Fastest when the rays are coherent (neighbouring
    /// pixels' shadow rays to one light). Compiled per kernel: the lanes' box tests are one
    /// eight-wide instruction each with AVX2 (the same bits as the baseline's two four-wide
    /// ones; nothing is fused).
    #[must_use]
    pub fn occluded_packet(&self, rays: &[Ray]) -> u32 {
        dispatch(KernelKind::best(), Job { scene: self, rays })
    }
}

/// The instances' tree's leaves, for a packet in world space.
struct Instances<'a> {
    scene: &'a Scene,
    rays: &'a [Ray],
    /// The valid rays' slab constants.
    world: [Option<Slabs>; PACKET],
}

impl Leaves for Instances<'_> {
    #[inline(always)]
    fn test(&mut self, first: u32, count: u32, m: u32, stack: &mut Vec<(u32, u32)>) -> u32 {
        let mut blocked = 0;
        for slot in first..first + count {
            let k = self.scene.tlas.order[slot as usize] as usize;
            blocked |= self.instance(k, m & !blocked, stack);
            if m & !blocked == 0 {
                break;
            }
        }
        blocked
    }
}

impl Instances<'_> {
    /// The rays of `mask` that instance `k` blocks (the one-ray query's leaf of the
    /// instances' tree, for the packet): each ray tested against the instance's box and
    /// carried into its space, then the mesh's tree walked once for all of them.
    #[inline(always)]
    fn instance(&self, k: usize, mask: u32, stack: &mut Vec<(u32, u32)>) -> u32 {
        let scene = self.scene;
        let inst = &scene.instances[k];
        let mesh = &scene.meshes[inst.mesh as usize];
        let mut lanes = Lanes::empty();
        let mut tris = Triangles {
            tris: &mesh.tris,
            sheared: [None; PACKET],
            range: [(0.0, 0.0); PACKET],
        };
        let mut live = 0u32;
        let mut m = mask;
        while m != 0 {
            let i = m.trailing_zeros() as usize;
            m &= m - 1;
            let (ray, Some(slabs)) = (&self.rays[i], &self.world[i]) else {
                continue;
            };
            if slabs.enter(&scene.boxes[k], ray.tmin, ray.tmax).is_none() {
                continue;
            }
            let Some((s, sl)) = scene.local(inst, ray) else {
                continue;
            };
            lanes.set(i, &sl, ray.tmin, ray.tmax);
            tris.sheared[i] = Some(s);
            tris.range[i] = (ray.tmin, ray.tmax);
            live |= 1 << i;
        }
        if live == 0 {
            return 0;
        }
        mesh.bvh.any_packet(&lanes, live, stack, &mut tris)
    }
}

/// A mesh's triangles, for a packet carried into the mesh's space.
struct Triangles<'a> {
    tris: &'a [[glam::Vec3; 3]],
    sheared: [Option<Sheared>; PACKET],
    range: [(f32, f32); PACKET],
}

impl Leaves for Triangles<'_> {
    #[inline(always)]
    fn test(&mut self, first: u32, count: u32, m: u32, _: &mut Vec<(u32, u32)>) -> u32 {
        let mut blocked = 0;
        for slot in first..first + count {
            let [a, b, c] = self.tris[slot as usize];
            let mut rays = m & !blocked;
            while rays != 0 {
                let i = rays.trailing_zeros() as usize;
                rays &= rays - 1;
                if let Some(s) = &self.sheared[i] {
                    let (tmin, tmax) = self.range[i];
                    if s.hit(a, b, c, tmin, tmax).is_some() {
                        blocked |= 1 << i;
                    }
                }
            }
            if m & !blocked == 0 {
                break;
            }
        }
        blocked
    }
}

#[cfg(test)]
mod tests {
    use glam::{Mat4, Quat, Vec3};

    use super::PACKET;
    use crate::{Instance, Ray, Scene};

    /// Test randomness with points in a cube.
    struct Rng(realist_testkit::SplitMix);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0.next_u64()
        }
        fn unit(&mut self) -> f32 {
            self.0.unit_f32()
        }
        fn point(&mut self, r: f32) -> Vec3 {
            Vec3::new(self.unit(), self.unit(), self.unit()) * 2.0 * r - Vec3::splat(r)
        }
    }

    /// A soup of small triangles in a ball, a ground of two triangles (flat: its rays
    /// leave it), a turned and scaled copy of the soup, and a mirrored one.
    fn scene(rng: &mut Rng) -> Scene {
        let mut soup = (Vec::new(), Vec::new());
        for t in 0..600u32 {
            let c = rng.point(1.0);
            for _ in 0..3 {
                soup.0.push(c + rng.point(0.15));
            }
            soup.1.push([3 * t, 3 * t + 1, 3 * t + 2]);
        }
        let ground = (
            vec![
                Vec3::new(-4.0, -1.2, -4.0),
                Vec3::new(4.0, -1.2, -4.0),
                Vec3::new(4.0, -1.2, 4.0),
                Vec3::new(-4.0, -1.2, 4.0),
            ],
            vec![[0, 2, 1], [0, 3, 2]],
        );
        let turned = Mat4::from_scale_rotation_translation(
            Vec3::splat(0.7),
            Quat::from_rotation_y(0.6) * Quat::from_rotation_x(0.3),
            Vec3::new(2.0, 0.3, -0.5),
        );
        let mirrored = Mat4::from_translation(Vec3::new(-2.2, 0.0, 0.4))
            * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
        let instances = [
            (0, Mat4::IDENTITY),
            (1, Mat4::IDENTITY),
            (0, turned),
            (0, mirrored),
        ]
        .iter()
        .enumerate()
        .filter_map(|(k, &(m, to_world))| Instance::new(m, k as u64, to_world))
        .collect();
        Scene::build(vec![soup, ground], instances)
    }

    /// Packets of shadow-like rays (neighbouring origins, one direction), of rays from one
    /// point fanning out, and of unrelated rays, with some invalid ones and short ranges:
    /// every ray's answer is the one-ray query's.
    #[test]
    fn packets_answer_as_single_rays() {
        let mut rng = Rng(realist_testkit::SplitMix(7));
        let scene = scene(&mut rng);
        let (mut checked, mut blocked) = (0, 0);
        for round in 0..3000 {
            let n = 1 + (rng.next() % PACKET as u64) as usize;
            let base = rng.point(2.5);
            let light = rng.point(1.0).normalize_or(Vec3::Y);
            let rays: Vec<Ray> = (0..n)
                .map(|i| {
                    let (o, d) = match round % 3 {
                        0 => (
                            base + Vec3::new(i as f32 * 0.01, 0.0, 0.003 * i as f32),
                            light,
                        ),
                        1 => (base, rng.point(1.0)),
                        _ => (rng.point(3.0), rng.point(1.0)),
                    };
                    let tmax = if rng.next().is_multiple_of(4) {
                        rng.unit() * 3.0
                    } else {
                        f32::INFINITY
                    };
                    match rng.next() % 40 {
                        0 => Ray::new(Vec3::NAN, d, 0.0, tmax),
                        1 => Ray::new(o, Vec3::ZERO, 0.0, tmax),
                        2 => Ray::new(o, Vec3::new(0.0, 1.0, 0.0), 0.0, tmax),
                        _ => Ray::new(o, d, rng.unit() * 0.1, tmax),
                    }
                })
                .collect();
            let got = scene.occluded_packet(&rays);
            for (i, r) in rays.iter().enumerate() {
                let want = scene.occluded(r);
                assert_eq!(got >> i & 1 == 1, want, "round {round}, ray {i}: {r:?}");
                blocked += usize::from(want);
                checked += 1;
            }
            assert_eq!(got >> n, 0, "round {round}: bits past the packet");
        }
        // Both answers are common, or the comparison proves little.
        assert!(
            blocked > checked / 5 && blocked < checked * 4 / 5,
            "{blocked} of {checked}"
        );
    }

    /// More than a packet's rays: only the first [`PACKET`] are answered.
    #[test]
    fn a_long_slice_answers_its_first_packet() {
        let mut rng = Rng(realist_testkit::SplitMix(3));
        let scene = scene(&mut rng);
        let rays = vec![Ray::new(Vec3::new(0.0, 5.0, 0.0), -Vec3::Y, 0.0, f32::INFINITY); 20];
        assert_eq!(scene.occluded_packet(&rays), (1 << PACKET) - 1);
        assert_eq!(scene.occluded_packet(&[]), 0);
    }
}
