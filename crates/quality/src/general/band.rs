//! One band of the image: the visibility of its opaque and masked triangles, the blended
//! fragments composited in depth order, and the box filter into pixels.

use super::*;

/// Renders one band: visibility of opaque and masked triangles, shading of the nearest,
/// blended fragments composited in depth order, box filter. Returns the band's pixels,
/// row-major.
pub(super) fn band(view: &View, insts: &[Inst], bin: &[(u32, u32)], r: Rect) -> Vec<[f64; 3]> {
    let s = view.samples;
    let sf = f64::from(s);
    let (sx0, sy0) = (i64::from(r.x0 * s), i64::from(r.y0 * s));
    let (sw, sh) = (((r.x1 - r.x0) * s) as usize, ((r.y1 - r.y0) * s) as usize);
    let clamp = |b: [i64; 4]| {
        [
            b[0].max(sx0),
            b[1].min(sx0 + sw as i64 - 1),
            b[2].max(sy0),
            b[3].min(sy0 + sh as i64 - 1),
        ]
    };
    let slot = |sx: i64, sy: i64| (sy - sy0) as usize * sw + (sx - sx0) as usize;
    // 1 / w of the nearest opaque fragment (0: none) and its triangle in `tris`.
    let mut depth = vec![0.0f64; sw * sh];
    let mut id = vec![u32::MAX; sw * sh];
    let mut tris: Vec<Tri> = Vec::new();
    let mut blended: Vec<Tri> = Vec::new();
    for &(i, t) in bin {
        let inst = &insts[i as usize];
        let Some(g) = setup(view, inst, i, t) else {
            continue;
        };
        let b = clamp(g.bounds);
        if b[0] > b[1] || b[2] > b[3] {
            continue;
        }
        let tri = Tri::new(Setup { bounds: b, ..g }, inst);
        if inst.alpha == Alpha::Blend {
            blended.push(tri);
            continue;
        }
        let k = tris.len() as u32;
        cover(&tri.g, sf, b, |sx, sy, inv_w, px, py| {
            let o = slot(sx, sy);
            // Nearest wins; on an exact tie the first drawn stays.
            if inv_w > depth[o] && tri.kept(inst, px, py) {
                depth[o] = inv_w;
                id[o] = k;
            }
        });
        tris.push(tri);
    }
    // Blended fragments in front of the opaque surface: (slot, 1/w, draw order, colour),
    // per sample farthest (smallest 1/w) first, equal depths in draw order.
    let mut frags: Vec<(u32, f64, u32, DVec4)> = Vec::new();
    for (seq, tri) in blended.iter().enumerate() {
        let inst = &insts[tri.g.inst as usize];
        cover(&tri.g, sf, tri.g.bounds, |sx, sy, inv_w, px, py| {
            let o = slot(sx, sy);
            if inv_w > depth[o] {
                if let Some(c) = tri.shade(view, inst, px, py) {
                    frags.push((o as u32, inv_w, seq as u32, c));
                }
            }
        });
    }
    frags.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
    // Shade the nearest opaque fragment of every sample, composite the blended ones over
    // it, and box-filter into the band's pixels.
    let (pw, ph) = ((r.x1 - r.x0) as usize, (r.y1 - r.y0) as usize);
    let su = s as usize;
    let mut sum = vec![DVec3::ZERO; pw * ph];
    let mut next = frags.iter().peekable();
    for (o, &k) in id.iter().enumerate() {
        let (sx, sy) = (o % sw, o / sw);
        // The background colour is shown as it is (neither exposed nor tone mapped).
        let mut surface = true;
        let mut c = match tris.get(k as usize) {
            None => {
                surface = false;
                view.background
            }
            Some(tri) => {
                let (px, py) = (
                    sample_pos(sx as i64 + sx0, sf),
                    sample_pos(sy as i64 + sy0, sf),
                );
                tri.shade(view, &insts[tri.g.inst as usize], px, py)
                    .map_or(view.background, |c| c.truncate())
            }
        };
        while let Some(&&(_, _, _, f)) = next.peek().filter(|f| f.0 as usize == o) {
            let a = f.w.clamp(0.0, 1.0);
            c = f.truncate() * a + c * (1.0 - a);
            surface = true;
            next.next();
        }
        if surface {
            c *= view.exposure;
        }
        if surface && view.tone != crate::render::ToneMap::Clamp {
            c = view
                .tone
                .apply(c.as_vec3().extend(1.0))
                .truncate()
                .as_dvec3();
        }
        sum[(sy / su) * pw + sx / su] += c;
    }
    let n = f64::from(s * s);
    sum.into_iter().map(|c| (c / n).to_array()).collect()
}
