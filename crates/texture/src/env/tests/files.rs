//! Reading environment images (errors naming the file, bad texels), the memory and disk caches, and builds that are the same on every run and thread count.

use super::*;

#[test]
fn from_rgb_checks_size_and_replaces_bad_texels() {
    assert!(EnvImage::from_rgb(0, 1, vec![]).is_err());
    assert!(EnvImage::from_rgb(2, 1, vec![[0.0; 3]]).is_err());
    assert!(EnvImage::from_rgb(MAX_ENV_SIDE + 1, 1, vec![]).is_err());
    let t = vec![
        [f32::NAN, 1.0, 1.0],
        [f32::INFINITY, 0.0, 0.0],
        [-1.0, 0.5, 0.5],
        [0.25, 0.5, 1e38],
        [1.0, 2.0, 3.0],
    ];
    let img = EnvImage::from_rgb(5, 1, t).expect("valid size");
    assert_eq!(img.replaced_texels(), 4);
    assert_eq!(img.texel(0, 0), Some(Vec3::new(0.0, 1.0, 1.0)));
    assert_eq!(img.texel(2, 0), Some(Vec3::new(0.0, 0.5, 0.5)));
    assert_eq!(img.texel(3, 0), Some(Vec3::new(0.25, 0.5, MAX_RADIANCE)));
    assert_eq!(img.texel(4, 0), Some(Vec3::new(1.0, 2.0, 3.0)));
}

pub(super) fn save(path: &Path, w: u32, h: u32, texels: &[[f32; 3]]) {
    let buf = image::Rgb32FImage::from_raw(w, h, texels.iter().flatten().copied().collect())
        .expect("size");
    image::DynamicImage::ImageRgb32F(buf)
        .save(path)
        .expect("save");
}

pub(super) fn gradient(w: u32, h: u32, seed: f32) -> Vec<[f32; 3]> {
    (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            [
                0.1 + x / w as f32,
                0.2 + y / h as f32,
                seed + 0.01 * ((x * 7.0 + y * 3.0) % 5.0),
            ]
        })
        .collect()
}

#[test]
fn loading_errors_name_the_file() {
    let dir = TempDir::new("load");
    let msg = |p: &Path| match EnvImage::load(p) {
        Ok(_) => panic!("{} loaded", p.display()),
        Err(e) => e.to_string(),
    };
    let missing = dir.path().join("missing.hdr");
    assert!(msg(&missing).contains("missing.hdr"));

    let text = dir.path().join("notes.hdr");
    std::fs::write(&text, "this is not an image\n").expect("write");
    assert!(msg(&text).contains("notes.hdr"));

    let png = dir.path().join("pic.png");
    image::RgbImage::new(4, 2).save(&png).expect("save png");
    let m = msg(&png);
    assert!(m.contains("pic.png") && m.contains("unsupported"), "{m}");

    let huge = dir.path().join("huge.hdr");
    std::fs::write(
        &huge,
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8 +X 20000\n",
    )
    .expect("write");
    let m = msg(&huge);
    assert!(m.contains("huge.hdr") && m.contains("20000x8"), "{m}");

    let good = dir.path().join("good.hdr");
    let texels = gradient(64, 32, 0.5);
    save(&good, 64, 32, &texels);
    let img = EnvImage::load(&good).expect("loads");
    assert_eq!(
        (img.width(), img.height(), img.name()),
        (64, 32, "good.hdr")
    );
    // RGBE keeps 8 bits of mantissa.
    let t = img.texel(10, 5).expect("in range");
    assert!(
        rel_err(t, Vec3::from_array(texels[5 * 64 + 10])) < 0.01,
        "{t}"
    );

    let bytes = std::fs::read(&good).expect("read");
    let cut = dir.path().join("cut.hdr");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
    assert!(msg(&cut).contains("cut.hdr"));
}

