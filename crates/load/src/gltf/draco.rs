//! `KHR_draco_mesh_compression`: a primitive whose attributes and indices are one Draco
//! stream in a bufferView.
//!
//! The primitive's extension object `{bufferView, attributes: {"POSITION": id, ...}}` names
//! the stream and, for each compressed attribute, its Draco attribute id. The stream is
//! decoded (`draco-core`, a pure-Rust Draco decoder) and each listed attribute's accessor,
//! and the indices accessor, are then read from the decoded mesh instead of from their
//! bufferViews: [`Doc::draco_prepare`] packs them into the accessors' own component types
//! (so `KHR_mesh_quantization`-style integer accessors stay integers) and the accessor
//! reader takes them from [`Doc::draco_accessors`] while the primitive is built. Draco may
//! reorder vertices, which is why every compressed attribute and the indices must come from
//! the one decoded mesh; attributes the extension does not list are read as usual.
//!
//! Checked: the accessor counts against the decoded point and face counts, the mode
//! (TRIANGLES), and memory: the decoder's own ceiling on decoded bytes is what is left of the
//! load's budget, and the packed accessors are charged before they are made. A stream the
//! decoder refuses, or a panic inside it, is an error naming the mesh and primitive.

use draco_core::{DecodeLimits, DecoderBuffer, Mesh, MeshDecoder};
use gltf::json::accessor::{ComponentType, GenericComponentType, Type};
use gltf::json::mesh::{Mode, Primitive};
use gltf::json::validation::Checked;
use serde_json::Value;

use super::{Doc, GltfError};
use crate::{catch_decoder, LoadError};

/// The extension's name.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// An accessor's elements taken from a decoded Draco mesh, tightly packed little-endian in
/// the accessor's component type.
#[derive(Clone, Debug)]
pub struct Packed(pub Vec<u8>);

/// Decodes a Draco stream into a mesh, with at most `max_bytes` of decoded attribute values.
/// A panic inside the decoder is an error.
pub fn decode(bytes: &[u8], max_bytes: u64) -> Result<Mesh, String> {
    catch_decoder(|| {
        let limits = DecodeLimits::default().with_max_decoded_bytes(max_bytes);
        let mut buffer = DecoderBuffer::new(bytes).with_limits(limits);
        let mut mesh = Mesh::new();
        MeshDecoder::new()
            .decode(&mut buffer, &mut mesh)
            .map_err(|e| format!("Draco stream: {e}"))?;
        Ok(mesh)
    })
}

/// Bytes per component of `c`.
fn component_size(c: ComponentType) -> usize {
    match c {
        ComponentType::I8 | ComponentType::U8 => 1,
        ComponentType::I16 | ComponentType::U16 => 2,
        ComponentType::U32 | ComponentType::F32 => 4,
    }
}

/// Appends `v` as a component of type `c`: floats as they are, integers rounded (Draco keeps
/// integer attributes as their stored integers, normalized or not); `None` if it does not fit.
fn push(out: &mut Vec<u8>, c: ComponentType, v: f32) -> Option<()> {
    let int = |lo: f32, hi: f32| {
        let r = v.round();
        (r.is_finite() && r >= lo && r <= hi).then_some(r)
    };
    match c {
        ComponentType::F32 => out.extend_from_slice(&v.to_le_bytes()),
        ComponentType::U8 => out.push(int(0.0, 255.0)? as u8),
        ComponentType::I8 => out.push(int(-128.0, 127.0)? as i8 as u8),
        ComponentType::U16 => out.extend_from_slice(&(int(0.0, 65535.0)? as u16).to_le_bytes()),
        ComponentType::I16 => {
            out.extend_from_slice(&(int(-32768.0, 32767.0)? as i16).to_le_bytes());
        }
        ComponentType::U32 => {
            out.extend_from_slice(&(int(0.0, u32::MAX as f32)? as u32).to_le_bytes())
        }
    }
    Some(())
}

