//! The colour toolkit (`realist color`, crates/color) over numpy arrays, and the
//! chromaticity diagram (`realist chroma`) as an RGBA array. `realist/color.py` wraps these
//! under readable names.

use numpy::ndarray::{ArrayD, Axis, IxDyn};
use numpy::{IntoPyArray, PyArray3, PyArrayDyn, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use realist::color::named::{convert, parse_colour, MODELS};
use realist::color::{self, Illuminant, Observer, RgbSpace, Transfer};
use realist::overlay::chroma::{self, ChromaOptions, FillStyle, Marker, Plane};

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(color_convert, m)?)?;
    m.add_function(wrap_pyfunction!(color_map, m)?)?;
    m.add_function(wrap_pyfunction!(delta_e, m)?)?;
    m.add_function(wrap_pyfunction!(chromaticity_diagram, m)?)?;
    m.add("COLOR_MODELS", MODELS.to_vec())?;
    m.add(
        "COLOR_FUNCTIONS",
        FUNCTIONS.iter().map(|f| f.0).collect::<Vec<_>>(),
    )?;
    m.add("GAMUTS", RgbSpace::NAMES.to_vec())?;
    Ok(())
}

/// One colour in every model (or those in `to`), as `realist color VALUE --json` prints it:
/// a dict from model name to a list of floats, with "srgb" the colour read.
#[pyfunction]
#[pyo3(signature = (value, to=None))]
fn color_convert<'py>(
    py: Python<'py>,
    value: &str,
    to: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    let rgb = parse_colour(value).map_err(PyValueError::new_err)?;
    let models = to.unwrap_or_else(|| MODELS.iter().map(|m| (*m).to_owned()).collect());
    let out = PyDict::new(py);
    out.set_item("srgb", rgb.to_vec())?;
    for m in models {
        let key = m.trim().to_ascii_lowercase();
        let v = convert(rgb, &key).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown model '{m}' (expected {})",
                MODELS.join(", ")
            ))
        })?;
        out.set_item(key, v)?;
    }
    Ok(out)
}

type Map3 = fn([f64; 3]) -> [f64; 3];

fn d65() -> [f64; 3] {
    Illuminant::D65.xyz(Observer::Cie1931)
}

/// The per-colour functions `color_map` applies, by name (D65 and the 2 degree observer
/// where a white is needed).
const FUNCTIONS: [(&str, Map3); 16] = [
    ("srgb_to_xyz", color::srgb_to_xyz),
    ("xyz_to_srgb", color::xyz_to_srgb),
    ("srgb_to_lab", color::srgb_to_lab),
    ("srgb_to_linear", color::srgb_decode3),
    ("linear_to_srgb", color::srgb_encode3),
    ("xyz_to_lab", |v| color::xyz_to_lab(v, d65())),
    ("lab_to_xyz", |v| color::lab_to_xyz(v, d65())),
    ("xyz_to_luv", |v| color::xyz_to_luv(v, d65())),
    ("luv_to_xyz", |v| color::luv_to_xyz(v, d65())),
    ("lab_to_lch", color::lab_to_lch),
    ("lch_to_lab", color::lch_to_lab),
    ("xyz_to_xyy", color::xyz_to_xyy),
    ("xyy_to_xyz", color::xyy_to_xyz),
    ("rgb_to_hsv", color::rgb_to_hsv),
    ("hsv_to_rgb", color::hsv_to_rgb),
    ("rgb_to_hsl", color::rgb_to_hsl),
];

/// A (..., 3) float64 array's colours.
fn triples<'a>(
    a: &'a PyReadonlyArrayDyn<'_, f64>,
    name: &str,
) -> PyResult<numpy::ndarray::ArrayViewD<'a, f64>> {
    if a.shape().last() != Some(&3) {
        return Err(PyValueError::new_err(format!(
            "{name}: expected an array of colours, shape (..., 3), got {:?}",
            a.shape()
        )));
    }
    Ok(a.as_array())
}

/// Applies the function `name` (one of COLOR_FUNCTIONS) to every colour of a (..., 3)
/// float64 array; returns an array of the same shape.
#[pyfunction]
fn color_map<'py>(
    py: Python<'py>,
    name: &str,
    colours: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let f = FUNCTIONS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, f)| *f)
        .ok_or_else(|| PyValueError::new_err(format!("unknown colour function '{name}'")))?;
    let view = triples(&colours, "colours")?;
    let mut out = ArrayD::<f64>::zeros(IxDyn(view.shape()));
    let last = Axis(view.ndim() - 1);
    for (src, mut dst) in view.lanes(last).into_iter().zip(out.lanes_mut(last)) {
        let r = f([src[0], src[1], src[2]]);
        dst.iter_mut().zip(r).for_each(|(d, v)| *d = v);
    }
    Ok(out.into_pyarray(py))
}

/// The colour difference ΔE ("1976", "1994" or "2000") between two (..., 3) arrays of L*a*b*
/// colours of the same shape; returns shape (...).
#[pyfunction]
fn delta_e<'py>(
    py: Python<'py>,
    kind: &str,
    lab1: PyReadonlyArrayDyn<'py, f64>,
    lab2: PyReadonlyArrayDyn<'py, f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let f: fn([f64; 3], [f64; 3]) -> f64 = match kind {
        "1976" => color::delta_e_1976,
        "1994" => color::delta_e_1994,
        "2000" => color::delta_e_2000,
        k => {
            return Err(PyValueError::new_err(format!(
                "delta_e '{k}': expected 1976, 1994 or 2000"
            )))
        }
    };
    let (a, b) = (triples(&lab1, "lab1")?, triples(&lab2, "lab2")?);
    if a.shape() != b.shape() {
        return Err(PyValueError::new_err(format!(
            "lab1 and lab2 differ in shape: {:?} and {:?}",
            a.shape(),
            b.shape()
        )));
    }
    let last = Axis(a.ndim() - 1);
    let values: Vec<f64> = a
        .lanes(last)
        .into_iter()
        .zip(b.lanes(last))
        .map(|(x, y)| f([x[0], x[1], x[2]], [y[0], y[1], y[2]]))
        .collect();
    let shape = &a.shape()[..a.ndim() - 1];
    let out = ArrayD::from_shape_vec(IxDyn(shape), values)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(out.into_pyarray(py))
}

