use glam::{Mat4, Quat, Vec3};
use proptest::prelude::*;

use crate::triangle::Sheared;
use crate::{Instance, Mesh, Ray, Scene};

/// A closed latitude-longitude sphere (fans at the poles): positions and triangles.
fn sphere(center: Vec3, r: f32, lat: usize, lon: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = vec![center + Vec3::Y * r];
    for i in 1..lat {
        let th = std::f32::consts::PI * i as f32 / lat as f32;
        for j in 0..lon {
            let ph = std::f32::consts::TAU * j as f32 / lon as f32;
            p.push(
                center
                    + r * Vec3::new(
                        libm::sinf(th) * libm::cosf(ph),
                        libm::cosf(th),
                        libm::sinf(th) * libm::sinf(ph),
                    ),
            );
        }
    }
    p.push(center - Vec3::Y * r);
    let south = (p.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * lon + (j % lon)) as u32;
    let mut t = Vec::new();
    for j in 0..lon {
        t.push([0, ring(1, j + 1), ring(1, j)]);
        t.push([south, ring(lat - 1, j), ring(lat - 1, j + 1)]);
    }
    for i in 1..lat - 1 {
        for j in 0..lon {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            t.push([a, b, d]);
            t.push([a, d, c]);
        }
    }
    (p, t)
}

/// Every vertex and edge midpoint of a mesh (each edge once).
fn targets(p: &[Vec3], t: &[[u32; 3]]) -> Vec<Vec3> {
    let mut edges: Vec<(u32, u32)> = t
        .iter()
        .flat_map(|&[a, b, c]| [(a, b), (b, c), (c, a)])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    p.iter()
        .copied()
        .chain(
            edges
                .iter()
                .map(|&(a, b)| (p[a as usize] + p[b as usize]) * 0.5),
        )
        .collect()
}

pub(crate) fn brute(p: &[Vec3], t: &[[u32; 3]], o: Vec3, d: Vec3, tmax: f32) -> Option<(f32, u32)> {
    let s = Sheared::new(o, d)?;
    let mut best: Option<(f32, u32)> = None;
    for (i, &[a, b, c]) in t.iter().enumerate() {
        let lim = best.map_or(tmax, |b| b.0);
        if let Some((th, _)) = s.hit(p[a as usize], p[b as usize], p[c as usize], 0.0, lim) {
            best = Some((th, i as u32));
        }
    }
    best
}

fn one(p: Vec<Vec3>, t: Vec<[u32; 3]>, to_world: Mat4) -> Scene {
    Scene::build(vec![(p, t)], vec![Instance::new(0, 7, to_world).unwrap()])
}

/// Rays from points inside a closed mesh aimed exactly at its vertices and edge midpoints:
/// none may pass through (the watertightness test). From the centre, rays to the
/// vertices on a coordinate plane have direction components of about 1e-9 (what made
/// `obvhs`'s own traversal miss); from off-centre points, boxes that just touch a vertex.
#[test]
fn rays_at_shared_edges_and_vertices_of_a_closed_mesh_never_miss() {
    let cases = [
        (Vec3::ZERO, 1.0, Mat4::IDENTITY),
        (Vec3::new(3.0, -2.0, 5.0), 2.5, Mat4::IDENTITY),
        (
            Vec3::new(0.5, 0.0, 0.0),
            1.0,
            Mat4::from_scale_rotation_translation(
                Vec3::new(2.0, 0.5, 1.0),
                Quat::from_euler(glam::EulerRot::XYZ, 0.3, 1.1, -0.4),
                Vec3::new(10.0, 0.0, -3.0),
            ),
        ),
    ];
    let mut rays = 0;
    for (center, r, to_world) in cases {
        let (p, t) = sphere(center, r, 96, 128);
        let aims = targets(&p, &t);
        let scene = one(p.clone(), t.clone(), to_world);
        for from in [
            center,
            center + Vec3::new(0.13, -0.07, 0.21) * r,
            center + Vec3::new(-0.4, 0.3, 0.1) * r,
        ] {
            let (o, world_aims): (Vec3, Vec<Vec3>) = (
                to_world.transform_point3(from),
                aims.iter().map(|&a| to_world.transform_point3(a)).collect(),
            );
            let misses = world_aims
                .iter()
                .filter(|&&a| {
                    let ray = Ray::new(o, (a - o) * 1.5, 0.0, f32::INFINITY);
                    scene.closest(&ray).is_none() || !scene.occluded(&ray)
                })
                .count();
            rays += world_aims.len();
            assert_eq!(
                misses,
                0,
                "{misses} of {} rays from {from} slipped out",
                world_aims.len()
            );
        }
    }
    assert!(rays > 100_000, "{rays}");
}

