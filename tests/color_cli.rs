//! `realist color VALUE --json` against every colour of colour-science's reference
//! (`$REALIST_SHARED/color/reference.json`; reported as ignored when unset).

mod common;

use std::process::Command;

use serde_json::Value;

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn color_json_matches_colour_science() {
    let reference = common::colour_reference("the `realist color` reference test");
    let colours = reference["colour_models"]["colours"].as_object().unwrap();
    let keys = [
        ("linear", "srgb_linear"),
        ("hsv", "hsv"),
        ("hsl", "hsl"),
        ("cmy", "cmy"),
        ("cmyk", "cmyk"),
        ("yiq", "yiq_skimage"),
        ("yuv", "yuv_bt601_skimage"),
        ("ycbcr601", "ycbcr_bt601_full_float"),
        ("ycbcr709", "ycbcr_bt709_full_float"),
        ("xyz", "XYZ"),
        ("xyy", "xyY"),
        ("u'v'", "uv_prime_1976"),
        ("lab", "Lab_D65"),
        ("lch", "LCHab_D65"),
        ("luv", "Luv_D65"),
    ];
    let mut checked = 0;
    for (name, e) in colours {
        let rgb: Vec<String> = e["srgb"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.to_string())
            .collect();
        let out = Command::new(env!("CARGO_BIN_EXE_realist"))
            .args(["color", &rgb.join(","), "--json"])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let got: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(
            got.as_object().unwrap().len(),
            16,
            "{name}: every model by default"
        );
        for (model, key) in keys {
            let g = got[model].as_array().unwrap();
            let w = e[key].as_array().unwrap();
            assert_eq!(g.len(), w.len(), "{name} {model}");
            for (a, b) in g.iter().zip(w) {
                let d = (a.as_f64().unwrap() - b.as_f64().unwrap()).abs();
                assert!(d <= 1e-9, "{name} {model}: got {g:?}, want {w:?}");
            }
            checked += 1;
        }
        // CIE 1960 uv from the reference's xy.
        let xyy = &e["xyY"];
        let (x, y) = (xyy[0].as_f64().unwrap(), xyy[1].as_f64().unwrap());
        let d = -2.0 * x + 12.0 * y + 3.0;
        let uv = &got["uv"];
        assert!(
            (uv[0].as_f64().unwrap() - 4.0 * x / d).abs() < 1e-12,
            "{name} uv"
        );
        assert!(
            (uv[1].as_f64().unwrap() - 6.0 * y / d).abs() < 1e-12,
            "{name} uv"
        );
    }
    assert_eq!(checked, 15 * 15);

    let out = Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(["color", "#ff0000", "--to", "hsv,nope"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("unknown model 'nope'") && err.lines().count() == 1,
        "{err}"
    );
}
