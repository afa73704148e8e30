//! Deterministic mutation test of the loaders (fixed seed): at least 20,000 mutants of small
//! valid glTF, GLB and OBJ+MTL files - bit flips, truncations, overwritten length fields and
//! corrupted numbers (indices, counts, offsets) - each loaded and, when it loads, rendered.
//! No mutant may panic (a panic inside a loader comes back as `LoadError::Panic`), produce a
//! non-finite pixel, or take more than a few seconds.

mod common;

use std::path::Path;
use std::time::{Duration, Instant};

use realist::load::{load, LoadError, LoadOptions};
use realist::render::{PreparedScene, Settings, Shot};
use realist::shade::Shading;

/// xorshift64*: small, deterministic, good enough to pick mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Numbers that break things when they replace a number in a text file.
const HOSTILE_NUMBERS: [&str; 12] = [
    "0",
    "-1",
    "1",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "1e30",
    "nan",
    "inf",
    "99999999999999999999",
    "3.5",
];

/// One random mutation of `data`.
fn mutate(rng: &mut Rng, data: &[u8]) -> Vec<u8> {
    let mut out = data.to_vec();
    match rng.below(6) {
        // Flip one to eight bits.
        0 => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(out.len());
                out[i] ^= 1 << rng.below(8);
            }
        }
        // Truncate.
        1 => out.truncate(rng.below(out.len())),
        // Overwrite a 4-byte little-endian word (GLB lengths, counts, offsets).
        2 => {
            let i = rng.below(out.len().saturating_sub(4));
            let v: u32 = match rng.below(4) {
                0 => 0,
                1 => u32::MAX,
                2 => 0x7fff_fff0,
                _ => rng.next() as u32,
            };
            if i + 4 <= out.len() {
                out[i..i + 4].copy_from_slice(&v.to_le_bytes());
            }
        }
        // Replace a number in text (indices, counts, offsets, components).
        3 | 4 => {
            let digits: Vec<usize> = out
                .iter()
                .enumerate()
                .filter(|(_, b)| b.is_ascii_digit())
                .map(|(i, _)| i)
                .collect();
            if let Some(&start) = digits.get(rng.below(digits.len())) {
                let end = (start..out.len())
                    .find(|&j| !out[j].is_ascii_digit())
                    .unwrap_or(out.len());
                let with = HOSTILE_NUMBERS[rng.below(HOSTILE_NUMBERS.len())].as_bytes();
                out.splice(start..end, with.iter().copied());
            }
        }
        // Duplicate a slice in place.
        _ => {
            let a = rng.below(out.len());
            let b = (a + rng.below(64)).min(out.len());
            let slice = out[a..b].to_vec();
            let at = rng.below(out.len());
            out.splice(at..at, slice);
        }
    }
    out
}

const OBJ: &str = "mtllib m.mtl\no first\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
vn 0 0 1\nusemtl red\nf 1/1/1 2/2/1 3/3/1 4/4/1\ng second\nf -5/1 -4/2 -1/3\nf 2 3 5\nl 1 2\n";
const MTL: &str =
    "newmtl red\nKa 0.1 0.1 0.1\nKd 0.8 0.2 0.2\nKs 0.5 0.5 0.5\nNs 40\nd 1\nmap_Kd t.png\n";

#[derive(Default, Debug)]
struct Tally {
    ok: usize,
    error: usize,
    panic: Vec<String>,
    slowest: Duration,
}

