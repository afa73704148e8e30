//! The library in a dozen lines: load a model (or build the demo scene), render it with
//! every shading mode, and save the images.
//!
//! ```text
//! cargo run --release --example render_model -- [MODEL] [OUT_DIR]
//! ```

use std::path::PathBuf;

use realist::load::{self, LoadOptions};
use realist::render::{self, PreparedScene, Settings, Shot};
use realist::scene;
use realist::shade::Shading;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene = match args.next() {
        Some(path) => load::load(&PathBuf::from(path), &LoadOptions::default())?,
        None => scene::demo(),
    };
    let out = PathBuf::from(args.next().unwrap_or_else(|| "target/render_model".into()));
    std::fs::create_dir_all(&out)?;
    // Triangulate once, render many times.
    let prepared = PreparedScene::new(scene);
    for mode in Shading::ALL {
        let opts = Shot {
            width: 640,
            height: 360,
            settings: Settings {
                shading: Some(mode),
                ..Settings::default()
            },
            ..Shot::default()
        };
        let frame = render::render(&prepared, &opts);
        let path = out.join(format!("{mode}.png"));
        realist::color::png::Png::rgb(opts.width, opts.height, &frame.srgb8())
            .with_text("Description", format!("shading {mode}"))
            .write(&path)?;
        println!(
            "{mode:>9}: {} pixels shaded -> {}",
            frame.stats.pixels_shaded,
            path.display()
        );
    }
    Ok(())
}