/// The hierarchy finds what testing every triangle finds: same nearest triangle and `t`.
#[test]
fn nearest_hits_match_testing_every_triangle() {
    let (mut p, t) = sphere(Vec3::ZERO, 1.0, 24, 32);
    // A second, smaller sphere inside and a wobble, so rays meet several layers.
    let (q, u) = sphere(Vec3::new(0.3, 0.1, 0.0), 0.4, 12, 16);
    let base = p.len() as u32;
    p.extend(q);
    let mut t = t;
    t.extend(u.iter().map(|&[a, b, c]| [a + base, b + base, c + base]));
    for (i, v) in p.iter_mut().enumerate() {
        *v *= 1.0 + 0.05 * libm::sinf((i as f32) * 1.7);
    }
    let scene = one(p.clone(), t.clone(), Mat4::IDENTITY);
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    let mut hits = 0;
    for _ in 0..4000 {
        let o = Vec3::new(next(), next(), next()) * 3.0;
        // Aimed near the spheres, so most rays hit.
        let d = Vec3::new(next(), next(), next()) * 0.9 - o;
        let want = brute(&p, &t, o, d, f32::INFINITY);
        let got = scene.closest(&Ray::new(o, d, 0.0, f32::INFINITY));
        assert_eq!(got.map(|h| (h.t, h.triangle)), want, "ray {o} {d}");
        assert_eq!(
            scene.occluded(&Ray::new(o, d, 0.0, f32::INFINITY)),
            want.is_some()
        );
        hits += usize::from(want.is_some());
    }
    assert!(hits > 1000, "{hits}");
}

/// After a pose moves the vertices, the refit hierarchy finds what brute force finds.
#[test]
fn refit_follows_moved_vertices() {
    let (p, t) = sphere(Vec3::ZERO, 1.0, 32, 48);
    let mut scene = one(p.clone(), t.clone(), Mat4::IDENTITY);
    let moved: Vec<Vec3> = p
        .iter()
        .map(|v| *v * Vec3::new(1.6, 0.7, 1.0) + Vec3::new(0.0, v.x * 0.5, 0.2))
        .collect();
    scene.refit(0, &moved, &t);
    for k in 0..500 {
        let a = k as f32 * 0.37;
        let o = Vec3::new(
            libm::cosf(a) * 4.0,
            libm::sinf(a * 0.7) * 2.0,
            libm::sinf(a) * 4.0,
        );
        let d = -o + Vec3::new(libm::sinf(a * 3.1), 0.3 * libm::cosf(a * 1.3), 0.2);
        let want = brute(&moved, &t, o, d, f32::INFINITY).map(|h| h.1);
        let got = scene
            .closest(&Ray::new(o, d, 0.0, f32::INFINITY))
            .map(|h| h.triangle);
        assert_eq!(got, want, "ray {k}");
    }
}

/// Copies of one mesh as instances: each found where it was placed, with its key.
#[test]
fn instances_are_hit_where_they_are_placed() {
    let (p, t) = sphere(Vec3::ZERO, 1.0, 16, 24);
    let mesh = Mesh::new(&p, &t);
    let instances = (0..50)
        .map(|k| {
            let at = Vec3::new((k % 10) as f32 * 3.0, (k / 10) as f32 * 3.0, 0.0);
            Instance::new(
                0,
                k,
                Mat4::from_translation(at)
                    * Mat4::from_scale(Vec3::splat(0.5 + (k % 3) as f32 * 0.25)),
            )
            .unwrap()
        })
        .collect();
    let scene = Scene::assemble(vec![mesh.into()], instances);
    for k in 0..50u64 {
        let at = Vec3::new((k % 10) as f32 * 3.0, (k / 10) as f32 * 3.0, 0.0);
        let r = 0.5 + (k % 3) as f32 * 0.25;
        let hit = scene
            .closest(&Ray::new(at + Vec3::Z * 10.0, -Vec3::Z, 0.0, f32::INFINITY))
            .unwrap();
        assert_eq!(hit.key, k);
        assert!(
            (hit.t - (10.0 - r)).abs() < 2e-3 * r,
            "{} vs {}",
            hit.t,
            10.0 - r
        );
    }
    // Between the copies: nothing.
    assert!(scene
        .closest(&Ray::new(
            Vec3::new(1.5, 1.5, 10.0),
            -Vec3::Z,
            0.0,
            f32::INFINITY
        ))
        .is_none());
}