impl Doc<'_> {
    /// If primitive `p` of mesh `m` is Draco-compressed, decodes it and fills
    /// [`Doc::draco_accessors`] with its attributes' and indices' accessors; returns whether
    /// it did. The caller clears the map once the primitive is read.
    pub(super) fn draco_prepare(
        &self,
        prim: &Primitive,
        m: usize,
        p: usize,
    ) -> Result<bool, LoadError> {
        let ext = prim
            .extensions
            .as_ref()
            .and_then(|e| e.others.get(EXTENSION));
        let Some(ext) = ext else {
            return Ok(false);
        };
        let err = |reason: String| {
            LoadError::from(GltfError::Primitive {
                path: self.path.to_owned(),
                mesh: m,
                primitive: p,
                reason: format!("{EXTENSION}: {reason}"),
            })
        };
        if !matches!(prim.mode, Checked::Valid(Mode::Triangles)) {
            return Err(err("only TRIANGLES primitives are supported".into()));
        }
        let view = ext
            .get("bufferView")
            .and_then(Value::as_u64)
            .ok_or_else(|| err("bufferView is missing or not an index".into()))?;
        let ids = ext
            .get("attributes")
            .and_then(Value::as_object)
            .ok_or_else(|| err("attributes is missing or not an object".into()))?;
        let from = format!("mesh {m} primitive {p} ({EXTENSION})");
        let (bytes, _) = self.view(usize::try_from(view).unwrap_or(usize::MAX), &from)?;
        let mesh = decode(bytes, self.budget.remaining()).map_err(err)?;
        let points = mesh.num_points();
        let mut packed = std::collections::HashMap::new();
        for (key, accessor) in &prim.attributes {
            let Checked::Valid(semantic) = key else {
                continue;
            };
            let name = serde_json::to_value(semantic)
                .ok()
                .and_then(|v| v.as_str().map(str::to_owned))
                .unwrap_or_default();
            let Some(id) = ids.get(&name) else {
                continue;
            };
            let id = id
                .as_u64()
                .and_then(|i| u32::try_from(i).ok())
                .ok_or_else(|| err(format!("attribute id of {name} is not an integer")))?;
            let attribute = mesh
                .attribute_by_unique_id(id)
                .ok_or_else(|| err(format!("{name}: the stream has no attribute {id}")))?;
            let a = accessor.value();
            let (component, components, count) = self
                .accessor_shape(a)
                .map_err(|e| err(format!("{name}: {e}")))?;
            if count != points as u64 {
                return Err(err(format!(
                    "{name}: accessor {a} has count {count}, the decoded mesh {points} points"
                )));
            }
            let size = points * components * component_size(component);
            self.budget.charge(size as u64 * 2, || {
                format!("{from} {name} ({points} points)")
            })?;
            let values = attribute.read_f32s(points, components);
            let mut out = Vec::with_capacity(size);
            for &v in &values {
                push(&mut out, component, v).ok_or_else(|| {
                    err(format!(
                        "{name}: decoded value {v} does not fit {component:?}"
                    ))
                })?;
            }
            packed.insert(a, Packed(out));
        }
        if let Some(indices) = prim.indices {
            let a = indices.value();
            let (component, components, count) = self
                .accessor_shape(a)
                .map_err(|e| err(format!("indices: {e}")))?;
            let faces = mesh.faces();
            let corners = faces.len() as u64 * 3;
            if components != 1 || count != corners {
                return Err(err(format!(
                    "indices accessor {a} has count {count}, the decoded mesh {} triangles",
                    faces.len()
                )));
            }
            let size = corners as usize * component_size(component);
            self.budget
                .charge(size as u64, || format!("{from} indices ({corners})"))?;
            let mut out = Vec::with_capacity(size);
            for &v in faces.iter().flatten() {
                let ok = match component {
                    ComponentType::U8 => u8::try_from(v.0).map(|x| out.push(x)).is_ok(),
                    ComponentType::U16 => u16::try_from(v.0)
                        .map(|x| out.extend_from_slice(&x.to_le_bytes()))
                        .is_ok(),
                    ComponentType::U32 => {
                        out.extend_from_slice(&v.0.to_le_bytes());
                        true
                    }
                    _ => false,
                };
                if !ok {
                    return Err(err(format!("index {} does not fit {component:?}", v.0)));
                }
            }
            packed.insert(a, Packed(out));
        } else {
            return Err(err("the primitive has no indices accessor".into()));
        }
        *self.draco_accessors.borrow_mut() = packed;
        Ok(true)
    }

    /// Component type, component count and count of accessor `a`.
    fn accessor_shape(&self, a: usize) -> Result<(ComponentType, usize, u64), String> {
        let acc = self
            .json
            .accessors
            .get(a)
            .ok_or_else(|| format!("accessor {a} does not exist"))?;
        let Checked::Valid(GenericComponentType(component)) = acc.component_type else {
            return Err(format!("accessor {a} has an invalid componentType"));
        };
        let components = match acc.type_ {
            Checked::Valid(Type::Scalar) => 1,
            Checked::Valid(Type::Vec2) => 2,
            Checked::Valid(Type::Vec3) => 3,
            Checked::Valid(Type::Vec4) => 4,
            _ => return Err(format!("accessor {a} is not SCALAR or VEC2..4")),
        };
        Ok((component, components, acc.count.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn garbage_is_an_error() {
        assert!(decode(b"", 1 << 20).is_err());
        assert!(decode(b"DRACO\x02\x02\x01\x01\x00\x00\xff\xff\xff\xff", 1 << 20).is_err());
        assert!(decode(&[0u8; 64], 1 << 20).is_err());
    }

    #[test]
    fn values_pack_into_the_accessor_type() {
        let mut out = Vec::new();
        push(&mut out, ComponentType::U16, 65535.0).unwrap();
        push(&mut out, ComponentType::I8, -3.2).unwrap();
        push(&mut out, ComponentType::F32, 0.5).unwrap();
        assert_eq!(out, [255, 255, 253, 0, 0, 0, 63]);
        assert!(push(&mut out, ComponentType::U8, 256.0).is_none());
        assert!(push(&mut out, ComponentType::U8, f32::NAN).is_none());
    }
}
