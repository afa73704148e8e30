//! The builder's invariants on ordinary and degenerate inputs, and its trees' closest hits
//! against brute force.

use glam::{Mat4, Vec3};

use super::{MAX_LEAF, MEDIAN_DEPTH};
use crate::bvh::{Bvh, Node};
use crate::tests::brute;
use crate::{Instance, Ray, Scene};

/// A xorshift generator of floats in `[-1, 1)`.
fn rng(seed: u64) -> impl FnMut() -> f32 {
    let mut s = seed;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    }
}

fn contains(outer: &Node, lo: Vec3, hi: Vec3) -> bool {
    outer.min().cmple(lo).all() && outer.max().cmpge(hi).all()
}

/// Checks the tree's shape against `boxes` and returns the depth it measured: every
/// primitive in `order` once, every node after its parent with its sibling beside it, every
/// box around its children's or its primitives', leaves of 1 to [`MAX_LEAF`] covering the
/// slots once, and `depth` the deepest leaf's.
fn check(bvh: &Bvh, boxes: &[(Vec3, Vec3)]) -> usize {
    let d = check_nodes(&bvh.nodes, &bvh.order, boxes);
    assert_eq!(bvh.depth, d);
    d
}

/// [`check`] on the parts of a tree; returns its depth.
fn check_nodes(nodes: &[Node], order: &[u32], boxes: &[(Vec3, Vec3)]) -> usize {
    let n = boxes.len();
    let mut seen = vec![false; n];
    for &k in order {
        assert!(!std::mem::replace(&mut seen[k as usize], true), "{k} twice");
    }
    assert_eq!(order.len(), n);
    assert!(seen.iter().all(|&s| s));
    // Each node's parent and depth (root 1), filled as parents are met: a child before its
    // parent would be met unfilled.
    let mut depth = vec![0usize; nodes.len()];
    depth[0] = 1;
    let mut slots = vec![0u8; n];
    for (k, node) in nodes.iter().enumerate() {
        assert!(
            depth[k] > 0,
            "node {k} is nobody's child, or comes before its parent"
        );
        if node.count() > 0 {
            let (first, count) = (node.index() as usize, node.count() as usize);
            assert!(count <= MAX_LEAF, "a leaf of {count}");
            for slot in first..first + count {
                slots[slot] += 1;
                let (lo, hi) = boxes[order[slot] as usize];
                assert!(contains(node, lo, hi), "leaf {k} around slot {slot}");
            }
        } else {
            let c = node.index() as usize;
            assert!(c > k && c + 1 < nodes.len(), "node {k}'s children at {c}");
            for child in [c, c + 1] {
                assert_eq!(depth[child], 0, "node {child} has two parents");
                depth[child] = depth[k] + 1;
                let b = &nodes[child];
                assert!(
                    contains(node, b.min(), b.max()),
                    "node {k} around {child}: {node:?} {b:?}"
                );
            }
        }
    }
    assert!(slots.iter().all(|&s| s == 1), "every slot in one leaf");
    depth.iter().copied().max().unwrap_or(0)
}

/// The most a tree over `n` primitives may reach: SAH cuts down to [`MEDIAN_DEPTH`], then
/// halving.
fn depth_bound(n: usize) -> usize {
    MEDIAN_DEPTH + libm::log2(n as f64).ceil() as usize + 1
}

fn cube(c: Vec3, r: f32) -> (Vec3, Vec3) {
    (c - Vec3::splat(r), c + Vec3::splat(r))
}

