//! Accessor reading with checked arithmetic.
//!
//! An accessor is first copied into tightly packed little-endian elements: from its
//! bufferView (`byteOffset + byteStride * (count - 1) + elementSize <= byteLength`, the view
//! itself inside its buffer, stride no smaller than an element), or as zeros when it has no
//! bufferView; then sparse substitution is applied (every sparse index < count). Only then
//! is it converted, to `f32` (with normalisation of integer components) or to `u32`
//! indices. The packed copy and the result are charged to the budget first.

use gltf::json::accessor::{ComponentType, GenericComponentType, IndexComponentType, Type};
use gltf::json::validation::Checked;

use super::{Doc, GltfError};
use crate::LoadError;

/// The component types accepted for an attribute.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Format {
    /// FLOAT only.
    Float,
    /// FLOAT, or normalized UNSIGNED_BYTE / UNSIGNED_SHORT.
    FloatOrUnorm,
    /// FLOAT or any 8- or 16-bit integer, normalized or not (`KHR_mesh_quantization`).
    Quantized,
}

impl Format {
    fn accepts(self, c: ComponentType, normalized: bool) -> bool {
        use ComponentType::{F32, I16, I8, U16, U8};
        match self {
            Format::Float => c == F32,
            Format::FloatOrUnorm => c == F32 || (normalized && matches!(c, U8 | U16)),
            Format::Quantized => matches!(c, F32 | I8 | U8 | I16 | U16),
        }
    }

    fn expected(self) -> &'static str {
        match self {
            Format::Float => "FLOAT",
            Format::FloatOrUnorm => "FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT",
            Format::Quantized => "FLOAT or an 8/16-bit integer type",
        }
    }
}

/// One component as `f32`; normalized integers map to [0, 1] (unsigned) or [-1, 1]
/// (signed, as `max(x / max, -1)`), other integers keep their value.
fn to_f32(c: ComponentType, normalized: bool, b: &[u8]) -> f32 {
    let (value, max) = match (c, b) {
        (ComponentType::F32, &[a, b, c, d]) => return f32::from_le_bytes([a, b, c, d]),
        (ComponentType::U8, &[a]) => (f32::from(a), 255.0),
        (ComponentType::I8, &[a]) => (f32::from(a as i8), 127.0),
        (ComponentType::U16, &[a, b]) => (f32::from(u16::from_le_bytes([a, b])), 65535.0),
        (ComponentType::I16, &[a, b]) => (f32::from(i16::from_le_bytes([a, b])), 32767.0),
        (ComponentType::U32, &[a, b, c, d]) => {
            (u32::from_le_bytes([a, b, c, d]) as f32, u32::MAX as f32)
        }
        _ => return 0.0,
    };
    if normalized {
        (value / max).max(-1.0)
    } else {
        value
    }
}

/// An accessor's elements, tightly packed.
struct Packed {
    component: ComponentType,
    components: usize,
    normalized: bool,
    bytes: Vec<u8>,
}

fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