#[test]
fn exr_bad_texels_are_counted() {
    let dir = TempDir::new("exr");
    let path = dir.path().join("bad.exr");
    let mut texels = gradient(16, 8, 1.0);
    texels[3] = [f32::NAN, 1.0, 1.0];
    texels[20] = [1.0, f32::INFINITY, 1.0];
    texels[100] = [1.0, 1.0, -2.0];
    save(&path, 16, 8, &texels);
    let img = EnvImage::load(&path).expect("loads");
    assert_eq!(img.replaced_texels(), 3);
    assert_eq!(img.texel(3, 0), Some(Vec3::new(0.0, 1.0, 1.0)));
    assert_eq!(img.texel(4, 1), Some(Vec3::new(1.0, 0.0, 1.0)));
    assert_eq!(img.texel(4, 6), Some(Vec3::new(1.0, 1.0, 0.0)));
    assert_eq!(img.texel(5, 0), Some(Vec3::from_array(texels[5])));
}

#[test]
fn memory_cache_hits_by_content() {
    let cache = EnvCache::new(EnvCache::DEFAULT_BYTES);
    let img = EnvImage::from_rgb(96, 48, gradient(96, 48, 0.3)).expect("valid");
    let first = cache.get_or_build(img.clone(), None);
    assert_eq!(first.hit, CacheHit::Miss);
    let second = cache.get_or_build(img.clone().with_name("renamed"), None);
    assert_eq!(second.hit, CacheHit::Memory);
    assert!(Arc::ptr_eq(&first.env, &second.env));

    let mut other = gradient(96, 48, 0.3);
    other[1234][1] += 1e-3;
    let other = EnvImage::from_rgb(96, 48, other).expect("valid");
    assert_ne!(content_key(&img), content_key(&other));
    assert_eq!(content_key(&img), content_key(&img.clone()));
    assert_eq!(cache.get_or_build(other, None).hit, CacheHit::Miss);
    assert_eq!(cache.len(), 2);

    // A budget of one byte keeps only the most recent.
    let small = EnvCache::new(1);
    let _ = small.get_or_build(img.clone(), None);
    let _ = small.get_or_build(EnvImage::uniform(Vec3::ONE), None);
    assert_eq!(small.len(), 1);
    assert_eq!(small.get_or_build(img, None).hit, CacheHit::Miss);
}

pub(super) fn same_bits(a: &Prefiltered, b: &Prefiltered) -> bool {
    let bits = |p: &Prefiltered| -> Vec<u32> {
        let sh = p.sh().iter().flat_map(|c| c.to_array());
        let levels = p.level_planes().flat_map(|l| l.rgb.iter().copied());
        sh.chain(levels).map(f32::to_bits).collect()
    };
    bits(a) == bits(b)
}

#[test]
fn disk_cache_round_trip_and_bad_files() {
    let dir = TempDir::new("cache");
    let img = EnvImage::from_rgb(80, 40, gradient(80, 40, 0.7)).expect("valid");
    let key = content_key(&img);
    let built = EnvCache::new(usize::MAX).get_or_build(img.clone(), Some(dir.path()));
    assert_eq!(built.hit, CacheHit::Miss);
    assert!(built.disk_note.is_none(), "{:?}", built.disk_note);
    let path = file_path(dir.path(), key);
    let good = std::fs::read(&path).expect("cache file written");

    let from_disk = EnvCache::new(usize::MAX).get_or_build(img.clone(), Some(dir.path()));
    assert_eq!(from_disk.hit, CacheHit::Disk);
    assert!(same_bits(&built.env, &from_disk.env));

    let mut flipped = good.clone();
    flipped[good.len() / 2] ^= 0x40;
    let mut wrong_key = good.clone();
    wrong_key[16] ^= 1;
    let bad_files: [Vec<u8>; 5] = [
        flipped,
        good[..good.len() - 9].to_vec(),
        b"RLENVPF\0garbage".to_vec(),
        vec![0xff; good.len()],
        wrong_key,
    ];
    for bad in bad_files {
        std::fs::write(&path, &bad).expect("corrupt");
        let rebuilt = EnvCache::new(usize::MAX).get_or_build(img.clone(), Some(dir.path()));
        assert_eq!(rebuilt.hit, CacheHit::Miss);
        assert!(rebuilt.disk_note.is_some());
        assert!(same_bits(&built.env, &rebuilt.env));
        assert_eq!(std::fs::read(&path).expect("rewritten"), good);
    }
    let again = EnvCache::new(usize::MAX).get_or_build(img, Some(dir.path()));
    assert_eq!(again.hit, CacheHit::Disk);
}

