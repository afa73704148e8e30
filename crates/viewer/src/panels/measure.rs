//! Measuring: with "pick points" on, a click in the view picks a point snapped to a vertex
//! or an edge within a few pixels, else the surface ([`crate::render::measure::pick`]); two
//! points give their distance, three the angle at the middle one. The labels are drawn in
//! the view; the panel lists the values and the model's bounding box, and copies them as
//! text. Values are in the file's units (glTF: metres).

use eframe::egui;
use glam::Vec3;

use super::{row, Cx, Dock, Panel};
use crate::render::measure::{angle_degrees, distance, Pick};

/// How near (in pixels of the frame) a vertex or an edge must be for a click to snap to it.
pub const SNAP_PIXELS: f32 = 8.0;

/// The points picked, and whether clicks pick them.
#[derive(Clone, Debug, Default)]
pub struct Measure {
    /// Clicks in the view pick points (instead of probing a pixel).
    pub on: bool,
    /// At most [`Measure::MAX`]; the next click starts again.
    pub points: Vec<Pick>,
}

impl Measure {
    /// Points kept: two for a distance, three for an angle.
    pub const MAX: usize = 3;

    /// Adds a picked point (a fourth starts a new measurement).
    pub fn add(&mut self, p: Pick) {
        if self.points.len() >= Self::MAX {
            self.points.clear();
        }
        self.points.push(p);
    }

    /// The distance between each point and the next.
    #[must_use]
    pub fn distances(&self) -> Vec<f64> {
        self.points
            .windows(2)
            .map(|w| distance(w[0].position, w[1].position))
            .collect()
    }

    /// The angle at the second of three points, in degrees.
    #[must_use]
    pub fn angle(&self) -> Option<f64> {
        match &self.points[..] {
            [a, b, c] => angle_degrees(a.position, b.position, c.position),
            _ => None,
        }
    }

    /// Everything measured, as lines of text (what "copy" puts on the clipboard).
    #[must_use]
    pub fn text(&self, bounds: Option<(Vec3, Vec3)>) -> String {
        let mut out = String::new();
        for (i, p) in self.points.iter().enumerate() {
            let q = p.position;
            out += &format!(
                "{} = ({}, {}, {}) {}\n",
                name(i),
                q.x,
                q.y,
                q.z,
                p.snap.name()
            );
        }
        for (i, d) in self.distances().iter().enumerate() {
            out += &format!("{}{} = {}\n", name(i), name(i + 1), number(*d));
        }
        if let Some(a) = self.angle() {
            out += &format!("angle ABC = {}°\n", number(a));
        }
        if let Some((lo, hi)) = bounds {
            let s = hi - lo;
            out += &format!(
                "bounding box {} x {} x {}, diagonal {}\n",
                number(f64::from(s.x)),
                number(f64::from(s.y)),
                number(f64::from(s.z)),
                number(f64::from(s.length()))
            );
        }
        out
    }
}

/// The name of point `i`: A, B, C.
#[must_use]
pub fn name(i: usize) -> char {
    char::from(b'A' + (i % 26) as u8)
}

/// A measured value with six significant digits, without trailing zeros.
#[must_use]
pub fn number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (5 - libm::log10(v.abs()).floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    }
}

/// The measure panel (right).
#[derive(Default)]
pub struct MeasurePanel;

impl Panel for MeasurePanel {
    fn dock(&self) -> Dock {
        Dock::Right
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut Cx<'_>) {
        egui::CollapsingHeader::new("Measure")
            .id_salt("measure")
            .show(ui, |ui| show(ui, cx));
    }
}

fn show(ui: &mut egui::Ui, cx: &mut Cx<'_>) {
    let m = &mut cx.shared.measure;
    ui.checkbox(&mut m.on, "pick points with a click")
        .on_hover_text(format!(
            "A click picks a point on the model, snapped to a vertex or an edge within \
             {SNAP_PIXELS} pixels: two points give a distance, three the angle at the middle \
             one; a fourth click starts again. Units are the file's (glTF: metres)."
        ));
    let bounds = cx.session.scene.bounds();
    egui::Grid::new("measure-grid")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            // Four significant digits here (the panel is narrow); "copy" gives six.
            let short = |v: f32| {
                format!("{:.4}", f64::from(v))
                    .trim_end_matches('0')
                    .trim_end_matches('.')
                    .to_owned()
            };
            for (i, p) in m.points.iter().enumerate() {
                let q = p.position;
                row(
                    ui,
                    &format!("{} ({})", name(i), p.snap.name()),
                    format!("{}, {}, {}", short(q.x), short(q.y), short(q.z)),
                );
            }
            for (i, d) in m.distances().iter().enumerate() {
                row(ui, &format!("{}{}", name(i), name(i + 1)), number(*d));
            }
            if let Some(a) = m.angle() {
                row(ui, "angle ABC", format!("{}°", number(a)));
            }
            if let Some((lo, hi)) = bounds {
                let s = hi - lo;
                row(
                    ui,
                    "bounding box",
                    format!(
                        "{} x {} x {}",
                        number(f64::from(s.x)),
                        number(f64::from(s.y)),
                        number(f64::from(s.z))
                    ),
                );
                row(ui, "  diagonal", number(f64::from(s.length())));
            }
        });
    ui.horizontal(|ui| {
        if ui
            .button("copy")
            .on_hover_text("the points, distances, angle and bounding box as text")
            .clicked()
        {
            ui.ctx().copy_text(m.text(bounds));
        }
        if ui
            .add_enabled(!m.points.is_empty(), egui::Button::new("clear"))
            .clicked()
        {
            m.points.clear();
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_six_significant_digits() {
        assert_eq!(number(2.0), "2");
        assert_eq!(number(2.828_427_124_7), "2.82843");
        assert_eq!(number(90.000_000_1), "90");
        assert_eq!(number(0.001_234_567), "0.00123457");
        assert_eq!(number(123_456.7), "123457");
        assert_eq!(number(0.0), "0");
    }
}