/// Loads (and renders) the file at `path`; records the outcome.
fn run(path: &Path, tally: &mut Tally, what: &str) {
    let t = Instant::now();
    match load(path, &LoadOptions::default()) {
        Ok(scene) => {
            let prepared = PreparedScene::new(scene);
            for mode in [Shading::Phong, Shading::Wireframe] {
                let opts = Shot {
                    width: 24,
                    height: 16,
                    settings: Settings {
                        shading: Some(mode),
                        ..Settings::default()
                    },
                    ..Shot::default()
                };
                let fb = realist::render::render(&prepared, &opts).image();
                assert!(
                    fb.color.iter().all(|c| c.is_finite()),
                    "{what}: non-finite pixel"
                );
            }
            tally.ok += 1;
        }
        Err(LoadError::Panic { message, .. }) => tally.panic.push(format!("{what}: {message}")),
        Err(e) => {
            let msg = e.to_string();
            assert!(
                !msg.is_empty() && !msg.contains('\n'),
                "{what}: message not one line: {msg:?}"
            );
            tally.error += 1;
        }
    }
    tally.slowest = tally.slowest.max(t.elapsed());
}

#[test]
fn twenty_thousand_mutants_never_panic() {
    let dir = common::temp_dir("mutation");
    let gltf = common::gltf_json(
        r#""name": "root", "translation": [1, 2, 3]"#,
        r#""scale": [-1, 2, 1]"#,
    )
    .into_bytes();
    let glb = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("models/checker-cube.glb"))
        .expect("checker-cube.glb");
    let mut png = Vec::new();
    image::RgbaImage::from_pixel(2, 2, image::Rgba([200, 30, 30, 255]))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("png");
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    let mut tallies: Vec<(&str, Tally)> = vec![
        ("gltf", Tally::default()),
        ("glb", Tally::default()),
        ("obj+mtl", Tally::default()),
    ];
    const PER_FORMAT: usize = 7_000;
    for k in 0..PER_FORMAT {
        let path = dir.join("case.gltf");
        std::fs::write(&path, mutate(&mut rng, &gltf)).expect("write");
        run(&path, &mut tallies[0].1, &format!("gltf mutant {k}"));

        let path = dir.join("case.glb");
        std::fs::write(&path, mutate(&mut rng, &glb)).expect("write");
        run(&path, &mut tallies[1].1, &format!("glb mutant {k}"));

        // Mutate the OBJ, the MTL or the texture.
        let (mut obj, mut mtl, mut tex) = (
            OBJ.as_bytes().to_vec(),
            MTL.as_bytes().to_vec(),
            png.clone(),
        );
        match rng.below(3) {
            0 => obj = mutate(&mut rng, &obj),
            1 => mtl = mutate(&mut rng, &mtl),
            _ => tex = mutate(&mut rng, &tex),
        }
        std::fs::write(dir.join("m.mtl"), &mtl).expect("write");
        std::fs::write(dir.join("t.png"), &tex).expect("write");
        let path = dir.join("case.obj");
        std::fs::write(&path, &obj).expect("write");
        run(&path, &mut tallies[2].1, &format!("obj mutant {k}"));
    }
    let _ = std::fs::remove_dir_all(&dir);
    println!(
        "{:<8} {:>7} {:>7} {:>6} {:>12}",
        "format", "loaded", "error", "panic", "slowest ms"
    );
    let mut total = 0;
    for (name, t) in &tallies {
        println!(
            "{name:<8} {:>7} {:>7} {:>6} {:>12.1}",
            t.ok,
            t.error,
            t.panic.len(),
            t.slowest.as_secs_f64() * 1e3
        );
        total += t.ok + t.error + t.panic.len();
    }
    println!("{total} mutants");
    assert!(total >= 20_000);
    let panics: Vec<&String> = tallies.iter().flat_map(|(_, t)| &t.panic).collect();
    assert!(
        panics.is_empty(),
        "{} mutants panicked, e.g. {:?}",
        panics.len(),
        &panics[..panics.len().min(5)]
    );
    for (name, t) in &tallies {
        // Every format must keep loading a good share of its mutants (mutations that only
        // touch values), or the test is not exercising the loaders past their first check.
        assert!(
            t.ok > PER_FORMAT / 50,
            "{name}: only {} of {PER_FORMAT} mutants loaded",
            t.ok
        );
        assert!(
            t.slowest < Duration::from_secs(5),
            "{name}: a mutant took {:?}",
            t.slowest
        );
    }
}