#[test]
fn default_cache_dir_is_under_realist() {
    if let Some(d) = default_cache_dir() {
        assert!(
            d.is_absolute() && d.ends_with("realist/env"),
            "{}",
            d.display()
        );
    }
}

#[test]
fn builds_are_bit_identical_across_runs_and_threads() {
    let img = EnvImage::sky();
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("pool")
    };
    let one = pool(1).install(|| Prefiltered::build(img.clone()));
    let two = pool(2).install(|| Prefiltered::build(img.clone()));
    let again = Prefiltered::build(img);
    assert!(same_bits(&one, &two) && same_bits(&one, &again));
    let lut1 = pool(1).install(|| BrdfLut::compute(16, 128));
    let lut2 = pool(2).install(|| BrdfLut::compute(16, 128));
    assert_eq!(lut1, lut2);
}

#[test]
fn odd_and_tiny_sources_prefilter() {
    for (w, h) in [(1, 1), (3, 1), (1, 5), (7, 3), (1000, 500), (300, 300)] {
        let img = EnvImage::from_rgb(w, h, gradient(w, h, 0.2)).expect("valid");
        let env = Prefiltered::build(img);
        assert_eq!(env.levels(), SPECULAR_LEVELS);
        let (bw, bh) = env.level_size(0).expect("level 0");
        assert!(
            bw <= 256 && bh <= 128 && bw >= 1 && bh >= 1,
            "{w}x{h}: {bw}x{bh}"
        );
        for d in sphere_dirs(8) {
            for r in [0.0, 0.3, 1.0] {
                let s = env.specular(d, r);
                assert!(s.is_finite() && s.min_element() >= 0.0, "{w}x{h}: {s}");
            }
            assert!(env.irradiance(d).is_finite());
        }
        assert!(env.specular(Vec3::ZERO, f32::NAN).is_finite());
    }
}

/// The stored split-sum table is [`BrdfLut::compute`]'s (within 1e-6: the Hammersley
/// directions go through the C library's `sin` and `cos`, which may differ in the last bit
/// between platforms). `REPLACE=1` rewrites `lut.bin` from a fresh computation.
#[test]
fn stored_table_is_the_computed_one() {
    use crate::env::lut::{LUT_SAMPLES, LUT_SIZE};
    let computed = BrdfLut::compute(LUT_SIZE, LUT_SAMPLES);
    if std::env::var_os("REPLACE").is_some() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/env/lut.bin");
        std::fs::write(&path, computed.to_bytes()).expect("lut.bin");
        eprintln!("wrote {}", path.display());
        return;
    }
    let stored = BrdfLut::stored().expect("lut.bin is a 64x64 table of finite values");
    assert_eq!(stored.size(), computed.size());
    let mut worst = 0f32;
    for j in 0..LUT_SIZE {
        for i in 0..LUT_SIZE {
            let (nv, r) = (i as f32 / 63.0, j as f32 / 63.0);
            let (a, b) = stored.lookup(nv, r);
            let (ca, cb) = computed.lookup(nv, r);
            worst = worst.max((a - ca).abs()).max((b - cb).abs());
        }
    }
    assert!(
        worst <= 1e-6,
        "stored table differs from the computed one by {worst}"
    );
    assert!(std::ptr::eq(brdf_lut(), brdf_lut()));
}
