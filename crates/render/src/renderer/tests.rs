use super::*;
use crate::shade::Shading;

fn path_job(tone: super::super::ToneMap, exposure: f32) -> (PreparedScene, Settings, View) {
    let scene = PreparedScene::new(crate::scene::demo());
    let settings = Settings {
        shading: Some(Shading::Path),
        tone,
        exposure,
        ..Settings::default()
    };
    let camera = super::super::default_camera(scene.scene(), 48.0 / 32.0);
    let view = View {
        camera,
        width: 48,
        height: 32,
    };
    (scene, settings, view)
}

/// The target's colours, row-major.
fn colors(r: &Renderer) -> Vec<Vec4> {
    let t = r.target().expect("a frame");
    (0..t.height)
        .flat_map(|y| (0..t.width).map(move |x| (x, y)))
        .map(|(x, y)| t.pixel(x, y).expect("inside").0)
        .collect()
}

/// Paths added in batches 1, 1, 2, 4, 8 (16 in all) make, bit for bit, the image of
/// one run of 16 paths with the same seed, unmapped (clamp) and tone mapped once.
#[test]
fn paths_added_in_batches_equal_one_run_of_as_many() {
    for (tone, exposure) in [
        (super::super::ToneMap::Clamp, 0.0),
        (super::super::ToneMap::PbrNeutral, 0.5),
    ] {
        let (scene, settings, view) = path_job(tone, exposure);
        let mut r = Renderer::new();
        let mut shown = Vec::new();
        for batch in [0..1, 1..2, 2..4, 4..8, 8..16] {
            r.render_paths(&scene, &settings, &view, batch, &|| false)
                .expect("not stopped");
            shown.push(r.paths());
        }
        assert_eq!(shown, [1, 2, 4, 8, 16]);
        let once = super::super::path::path_image(&scene, &settings, &view, 16, 0);
        let (scale, tone) = (settings.exposure_scale(), settings.tone_for(scene.scene()));
        let bg = settings.background;
        let mut lit = 0;
        for (i, (got, mean)) in colors(&r).iter().zip(&once).enumerate() {
            let c = mean.extend(1.0);
            let want = if tone == super::super::ToneMap::Clamp && scale == 1.0 || c == bg {
                c
            } else {
                tone.apply((c.truncate() * scale).extend(1.0))
            };
            assert_eq!(*got, want, "pixel {i}, {tone:?}");
            lit += usize::from(mean.max_element() > 0.0);
        }
        assert!(lit > 48 * 32 / 4, "the demo is lit: {lit} pixels");
        // One path is what the path frame of one sample shows; a new sum starts at 0.
        r.render_paths(&scene, &settings, &view, 0..1, &|| false)
            .expect("not stopped");
        let first = colors(&r);
        r.render(
            &scene,
            &Settings {
                samples: 1,
                ..settings.clone()
            },
            &view,
        );
        assert_eq!(first, colors(&r));
        assert_eq!(r.paths(), 0, "a frame ends the sum");
    }
}

/// A range that does not continue the sum (a gap, or a new size) starts a new one over
/// `0..end`: the same image as one run of that many paths, and no panic.
#[test]
fn a_range_that_does_not_continue_the_sum_starts_anew() {
    let (scene, settings, view) = path_job(super::super::ToneMap::Clamp, 0.0);
    let mut r = Renderer::new();
    r.render_paths(&scene, &settings, &view, 0..2, &|| false)
        .expect("not stopped");
    r.render_paths(&scene, &settings, &view, 5..6, &|| false)
        .expect("not stopped");
    assert_eq!(r.paths(), 6);
    let once: Vec<Vec4> = super::super::path::path_image(&scene, &settings, &view, 6, 0)
        .iter()
        .map(|c| c.extend(1.0))
        .collect();
    assert_eq!(colors(&r), once);
    let small = View {
        width: 24,
        height: 16,
        ..view.clone()
    };
    r.render_paths(&scene, &settings, &small, 6..7, &|| false)
        .expect("not stopped");
    assert_eq!(r.paths(), 7);
}

#[test]
fn a_stopped_batch_loses_the_sum() {
    let (scene, settings, view) = path_job(super::super::ToneMap::Clamp, 0.0);
    let mut r = Renderer::new();
    r.render_paths(&scene, &settings, &view, 0..2, &|| false)
        .expect("not stopped");
    assert_eq!(
        r.render_paths(&scene, &settings, &view, 2..4, &|| true)
            .err(),
        Some(Interrupted)
    );
    assert_eq!(r.paths(), 0);
    assert!(!r.complete());
}
