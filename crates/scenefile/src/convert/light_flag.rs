//! The command line's `--light KIND:KEY=VALUE...`, read through the scene files' light table so both say the same about a light.

use super::*;

/// The light syntax of `--light`, for `--help`.
pub const LIGHT_SYNTAX: &str =
    "KIND[:KEY=VALUE]...  KIND: ambient, directional, point, spot, rect. \
Keys: name=TEXT, color=R,G,B (linear), intensity=X, pos=X,Y,Z, dir=X,Y,Z, target=X,Y,Z, \
inner=DEG, outer=DEG (spot half-angles), rect=H,V (degrees), up=X,Y,Z, image=PATH, \
att=none|inverse-square|linear,NEAR,FAR|range,R, and the flag shadow. \
Example: spot:pos=0,4,2:target=0,0,0:inner=20:outer=30:att=linear,1,10:shadow";

/// One `--light` value (see [`LIGHT_SYNTAX`]), with `image` relative to the working
/// directory.
///
/// # Errors
/// A message naming the part that is wrong.
pub fn parse_light(text: &str) -> Result<Light, String> {
    let mut parts = text.split(':');
    let kind: LightKind = parts.next().unwrap_or("").trim().parse()?;
    let mut spec = LightSpec {
        kind: crate::schema::Kw(kind),
        ..LightSpec::default()
    };
    let nums = |k: &str, v: &str, n: usize| -> Result<Vec<f64>, String> {
        let xs: Vec<f64> = v
            .split(',')
            .map(|x| {
                x.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("{k}: bad number '{x}'"))
            })
            .collect::<Result<_, _>>()?;
        if xs.len() == n {
            Ok(xs)
        } else {
            Err(format!("{k}: expected {n} numbers, got {}", xs.len()))
        }
    };
    let v3 = |k: &str, v: &str| nums(k, v, 3).map(|x| [x[0], x[1], x[2]]);
    let one = |k: &str, v: &str| nums(k, v, 1).map(|x| x[0]);
    for part in parts {
        let (k, v) = part.split_once('=').unwrap_or((part, ""));
        match (k.trim(), v) {
            ("shadow", "") => spec.shadow = Some(true),
            ("name", v) => spec.name = Some(v.to_owned()),
            ("color", v) => spec.color = Some(Rgba(nums(k, v, 3)?)),
            ("intensity", v) => spec.intensity = Some(one(k, v)?),
            ("pos" | "position", v) => spec.position = Some(v3(k, v)?),
            ("dir" | "direction", v) => spec.direction = Some(v3(k, v)?),
            ("target", v) => spec.target = Some(v3(k, v)?),
            ("up", v) => spec.up = Some(v3(k, v)?),
            ("inner", v) => spec.inner = Some(one(k, v)?),
            ("outer", v) => spec.outer = Some(one(k, v)?),
            ("rect", v) => {
                let x = nums(k, v, 2)?;
                spec.rect = Some([x[0], x[1]]);
            }
            ("image", v) => spec.image = Some(v.to_owned()),
            ("att" | "attenuation", v) => spec.attenuation = Some(parse_attenuation(v)?),
            (k, _) => return Err(format!("unknown light key '{k}' in '{part}'")),
        }
    }
    let mut l = light("--light", &spec).map_err(|(k, r)| format!("{k}: {r}"))?;
    if let Some(p) = &spec.image {
        let img = image(std::path::Path::new(p)).map_err(|e| e.to_string())?;
        l.image = Some(img);
    }
    Ok(l)
}

pub(super) fn parse_attenuation(v: &str) -> Result<AttenuationSpec, String> {
    let mut it = v.split(',');
    let mode = crate::schema::Keyword::parse_keyword(it.next().unwrap_or("").trim())?;
    let rest: Vec<f64> = it
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| format!("att: bad number '{x}'"))
        })
        .collect::<Result<_, _>>()?;
    let spec = |near, far, range| AttenuationSpec {
        mode: crate::schema::Kw(mode),
        near,
        far,
        range,
    };
    match (mode, rest.as_slice()) {
        (AttenuationMode::None | AttenuationMode::InverseSquare, []) => Ok(spec(None, None, None)),
        (AttenuationMode::Linear, &[n, f]) => Ok(spec(Some(n), Some(f), None)),
        (AttenuationMode::Range, &[r]) => Ok(spec(None, None, Some(r))),
        _ => Err(format!(
            "att={v}: expected none, inverse-square, linear,NEAR,FAR or range,R"
        )),
    }
}