/// Bad input: vertices that are not finite and indices out of range leave their triangles
/// out; a singular placement is refused; rays that are not finite find nothing.
#[test]
fn bad_geometry_and_rays_are_left_out_not_panicked_on() {
    let (mut p, mut t) = sphere(Vec3::ZERO, 1.0, 8, 8);
    p[3] = Vec3::new(f32::NAN, 0.0, 0.0);
    t.push([0, 1, 99_999]);
    let mesh = Mesh::new(&p, &t);
    let bad = t.iter().filter(|tri| tri.contains(&3)).count() + 1;
    assert_eq!(mesh.skipped, bad);
    assert!(Instance::new(0, 0, Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
    assert!(Instance::new(0, 0, Mat4::from_translation(Vec3::splat(f32::INFINITY))).is_none());
    let scene = Scene::assemble(
        vec![mesh.into(), Mesh::new(&[], &[]).into()],
        vec![
            Instance::new(0, 0, Mat4::IDENTITY).unwrap(),
            Instance::new(1, 1, Mat4::IDENTITY).unwrap(),
        ],
    );
    assert_eq!(
        scene.instances().len(),
        1,
        "the empty mesh's instance is dropped"
    );
    for (o, d) in [
        (Vec3::NAN, Vec3::X),
        (Vec3::ZERO, Vec3::ZERO),
        (Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0)),
    ] {
        assert!(scene.closest(&Ray::new(o, d, 0.0, f32::INFINITY)).is_none());
        assert!(!scene.occluded(&Ray::new(o, d, 0.0, f32::INFINITY)));
    }
    // All triangles degenerate (zero area): built, never hit.
    let flat = vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    let s = one(flat, vec![[0, 1, 2]; 1000], Mat4::IDENTITY);
    assert!(s
        .closest(&Ray::new(Vec3::new(1.0, 0.0, -1.0), Vec3::Z, 0.0, 10.0))
        .is_none());
}

proptest! {
    /// Random rays against random triangle soups: the hierarchy agrees with brute force.
    #[test]
    fn soups_agree_with_brute_force(
        verts in prop::collection::vec((-5.0f32..5.0, -5.0f32..5.0, -5.0f32..5.0), 3..120),
        o in (-6.0f32..6.0, -6.0f32..6.0, -6.0f32..6.0),
        d in (-1.0f32..1.0, -1.0f32..1.0, -1.0f32..1.0),
    ) {
        let p: Vec<Vec3> = verts.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
        let t: Vec<[u32; 3]> = (0..p.len() / 3).map(|k| [3 * k as u32, 3 * k as u32 + 1, 3 * k as u32 + 2]).collect();
        let (o, d) = (Vec3::new(o.0, o.1, o.2), Vec3::new(d.0, d.1, d.2));
        let scene = one(p.clone(), t.clone(), Mat4::IDENTITY);
        let want = brute(&p, &t, o, d, 100.0);
        let got = scene.closest(&Ray::new(o, d, 0.0, 100.0)).map(|h| (h.t, h.triangle));
        prop_assert_eq!(got, want);
    }
}

/// A flat mesh (a floor grid): rays leaving it are not tested against it, and the answers
/// are still brute force's, from on, above, below and along the plane.
#[test]
fn rays_leaving_a_flat_mesh_skip_it_and_agree_with_brute_force() {
    let n = 16;
    let mut p = Vec::new();
    for z in 0..=n {
        for x in 0..=n {
            p.push(Vec3::new(
                x as f32 / n as f32 * 2.0 - 1.0,
                0.25,
                z as f32 / n as f32 * 2.0 - 1.0,
            ));
        }
    }
    let at = |x: u32, z: u32| z * (n + 1) + x;
    let mut t = Vec::new();
    for z in 0..n {
        for x in 0..n {
            t.push([at(x, z), at(x, z + 1), at(x + 1, z)]);
            t.push([at(x + 1, z), at(x, z + 1), at(x + 1, z + 1)]);
        }
    }
    let mesh = Mesh::new(&p, &t);
    assert!(mesh.is_flat());
    let tilt = Mat4::from_rotation_x(0.4) * Mat4::from_translation(Vec3::new(0.0, 1.0, 0.0));
    let scene = one(p.clone(), t.clone(), tilt);
    let world: Vec<Vec3> = p.iter().map(|&v| tilt.transform_point3(v)).collect();
    let mut k = 0u32;
    // (Not from exactly on the plane: whether a ray from there meets it is a matter of
    // rounding, which differs between the two ways of computing it.)
    for oy in [0.25f32 + 1e-3, 0.25 - 1e-3, 2.0, -2.0] {
        for dy in [1.0f32, -1.0, 0.0, 0.3, -0.3] {
            k += 1;
            let a = k as f32 * 0.7;
            let o = tilt.transform_point3(Vec3::new(0.3 * libm::sinf(a), oy, 0.2 * libm::cosf(a)));
            let d = tilt.transform_vector3(Vec3::new(0.3, dy, 0.2));
            let want = brute(&world, &t, o, d, 10.0).map(|h| h.1);
            let got = scene
                .closest(&Ray::new(o, d, 0.0, 10.0))
                .map(|h| h.triangle);
            assert_eq!(got.is_some(), want.is_some(), "from y {oy} along {dy}");
            assert_eq!(scene.occluded(&Ray::new(o, d, 0.0, 10.0)), want.is_some());
        }
    }
}