#[test]
fn random_boxes_make_a_well_formed_tree() {
    for (n, seed) in [(1, 1), (2, 2), (5, 3), (37, 4), (1000, 5), (20_000, 6)] {
        let mut next = rng(seed);
        let boxes: Vec<_> = (0..n)
            .map(|_| {
                let c = Vec3::new(next(), next(), next()) * 10.0;
                let r = Vec3::new(next(), next(), next()).abs() * 0.3;
                (c - r, c + r)
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let d = check(&bvh, &boxes);
        // An SAH tree over scattered boxes is about as deep as a balanced one.
        assert!(
            d <= 3 * libm::log2(n as f64).ceil() as usize + 2,
            "{n}: depth {d}"
        );
    }
}

#[test]
fn degenerate_boxes_build_with_bounded_depth() {
    let one = Vec3::ONE;
    let cases: Vec<(&str, Vec<(Vec3, Vec3)>)> = vec![
        ("one box", vec![(Vec3::ZERO, one)]),
        ("two identical", vec![(Vec3::ZERO, one); 2]),
        ("10,000 identical", vec![(Vec3::ZERO, one); 10_000]),
        ("10,000 points", vec![(one, one); 10_000]),
        (
            "one plane",
            (0..5000)
                .map(|k| cube(Vec3::new((k % 71) as f32, (k / 71) as f32, 0.0), 0.5))
                .map(|(lo, hi)| (lo.with_z(2.0), hi.with_z(2.0)))
                .collect(),
        ),
        (
            "same centre, growing",
            (0..5000)
                .map(|k| cube(Vec3::ZERO, 1.0 + k as f32))
                .collect(),
        ),
        (
            "huge and tiny",
            (0..6000)
                .map(|k| {
                    let c = Vec3::new(k as f32 * 0.001, (k % 7) as f32, 0.0);
                    cube(c, if k % 3 == 0 { 1e6 } else { 1e-6 })
                })
                .collect(),
        ),
        (
            // Each box 1.1 times as far out as the last (areas still within f32): each cut
            // takes off only the few outermost.
            "geometric",
            (0..450)
                .map(|k| cube(Vec3::splat(1.1f32.powi(k)), 0.5))
                .collect(),
        ),
    ];
    for (name, boxes) in cases {
        let bvh = Bvh::build(&boxes);
        let d = check(&bvh, &boxes);
        assert!(d <= depth_bound(boxes.len()), "{name}: depth {d}");
    }
    assert!(Bvh::build(&[]).nodes.is_empty());
}

/// A triangle with corners around `c` of size `r`, turned by `k`.
fn tri(c: Vec3, r: f32, k: usize) -> [Vec3; 3] {
    let a = k as f32 * 0.7;
    [
        c + Vec3::new(libm::cosf(a), libm::sinf(a), 0.3) * r,
        c + Vec3::new(-libm::sinf(a), 0.2, libm::cosf(a)) * r,
        c + Vec3::new(0.1, -libm::cosf(a), -libm::sinf(a)) * r,
    ]
}

/// Rays through the soup's box from around it: the scene's closest hit is brute force's.
fn agrees_with_brute_force(name: &str, soup: &[[Vec3; 3]], rays: usize) {
    let p: Vec<Vec3> = soup.iter().flatten().copied().collect();
    let t: Vec<[u32; 3]> = (0..soup.len() as u32)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    let (lo, hi) = p
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).max_element().max(1e-3));
    let scene = Scene::build(
        vec![(p.clone(), t.clone())],
        vec![Instance::new(0, 0, Mat4::IDENTITY).unwrap()],
    );
    let mut next = rng(soup.len() as u64 + 11);
    let mut hits = 0;
    for _ in 0..rays {
        let o = c + Vec3::new(next(), next(), next()).normalize_or(Vec3::X) * r * 2.0;
        let aim = c + (hi - lo) * 0.5 * Vec3::new(next(), next(), next());
        let d = aim - o;
        let want = brute(&p, &t, o, d, f32::INFINITY);
        let got = scene.closest(&Ray::new(o, d, 0.0, f32::INFINITY));
        assert_eq!(got.map(|h| (h.t, h.triangle)), want, "{name}: ray {o} {d}");
        hits += usize::from(want.is_some());
    }
    assert!(hits > 0, "{name}: no ray hit");
}

#[test]
fn degenerate_soups_give_brute_force_hits() {
    let o = Vec3::ZERO;
    let plane: Vec<[Vec3; 3]> = (0..4900)
        .map(|k| {
            let c = Vec3::new((k % 70) as f32, 0.0, (k / 70) as f32);
            [c, c + Vec3::X * 0.9, c + Vec3::Z * 0.9]
        })
        .collect();
    let mixed: Vec<[Vec3; 3]> = (0..5000)
        .map(|k| {
            let c = Vec3::new((k % 50) as f32, (k / 50 % 10) as f32, (k / 500) as f32);
            tri(c, if k % 97 == 0 { 400.0 } else { 1e-3 }, k)
        })
        .collect();
    let cases: Vec<(&str, Vec<[Vec3; 3]>)> = vec![
        ("one", vec![tri(o, 1.0, 0)]),
        ("two identical", vec![tri(o, 1.0, 0); 2]),
        ("10,000 identical", vec![tri(o, 1.0, 3); 10_000]),
        ("one plane", plane),
        ("huge and tiny", mixed),
    ];
    for (name, soup) in &cases {
        agrees_with_brute_force(name, soup, 300);
    }
}

#[test]
fn random_soups_give_brute_force_hits() {
    for (n, seed) in [(3, 1), (40, 2), (700, 3), (6000, 4)] {
        let mut next = rng(seed);
        let soup: Vec<[Vec3; 3]> = (0..n)
            .map(|k| {
                let c = Vec3::new(next(), next(), next()) * 5.0;
                tri(c, 0.05 + next().abs() * 0.6, k)
            })
            .collect();
        agrees_with_brute_force(&format!("{n} random"), &soup, 600);
    }
}

/// From [`MEDIAN_DEPTH`] on, ranges are halved at the median whatever their boxes: a range
/// that starts there adds no more levels than a balanced tree of leaves of up to
/// [`MAX_LEAF`].
#[test]
fn median_cuts_below_the_depth_limit_are_balanced() {
    let mut next = rng(9);
    let boxes: Vec<_> = (0..10_000)
        .map(|k| {
            cube(
                Vec3::new(next(), next() * 1e-3, next()) * (k % 13) as f32,
                0.01,
            )
        })
        .collect();
    let mut prims: Vec<super::Prim> = boxes
        .iter()
        .enumerate()
        .map(|(i, &(a, b))| super::Prim::new(a, b, i as u32))
        .collect();
    let (bounds, centres) = super::cut::bounds_of(&prims);
    let tree = super::build_tree(super::Range {
        prims: &mut prims,
        first: 0,
        bounds,
        centres,
        depth: MEDIAN_DEPTH,
    });
    // 10,000 / 2^11 is above 4 and 10,000 / 2^12 below: twelve halvings below the range's
    // own level, which `check_nodes` counts as 1.
    assert_eq!(tree.depth(), MEDIAN_DEPTH + 12);
    let order: Vec<u32> = prims.iter().map(super::Prim::index).collect();
    assert_eq!(check_nodes(&super::splice(tree), &order, &boxes), 13);
}
