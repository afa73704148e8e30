//! Text that must not size the panels: paths and names elided to the width at hand, the
//! full text on hover and in the accessibility tree.
//!
//! The viewport's size is what is left between the side panels and the menu and status bars,
//! so nothing in those may grow with what it shows: a long path would shrink the 3D view (and
//! re-render it) just because a file was opened from a deeper folder. Two mechanisms keep the
//! panels still. Each side panel's contents sit in a scroll area that fills the panel and
//! never reports a larger size ([`bounded`]), so whatever is too wide scrolls instead of
//! pushing; and the texts known to be long (paths, file names, messages that quote them) are
//! elided here, as a file manager does: a path keeps its start and its file name and loses
//! the middle, a message keeps its start.

use std::borrow::Cow;

use eframe::egui;

/// The ellipsis that replaces what was cut.
const ELLIPSIS: char = '…';

/// Characters kept before the ellipsis, as a share of those kept: a path's end (the file
/// name) tells more than its start.
const HEAD_SHARE: f32 = 0.35;

/// `text` with its middle replaced by an ellipsis so that `fits` accepts it, keeping as many
/// characters as possible (about a third before the cut, the rest after it). The text itself
/// when it fits; just the ellipsis when nothing else does.
#[must_use]
pub fn elide_middle<'a>(text: &'a str, fits: impl Fn(&str) -> bool) -> Cow<'a, str> {
    if fits(text) {
        return Cow::Borrowed(text);
    }
    let chars: Vec<char> = text.chars().collect();
    let with = |kept: usize| -> String {
        let head = ((kept as f32 * HEAD_SHARE).round() as usize).min(kept);
        let tail = kept - head;
        let mut s: String = chars[..head].iter().collect();
        s.push(ELLIPSIS);
        s.extend(&chars[chars.len() - tail..]);
        s
    };
    // The widest elision that fits: `fits` is monotone in the characters kept (a longer cut
    // is never wider), so a binary search over 0..len finds it in log2(len) layouts.
    let (mut lo, mut hi) = (0, chars.len() - 1);
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        if fits(&with(mid)) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    Cow::Owned(with(lo))
}

/// A label at most `max_width` points wide (and never wider than what is left in `ui`):
/// `text` elided in the middle when it is wider, with the full text on hover and as the
/// label's accessible text. `strong` draws it in the strong text colour.
pub fn elided_middle(
    ui: &mut egui::Ui,
    text: &str,
    max_width: f32,
    strong: bool,
) -> egui::Response {
    let width = ui.available_width().min(max_width);
    let font = egui::TextStyle::Body.resolve(ui.style());
    let painter = ui.painter().clone();
    let fits = |s: &str| {
        painter
            .layout_no_wrap(s.to_owned(), font.clone(), egui::Color32::WHITE)
            .size()
            .x
            <= width
    };
    let shown = elide_middle(text, fits);
    let cut = shown.len() != text.len();
    let mut rich = egui::RichText::new(shown.as_ref());
    if strong {
        rich = rich.strong();
    }
    let response = ui.add(egui::Label::new(rich).wrap_mode(egui::TextWrapMode::Extend));
    if cut {
        let full = text.to_owned();
        response.widget_info(|| {
            egui::WidgetInfo::labeled(egui::accesskit::Role::Label, true, full.as_str())
        });
        response.on_hover_text(text)
    } else {
        response
    }
}

/// A label cut at the end to the width left (egui's own elision: the full text on hover and
/// in the accessibility tree), for messages whose start says what happened.
pub fn elided_end(ui: &mut egui::Ui, text: impl Into<egui::WidgetText>) -> egui::Response {
    ui.add(egui::Label::new(text).truncate())
}

/// A scroll area that takes exactly the room `ui` offers and scrolls (both ways) whatever is
/// larger, so the panel around it keeps the size the user gave it.
pub fn bounded(id: &str) -> egui::ScrollArea {
    egui::ScrollArea::both()
        .id_salt(id)
        .auto_shrink([false, false])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A monospace "width": one unit a character.
    fn at_most(n: usize) -> impl Fn(&str) -> bool {
        move |s: &str| s.chars().count() <= n
    }

    #[test]
    fn a_text_that_fits_is_kept_as_it_is() {
        assert!(matches!(
            elide_middle("/a/b.obj", at_most(8)),
            Cow::Borrowed("/a/b.obj")
        ));
    }

    #[test]
    fn a_long_path_keeps_its_start_and_its_file_name() {
        let path = "/home/someone/a folder with a long name/another one/model.glb";
        for n in [10, 20, 40, path.chars().count() - 1] {
            let e = elide_middle(path, at_most(n));
            assert_eq!(e.chars().count(), n, "{e}");
            assert_eq!(e.matches(ELLIPSIS).count(), 1, "{e}");
            let (head, tail) = e.split_once(ELLIPSIS).unwrap();
            assert!(path.starts_with(head) && path.ends_with(tail), "{e}");
            assert!(tail.len() >= head.len(), "the end is kept first: {e}");
        }
        assert!(elide_middle(path, at_most(20)).ends_with("model.glb"));
    }

    #[test]
    fn multibyte_characters_are_never_split() {
        let name = "モデル/とても長いフォルダの名前/ファイル.obj";
        for n in 1..name.chars().count() {
            let e = elide_middle(name, at_most(n));
            assert!(e.chars().count() <= n.max(1), "{n}: {e}");
        }
    }

    #[test]
    fn nothing_fits_leaves_the_ellipsis() {
        assert_eq!(elide_middle("abc", |_| false), "…");
        assert_eq!(elide_middle("", at_most(0)), "");
    }
}
