use super::*;

#[test]
fn resolve_odd_size() {
    let mut t = Target::new(70, 65, Vec4::ONE);
    let (ti, o) = t.locate(69, 64);
    t.tiles[ti].materialize();
    t.tiles[ti].set_color(o, Vec4::ZERO);
    let fb = t.resolve();
    assert_eq!(fb.pixel(69, 64), Vec4::ZERO);
    assert_eq!(fb.pixel(68, 64), Vec4::ONE);
    t.clear(Vec4::splat(0.5));
    assert_eq!(t.resolve().pixel(69, 64), Vec4::splat(0.5));
    assert_eq!(t.to_srgb8()[(64 * 70 + 69) * 3], 188);
}

#[test]
fn reshape_reuses_tiles_and_places_them() {
    let mut t = Target::new(200, 130, Vec4::ZERO);
    t.reshape(70, 65, Vec4::ONE);
    assert_eq!((t.tiles_x, t.tiles_y, t.tiles.len()), (2, 2, 4));
    assert_eq!(
        (t.tiles[3].x0, t.tiles[3].y0, t.tiles[3].w, t.tiles[3].h),
        (64, 64, 6, 1)
    );
    let (ti, o) = t.locate(69, 64);
    t.tiles[ti].materialize();
    t.tiles[ti].set_color(o, Vec4::new(0.5, 0.0, 1.0, 1.0));
    let mut rgba = vec![[0u8; 4]; 70 * 65];
    t.write_rgba8(&mut rgba);
    assert_eq!(rgba[64 * 70 + 69], [188, 0, 255, 255]);
    assert_eq!(rgba[0], [255, 255, 255, 255]);
    let rgb = t.to_srgb8();
    assert!(rgba.iter().zip(rgb.chunks(3)).all(|(a, b)| a[..3] == *b));
    t.reshape(200, 130, Vec4::ZERO);
    assert_eq!((t.tiles.len(), t.tiles[7].x0, t.tiles[7].w), (12, 192, 8));
    assert!(t.resolve().color.iter().all(|c| *c == Vec4::ZERO));
}

#[test]
fn depth_save_restore_swaps() {
    let mut t = Target::new(130, 10, Vec4::ZERO);
    t.clear(Vec4::ZERO);
    t.tiles[0].materialize();
    t.tiles[0].depth[5] = 0.25;
    let mut copy = DepthCopy::default();
    t.save_depth(&mut copy);
    // Scratch depth drawn into a stored tile and into a lazily cleared one.
    t.tiles[0].depth[5] = 0.75;
    t.tiles[1].materialize();
    t.tiles[1].depth[3] = 0.5;
    t.restore_depth(&mut copy);
    assert_eq!(t.tiles[0].depth[5], 0.25);
    assert!(t.tiles[1].pending_clear.is_some() && t.tiles[2].pending_clear.is_some());
    assert_eq!(
        (copy.at(0, 5), copy.at(1, 3), copy.at(2, 0)),
        (0.75, 0.5, 0.0)
    );
}
