//! Material overrides (`[[material]]`): which of the model's materials each selects, and
//! the values it sets.

use super::*;

/// Applies material overrides `specs` (key prefix `key`, e.g. `material`) to `materials`.
pub(crate) fn materials(
    key: &str,
    specs: &[MaterialSpec],
    materials: &mut [Material],
) -> Result<(), Bad> {
    for (i, s) in specs.iter().enumerate() {
        let key = format!("{key}[{i}]");
        let targets = select(&key, s, materials)?;
        for t in targets {
            override_material(&key, s, &mut materials[t])?;
        }
    }
    Ok(())
}

/// Checks an override's values without a model (every field but the selection).
pub(crate) fn check_material(key: &str, s: &MaterialSpec) -> Result<(), Bad> {
    if s.index.is_some() == s.name.is_some() {
        return Err(bad(key, "give exactly one of index or name"));
    }
    override_material(key, s, &mut Material::default())
}

/// Indices of the materials an override selects.
fn select(key: &str, s: &MaterialSpec, materials: &[Material]) -> Result<Vec<usize>, Bad> {
    let count = materials.len();
    match (s.index, &s.name) {
        (Some(i), None) if i < count => Ok(vec![i]),
        (Some(i), None) if count == 0 => Err(bad(
            format!("{key}.index"),
            format!("{i}, but the model has no materials (its meshes use the default)"),
        )),
        (Some(i), None) => Err(bad(
            format!("{key}.index"),
            format!("{i}, but the model has only {count} material(s)"),
        )),
        (None, Some(name)) => {
            let hits: Vec<usize> = (0..count).filter(|&m| materials[m].name == *name).collect();
            if hits.is_empty() {
                let names: Vec<&str> = materials.iter().take(12).map(|m| m.name.as_str()).collect();
                Err(bad(
                    format!("{key}.name"),
                    format!(
                        "no material is named '{name}' (the model has: {}{})",
                        names.join(", "),
                        if count > 12 { ", ..." } else { "" }
                    ),
                ))
            } else {
                Ok(hits)
            }
        }
        _ => Err(bad(key, "give exactly one of index or name")),
    }
}

fn override_material(key: &str, s: &MaterialSpec, m: &mut Material) -> Result<(), Bad> {
    let k = |f: &str| format!("{key}.{f}");
    if let Some(c) = &s.base_color {
        let c = color(&k("base_color"), c, MAX_RADIANCE, true)?;
        m.base_color = if s.base_color.as_ref().is_some_and(|c| c.0.len() == 3) {
            c.truncate().extend(m.base_color.w)
        } else {
            c
        };
    }
    if let Some(c) = &s.specular {
        m.specular = color(&k("specular"), c, MAX_RADIANCE, false)?.truncate();
    }
    if let Some(c) = &s.ambient {
        m.ambient = color(&k("ambient"), c, MAX_RADIANCE, false)?.truncate();
    }
    if let Some(n) = s.shininess {
        m.shininess = ranged(&k("shininess"), n, 1.0, 2000.0)?;
    }
    if let Some(d) = s.double_sided {
        m.double_sided = d;
    }
    let cutoff = s
        .alpha_cutoff
        .map(|c| ranged(&k("alpha_cutoff"), c, 0.0, 1.0))
        .transpose()?;
    match (s.alpha_mode.map(|a| a.0), cutoff) {
        (Some(AlphaKind::Opaque), None) => m.alpha_mode = AlphaMode::Opaque,
        (Some(AlphaKind::Blend), None) => m.alpha_mode = AlphaMode::Blend,
        (Some(AlphaKind::Mask), c) => m.alpha_mode = AlphaMode::Mask(c.unwrap_or(0.5)),
        (None, Some(c)) if matches!(m.alpha_mode, AlphaMode::Mask(_)) => {
            m.alpha_mode = AlphaMode::Mask(c);
        }
        (_, Some(_)) => {
            return Err(bad(
                k("alpha_cutoff"),
                "is only used with alpha_mode = \"mask\"",
            ))
        }
        (None, None) => {}
    }
    Ok(())
}
