//! The OBJ text as the `BufRead` that `tobj` parses, with a progress checkpoint every
//! [`CHUNK`] bytes: `tobj` asks for a line at a time, so this is where its parse can be
//! followed and cancelled without a check per line.

use std::io::{BufRead, Read};

use crate::progress::Tracker;

/// Bytes between two checkpoints (about half a millisecond of `tobj` parsing).
const CHUNK: usize = 64 << 10;

/// A byte slice read in [`CHUNK`]s; a cancelled load makes the next chunk an I/O error
/// (which `tobj` returns as its read error).
pub(super) struct Checked<'a> {
    text: &'a [u8],
    pos: usize,
    /// End of the chunk being read: the next checkpoint is when `pos` reaches it.
    end: usize,
    tracker: &'a Tracker,
}

impl<'a> Checked<'a> {
    pub(super) fn new(text: &'a [u8], tracker: &'a Tracker) -> Self {
        Self {
            text,
            pos: 0,
            end: 0,
            tracker,
        }
    }
}

impl BufRead for Checked<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.pos >= self.end && self.pos < self.text.len() {
            self.tracker
                .advance(self.pos as u64)
                .map_err(|e| std::io::Error::other(e.to_string()))?;
            self.end = self.pos.saturating_add(CHUNK).min(self.text.len());
        }
        Ok(self.text.get(self.pos..self.end).unwrap_or_default())
    }

    fn consume(&mut self, amt: usize) {
        self.pos = self.pos.saturating_add(amt).min(self.end);
    }
}

impl Read for Checked<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(buf.len());
        buf[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Progress;

    #[test]
    fn lines_cross_chunks_intact_and_a_cancel_is_an_error() {
        let text: String = (0..20_000).map(|i| format!("v {i} {i} {i}\n")).collect();
        let progress = Progress::new();
        let tracker = Tracker::new(std::path::Path::new("m.obj"), Some(&progress));
        let mut reader = Checked::new(text.as_bytes(), &tracker);
        let lines: Vec<String> = (&mut reader).lines().map(Result::unwrap).collect();
        assert_eq!(lines.len(), 20_000);
        assert_eq!(lines[19_999], "v 19999 19999 19999");
        assert!(text.len() > 3 * CHUNK);

        progress.cancel();
        let reader = Checked::new(text.as_bytes(), &tracker);
        let err = reader.lines().next().unwrap().unwrap_err();
        assert_eq!(err.to_string(), "m.obj: load cancelled");
    }
}
