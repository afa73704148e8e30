use std::path::Path;

use super::*;

fn toml(text: &str) -> Result<SceneFile, SceneFileError> {
    SceneFile::parse(text, Format::Toml, Path::new("dir/exp.toml"))
}

fn err(text: &str) -> String {
    match toml(text) {
        Ok(f) => panic!("accepted:\n{text}\n{f:?}"),
        Err(e) => e.to_string(),
    }
}

mod compare;
mod errors;
mod lights;
mod materials;
mod round_trip;
