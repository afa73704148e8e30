//! `realist._realist`: the native half of the `realist` Python package (pyo3 + rust-numpy,
//! built by maturin). The Python half (`python/realist/__init__.py`) converts arrays to
//! the dtypes this module takes and re-exports everything; the stubs
//! (`python/realist/__init__.pyi`) are the documented interface.
//!
//! | file | owns |
//! |---|---|
//! | `scene.rs` | `Scene`: a loaded model or one made from numpy arrays, prepared once |
//! | `camera.rs` | `Camera`: look-at, orbit, and a calibrated camera from intrinsics |
//! | `options.rs` | the keyword arguments of `render` as realist's settings |
//! | `frame.rs` | rendering one frame into plain buffers (no Python), and `Frame` |
//! | `render.rs` | `render` and `render_many` (the GIL released while they work) |
//! | `colour.rs` | the colour toolkit over numpy arrays, the chromaticity diagram |
//!
//! Nothing here panics on user input: bad arguments are `ValueError`s naming the argument,
//! files that cannot be loaded raise realist's message (a missing file `FileNotFoundError`),
//! and a panic inside a render is caught and raised as `RealistError`.

use pyo3::prelude::*;

mod camera;
mod colour;
mod frame;
mod options;
mod render;
mod scene;

pyo3::create_exception!(
    realist,
    RealistError,
    pyo3::exceptions::PyException,
    "An error from realist (a file it cannot read, a render that failed); the message is realist's."
);

/// The native module.
#[pymodule]
fn _realist(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("RealistError", m.py().get_type::<RealistError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<camera::Camera>()?;
    m.add_class::<frame::Frame>()?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::render_many, m)?)?;
    m.add_function(wrap_pyfunction!(render::shading_modes, m)?)?;
    colour::register(m)?;
    Ok(())
}