impl Doc<'_> {
    fn accessor_error(&self, accessor: usize, used_by: &str, reason: String) -> LoadError {
        GltfError::Accessor {
            path: self.path.to_owned(),
            accessor,
            used_by: used_by.to_owned(),
            reason,
        }
        .into()
    }

    /// Reads accessor `index` as `f32`s: returns the component count (one of `allowed`) and
    /// `count * components` values (see [`to_f32`]).
    pub(super) fn read_floats(
        &self,
        index: usize,
        used_by: &str,
        allowed: &[usize],
        format: Format,
    ) -> Result<(usize, Vec<f32>), LoadError> {
        let p = self.packed(index, used_by)?;
        let bad = |reason: String| self.accessor_error(index, used_by, reason);
        if !allowed.contains(&p.components) {
            return Err(bad(format!(
                "has {} components, expected {allowed:?}",
                p.components
            )));
        }
        if !format.accepts(p.component, p.normalized) {
            let (c, n, expected) = (p.component, p.normalized, format.expected());
            return Err(bad(format!(
                "component type {c:?} (normalized: {n}), expected {expected}"
            )));
        }
        self.budget.charge(p.bytes.len() as u64 * 4, || {
            format!("accessor {index} as floats")
        })?;
        let size = component_size(p.component);
        let values = p
            .bytes
            .chunks_exact(size)
            .map(|b| to_f32(p.component, p.normalized, b))
            .collect();
        Ok((p.components, values))
    }

    /// Reads accessor `index` as vertex indices (SCALAR UNSIGNED_BYTE/SHORT/INT).
    pub(super) fn read_indices(&self, index: usize, used_by: &str) -> Result<Vec<u32>, LoadError> {
        let p = self.packed(index, used_by)?;
        if p.components != 1 {
            return Err(self.accessor_error(
                index,
                used_by,
                format!("has {} components, expected SCALAR", p.components),
            ));
        }
        self.budget.charge(p.bytes.len() as u64 * 4, || {
            format!("accessor {index} as indices")
        })?;
        Ok(match p.component {
            ComponentType::U8 => p.bytes.iter().map(|&b| u32::from(b)).collect(),
            ComponentType::U16 => p
                .bytes
                .chunks_exact(2)
                .map(|b| u32::from(u16::from_le_bytes([b[0], b[1]])))
                .collect(),
            ComponentType::U32 => p
                .bytes
                .chunks_exact(4)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect(),
            c => {
                let reason = format!(
                    "component type {c:?}, expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT"
                );
                return Err(self.accessor_error(index, used_by, reason));
            }
        })
    }

    /// Copies accessor `index` into packed elements, applying sparse substitution.
    fn packed(&self, index: usize, used_by: &str) -> Result<Packed, LoadError> {
        let count_all = self.json.accessors.len();
        let acc = self
            .json
            .accessors
            .get(index)
            .ok_or_else(|| self.missing(used_by, "accessor", index, count_all))?;
        let bad = |reason: String| self.accessor_error(index, used_by, reason);
        let component = match acc.component_type {
            Checked::Valid(GenericComponentType(c)) => c,
            Checked::Invalid => return Err(bad("invalid componentType".into())),
        };
        let components = match acc.type_ {
            Checked::Valid(Type::Scalar) => 1,
            Checked::Valid(Type::Vec2) => 2,
            Checked::Valid(Type::Vec3) => 3,
            Checked::Valid(Type::Vec4) => 4,
            // Only FLOAT matrices are read (skins' inverse bind matrices): no column padding.
            Checked::Valid(Type::Mat4) if component == ComponentType::F32 => 16,
            Checked::Valid(t) => {
                return Err(bad(format!("type {t:?} is not a vertex attribute type")))
            }
            Checked::Invalid => return Err(bad("invalid type".into())),
        };
        let elem = components * component_size(component);
        let count = acc.count.0;
        let total = count
            .checked_mul(elem as u64)
            .filter(|&t| t <= isize::MAX as u64);
        let total = total.ok_or_else(|| bad(format!("count {count} is too large")))?;
        self.budget
            .charge(total, || format!("accessor {index} ({count} elements)"))?;
        let total = total as usize;
        // A Draco-compressed primitive's accessors come from its decoded mesh (`draco`).
        if let Some(packed) = self.draco_accessors.borrow().get(&index) {
            if packed.0.len() != total {
                return Err(bad(format!(
                    "{} bytes decoded from Draco, expected {total}",
                    packed.0.len()
                )));
            }
            return Ok(Packed {
                component,
                components,
                normalized: acc.normalized,
                bytes: packed.0.clone(),
            });
        }
        let mut bytes = match acc.buffer_view {
            None => vec![0u8; total],
            Some(v) => {
                let (view, stride) = self.view(v.value(), &format!("accessor {index}"))?;
                let stride = stride.unwrap_or(elem);
                if stride < elem {
                    return Err(bad(format!(
                        "byteStride {stride} is smaller than the element size {elem}"
                    )));
                }
                let offset = acc.byte_offset.map_or(0, |o| o.0);
                strided_copy(view, offset, stride, elem, count).map_err(bad)?
            }
        };
        if let Some(sparse) = &acc.sparse {
            self.apply_sparse(sparse, &mut bytes, elem, count)
                .map_err(bad)?;
        }
        Ok(Packed {
            component,
            components,
            normalized: acc.normalized,
            bytes,
        })
    }

    /// Substitutes the sparse values into `bytes` (`count` elements of `elem` bytes).
    fn apply_sparse(
        &self,
        sparse: &gltf::json::accessor::sparse::Sparse,
        bytes: &mut [u8],
        elem: usize,
        count: u64,
    ) -> Result<(), String> {
        let n = sparse.count.0;
        if n > count {
            return Err(format!("sparse count {n} exceeds count {count}"));
        }
        let isize = match sparse.indices.component_type {
            Checked::Valid(IndexComponentType(
                c @ (ComponentType::U8 | ComponentType::U16 | ComponentType::U32),
            )) => component_size(c),
            _ => {
                return Err(
                    "sparse indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT".into(),
                )
            }
        };
        let view_of = |v: usize| {
            self.view(v, "sparse accessor")
                .map(|(b, _)| b)
                .map_err(|e| e.to_string())
        };
        let ix_view = view_of(sparse.indices.buffer_view.value())?;
        let ix = strided_copy(ix_view, sparse.indices.byte_offset.0, isize, isize, n)
            .map_err(|e| format!("sparse indices: {e}"))?;
        let val_view = view_of(sparse.values.buffer_view.value())?;
        let vals = strided_copy(val_view, sparse.values.byte_offset.0, elem, elem, n)
            .map_err(|e| format!("sparse values: {e}"))?;
        for (j, (i, v)) in ix
            .chunks_exact(isize)
            .zip(vals.chunks_exact(elem))
            .enumerate()
        {
            let target = match i {
                [a] => u64::from(*a),
                [a, b] => u64::from(u16::from_le_bytes([*a, *b])),
                [a, b, c, d] => u64::from(u32::from_le_bytes([*a, *b, *c, *d])),
                _ => return Err("bad sparse index size".into()),
            };
            let start = (target as usize).checked_mul(elem);
            let dst = start.and_then(|s| bytes.get_mut(s..s.checked_add(elem)?));
            let dst = dst.ok_or_else(|| {
                format!("sparse index {target} (entry {j}) is not below count {count}")
            })?;
            dst.copy_from_slice(v);
        }
        Ok(())
    }
}

