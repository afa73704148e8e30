//! `realist render --turntable N`: numbered PNG frames and one animated PNG, decoded back.

mod common;

use std::io::BufReader;
use std::path::Path;
use std::process::Command;

fn realist(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(args)
        .env("LC_ALL", "C")
        .output()
        .unwrap()
}

fn succeeded(out: &std::process::Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A decoded animated PNG.
struct Apng {
    /// Every frame as RGB8 rows.
    frames: Vec<Vec<u8>>,
    /// The frame count and plays of its `acTL` chunk.
    count: u32,
    plays: u32,
    size: (u32, u32),
    /// The last frame's delay (numerator, denominator) in seconds.
    delay: (u16, u16),
}

fn decode_apng(path: &Path) -> Apng {
    let file = std::fs::File::open(path).unwrap();
    let mut reader = png::Decoder::new(BufReader::new(file)).read_info().unwrap();
    let info = reader.info();
    let actl = info.animation_control.expect("an animated PNG");
    let size = (info.width, info.height);
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let mut frames = Vec::new();
    let mut delay = (0, 0);
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    while frames.len() < actl.num_frames as usize {
        let out = reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control.expect("a frame control chunk");
        assert_eq!((fc.width, fc.height), size, "every frame is whole");
        delay = (fc.delay_num, fc.delay_den);
        frames.push(buf[..out.buffer_size()].to_vec());
    }
    Apng {
        frames,
        count: actl.num_frames,
        plays: actl.num_plays,
        size,
        delay,
    }
}

#[test]
fn turntable_frames_and_animated_png() {
    let dir = common::temp_dir("turntable");
    let pattern = dir.join("frame_{}.png");
    let apng = dir.join("spin.apng");
    let base = ["render", "--demo", "--turntable", "4", "--size", "64x48"];

    // Numbered PNGs, and the same frames into --animated.
    let mut args = base.to_vec();
    args.extend(["-o", pattern.to_str().unwrap()]);
    let stdout = succeeded(&realist(&args));
    assert!(stdout.contains("4 frames"), "{stdout}");
    let pngs: Vec<Vec<u8>> = (0..4)
        .map(|i| {
            let img = image::open(dir.join(format!("frame_{i}.png"))).unwrap();
            assert_eq!((img.width(), img.height()), (64, 48));
            img.to_rgb8().into_raw()
        })
        .collect();
    assert!(!dir.join("frame_4.png").exists());

    let mut args = base.to_vec();
    args.extend(["-o", apng.to_str().unwrap(), "--fps", "8"]);
    let stdout = succeeded(&realist(&args));
    assert!(stdout.contains("spin.apng"), "{stdout}");
    let Apng {
        frames,
        count,
        plays,
        size,
        delay,
    } = decode_apng(&apng);
    assert_eq!((count, frames.len()), (4, 4));
    assert_eq!(size, (64, 48));
    assert_eq!(plays, 0, "loops forever");
    assert_eq!(delay, (1, 8));
    for (i, f) in frames.iter().enumerate() {
        assert_eq!(f.len(), 64 * 48 * 3);
        // The animated image holds exactly the frames the PNG sequence holds.
        assert!(f == &pngs[i], "frame {i} differs from frame_{i}.png");
    }
    // The view changes from frame to frame.
    for i in 0..4 {
        for j in i + 1..4 {
            let differing = frames[i]
                .chunks(3)
                .zip(frames[j].chunks(3))
                .filter(|(a, b)| a != b)
                .count();
            assert!(
                differing > 64 * 48 / 20,
                "frames {i} and {j}: {differing} pixels differ"
            );
        }
    }

    // Both at once: -o with {} and --animated; the default turntable speed is 12 fps.
    let both = dir.join("both");
    std::fs::create_dir_all(&both).unwrap();
    let mut args = base.to_vec();
    let (p, a) = (both.join("f{}.png"), both.join("a.png"));
    args.extend(["-o", p.to_str().unwrap(), "--animated", a.to_str().unwrap()]);
    succeeded(&realist(&args));
    assert!(both.join("f3.png").exists());
    let both_apng = decode_apng(&a);
    assert_eq!(both_apng.frames, pngs);
    assert_eq!(both_apng.delay, (1, 12));

    // Several frames into one plain PNG name: an error naming the file, nothing written.
    let flat = dir.join("flat.png");
    let mut args = base.to_vec();
    args.extend(["-o", flat.to_str().unwrap()]);
    let out = realist(&args);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("flat.png") && err.contains("{}"), "{err}");
    assert!(!flat.exists());

    // Too many frames for one animated image.
    let out = realist(&[
        "render",
        "--demo",
        "--turntable",
        "10001",
        "--size",
        "8x8",
        "-o",
        apng.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("spin.apng") && err.contains("10000"), "{err}");

    std::fs::remove_dir_all(&dir).ok();
}