/// A gamut: a name (RgbSpace::NAMES) or six numbers (x, y of red, green, blue; white D65).
fn gamut(v: &Bound<'_, PyAny>, custom: &mut usize) -> PyResult<RgbSpace> {
    if let Ok(name) = v.extract::<String>() {
        return RgbSpace::named(&name).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown gamut '{name}' (expected {} or six numbers)",
                RgbSpace::NAMES.join(", ")
            ))
        });
    }
    let nums: Vec<f64> = v.extract().map_err(|_| {
        PyValueError::new_err("a gamut is a name or six numbers x1, y1, x2, y2, x3, y3")
    })?;
    if nums.len() != 6 || nums.iter().any(|v| !(-0.5..=1.5).contains(v)) {
        return Err(PyValueError::new_err(format!(
            "custom gamut {nums:?}: expected six chromaticities x1, y1, x2, y2, x3, y3"
        )));
    }
    *custom += 1;
    let p = [[nums[0], nums[1]], [nums[2], nums[3]], [nums[4], nums[5]]];
    let d65 = Illuminant::D65.xy(Observer::Cie1931);
    RgbSpace::new(&format!("custom {custom}"), p, d65, "D65", Transfer::Srgb)
        .map_err(|e| PyValueError::new_err(format!("custom gamut {nums:?}: {e}")))
}

/// A point to mark: (x, y) or (x, y, label), xy chromaticities.
fn marker(v: &Bound<'_, PyAny>) -> PyResult<Marker> {
    let bad = || PyValueError::new_err("a point is (x, y) or (x, y, label) with finite x and y");
    let (x, y, label) = if let Ok((x, y)) = v.extract::<(f64, f64)>() {
        (x, y, String::new())
    } else {
        v.extract::<(f64, f64, String)>().map_err(|_| bad())?
    };
    if !(x.is_finite() && y.is_finite()) {
        return Err(bad());
    }
    Ok(Marker { xy: [x, y], label })
}

/// The CIE chromaticity diagram (`realist chroma`) as straight-alpha sRGB RGBA, uint8
/// (size, size, 4).
#[pyfunction]
#[pyo3(signature = (size=1024, gamuts=None, points=None, *, plane="xy", observer="1931",
                    whites=None, planckian=false, fill="smooth", title=None))]
#[allow(clippy::too_many_arguments)]
fn chromaticity_diagram<'py>(
    py: Python<'py>,
    size: u32,
    gamuts: Option<Vec<Bound<'py, PyAny>>>,
    points: Option<Vec<Bound<'py, PyAny>>>,
    plane: &str,
    observer: &str,
    whites: Option<Vec<String>>,
    planckian: bool,
    fill: &str,
    title: Option<String>,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    if !(128..=8192).contains(&size) {
        return Err(PyValueError::new_err(format!(
            "size {size}: expected 128 to 8192 pixels"
        )));
    }
    let plane = Plane::named(plane).ok_or_else(|| {
        PyValueError::new_err(format!("unknown plane '{plane}' (expected xy, uv or u'v')"))
    })?;
    let observer = match observer {
        "1931" | "2" => Observer::Cie1931,
        "1964" | "10" => Observer::Cie1964,
        o => {
            return Err(PyValueError::new_err(format!(
                "unknown observer '{o}' (expected 1931 or 1964)"
            )))
        }
    };
    let fill = match fill.to_ascii_lowercase().as_str() {
        "smooth" => FillStyle::Smooth,
        "colour-science" | "color-science" => FillStyle::ColourScience,
        "none" => FillStyle::None,
        f => {
            return Err(PyValueError::new_err(format!(
                "unknown fill '{f}' (expected smooth, colour-science or none)"
            )))
        }
    };
    let mut custom = 0;
    let gamuts = gamuts
        .unwrap_or_default()
        .iter()
        .map(|g| gamut(g, &mut custom))
        .collect::<PyResult<Vec<_>>>()?;
    let points = points
        .unwrap_or_default()
        .iter()
        .map(marker)
        .collect::<PyResult<Vec<_>>>()?;
    if points.len() > 100_000 {
        return Err(PyValueError::new_err("points: more than 100000"));
    }
    let illuminants = whites
        .unwrap_or_default()
        .iter()
        .map(|w| {
            Illuminant::named(w)
                .map(|ill| Marker {
                    xy: ill.xy(observer),
                    label: ill.name().to_owned(),
                })
                .ok_or_else(|| {
                    PyValueError::new_err(format!(
                        "unknown illuminant '{w}' (expected a, c, d50, d65 or e)"
                    ))
                })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let opts = ChromaOptions {
        plane,
        size,
        observer,
        fill,
        gamuts,
        illuminants,
        planckian,
        points,
        title,
        ..ChromaOptions::default()
    };
    let rgba = py.detach(|| chroma::diagram(&opts).to_rgba8());
    let side = size as usize;
    let arr = numpy::ndarray::Array3::from_shape_vec((side, side, 4), rgba)
        .map_err(|e| crate::RealistError::new_err(format!("diagram size: {e}")))?;
    Ok(arr.into_pyarray(py))
}