/// Copies `count` elements of `elem` bytes, `stride` apart from `offset`, out of `view`,
/// after checking that `offset + stride * (count - 1) + elem <= view.len()`.
fn strided_copy(
    view: &[u8],
    offset: u64,
    stride: usize,
    elem: usize,
    count: u64,
) -> Result<Vec<u8>, String> {
    if count == 0 {
        return Ok(Vec::new());
    }
    let end = (stride as u64)
        .checked_mul(count - 1)
        .and_then(|x| x.checked_add(offset))
        .and_then(|x| x.checked_add(elem as u64));
    let fits = end.is_some_and(|e| e <= view.len() as u64);
    if !fits {
        let needed = end.map_or_else(|| "more than 2^64".to_string(), |e| e.to_string());
        return Err(format!(
            "needs {needed} bytes ({count} elements of {elem} bytes, stride {stride}, offset {offset}) but its bufferView has {}",
            view.len()
        ));
    }
    // In range of `view`, so these fit in usize.
    let (offset, count) = (offset as usize, count as usize);
    let mut out = Vec::with_capacity(count * elem);
    if stride == elem {
        out.extend_from_slice(view.get(offset..offset + count * elem).unwrap_or(&[]));
    } else {
        for i in 0..count {
            let s = offset + i * stride;
            out.extend_from_slice(view.get(s..s + elem).unwrap_or(&[]));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strided_copy_checks_the_range() {
        let view: Vec<u8> = (0..10).collect();
        assert_eq!(strided_copy(&view, 0, 4, 2, 3).unwrap(), [0, 1, 4, 5, 8, 9]);
        assert_eq!(
            strided_copy(&view, 2, 2, 2, 4).unwrap(),
            [2, 3, 4, 5, 6, 7, 8, 9]
        );
        assert!(strided_copy(&view, 1, 4, 2, 3)
            .unwrap_err()
            .contains("needs 11 bytes"));
        assert!(strided_copy(&view, 0, 4, 4, u64::MAX).is_err());
        assert!(strided_copy(&view, u64::MAX, 1, 1, 1).is_err());
        assert!(strided_copy(&view, 99, 1, 1, 0).unwrap().is_empty());
    }

    #[test]
    fn components_convert_and_normalise() {
        assert_eq!(to_f32(ComponentType::U8, true, &[255]), 1.0);
        assert_eq!(to_f32(ComponentType::I8, true, &[0x80]), -1.0);
        assert_eq!(
            to_f32(ComponentType::I16, false, &(-300i16).to_le_bytes()),
            -300.0
        );
        assert_eq!(to_f32(ComponentType::U16, true, &[0xff, 0xff]), 1.0);
        assert_eq!(
            to_f32(ComponentType::F32, false, &1.5f32.to_le_bytes()),
            1.5
        );
        assert!(Format::Quantized.accepts(ComponentType::I16, false));
        assert!(!Format::FloatOrUnorm.accepts(ComponentType::U8, false));
    }
}
