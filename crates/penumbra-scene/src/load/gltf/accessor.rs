//! Bounds-checked accessor reading. Every range is checked *before* any byte
//! is read (the `gltf` crate's readers can panic or misread on malformed
//! data), so a bad file gives a [`SceneError`] naming the accessor, never a
//! panic.

use super::Loader;
use crate::error::SceneError;
use ::gltf::json::accessor::{ComponentType, Type};
use ::gltf::json::validation::Checked;

/// Largest number of components read for an accessor that has no
/// `bufferView` (all zeros plus sparse values): 2^26 (≈ 67 M).
const MAX_IMPLICIT_COMPONENTS: u64 = 1 << 26;

pub(super) fn type_name(t: Type) -> &'static str {
    match t {
        Type::Scalar => "SCALAR",
        Type::Vec2 => "VEC2",
        Type::Vec3 => "VEC3",
        Type::Vec4 => "VEC4",
        Type::Mat2 => "MAT2",
        Type::Mat3 => "MAT3",
        Type::Mat4 => "MAT4",
    }
}

fn component_name(c: ComponentType) -> &'static str {
    match c {
        ComponentType::I8 => "BYTE",
        ComponentType::U8 => "UNSIGNED_BYTE",
        ComponentType::I16 => "SHORT",
        ComponentType::U16 => "UNSIGNED_SHORT",
        ComponentType::U32 => "UNSIGNED_INT",
        ComponentType::F32 => "FLOAT",
    }
}

/// One component as f32, applying `normalized` integer scaling.
fn decode_f32(b: &[u8], ct: ComponentType, normalized: bool) -> f32 {
    match ct {
        ComponentType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        ComponentType::U8 => {
            let v = b[0] as f32;
            if normalized { v / 255.0 } else { v }
        }
        ComponentType::I8 => {
            let v = b[0] as i8 as f32;
            if normalized { (v / 127.0).max(-1.0) } else { v }
        }
        ComponentType::U16 => {
            let v = u16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized { v / 65535.0 } else { v }
        }
        ComponentType::I16 => {
            let v = i16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        ComponentType::U32 => {
            let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            if normalized {
                (v as f64 / u32::MAX as f64) as f32
            } else {
                v as f32
            }
        }
    }
}

/// One unsigned integer component (indices); other types are refused earlier.
fn decode_u32(b: &[u8], ct: ComponentType) -> u32 {
    match ct {
        ComponentType::U8 => b[0] as u32,
        ComponentType::U16 => u16::from_le_bytes([b[0], b[1]]) as u32,
        ComponentType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        _ => 0,
    }
}

impl Loader<'_> {
    /// The bytes of `bufferViews[v]`, checked to lie inside its buffer.
    pub(super) fn view_bytes(&self, v: usize) -> Result<&[u8], SceneError> {
        let path = format!("bufferViews[{v}]");
        let view = self.root.buffer_views.get(v).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                path.clone(),
                format!(
                    "bufferView {v} does not exist (there are {})",
                    self.root.buffer_views.len()
                ),
            )
        })?;
        let b = view.buffer.value();
        let data = self.buffers.get(b).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                format!("{path}.buffer"),
                format!("buffer {b} does not exist"),
            )
        })?;
        let declared = self.root.buffers.get(b).map_or(0, |x| x.byte_length.0);
        let offset = view.byte_offset.map_or(0, |o| o.0);
        let len = view.byte_length.0;
        let end = offset.checked_add(len);
        match end {
            Some(end) if end <= declared && end <= data.len() as u64 => {
                Ok(&data[offset as usize..end as usize])
            }
            _ => Err(SceneError::at_path(
                self.file,
                path,
                format!(
                    "byteOffset {offset} + byteLength {len} runs past the end of buffers[{b}] (byteLength {declared})"
                ),
            )),
        }
    }

    /// Reads accessor `i` (which must have type `expected`) as `count × n`
    /// components, through `decode`. `usage` is the JSON path that refers to
    /// the accessor, for messages. `check` refuses component types.
    fn read_components<T: Copy + Default>(
        &self,
        i: usize,
        usage: &str,
        expected: Type,
        check: impl Fn(ComponentType) -> Result<(), String>,
        decode: impl Fn(&[u8], ComponentType, bool) -> T,
    ) -> Result<Vec<T>, SceneError> {
        let path = format!("accessors[{i}]");
        let err = |p: &str, msg: String| {
            SceneError::at_path(self.file, p.to_string(), format!("{msg} (used by {usage})"))
        };
        let acc = self.root.accessors.get(i).ok_or_else(|| {
            SceneError::at_path(
                self.file,
                usage.to_string(),
                format!(
                    "accessor {i} does not exist (there are {})",
                    self.root.accessors.len()
                ),
            )
        })?;
        let Checked::Valid(ty) = acc.type_ else {
            return Err(err(&path, "invalid accessor type".into()));
        };
        if ty != expected {
            return Err(err(
                &format!("{path}.type"),
                format!(
                    "type is {}, expected {}",
                    type_name(ty),
                    type_name(expected)
                ),
            ));
        }
        let Checked::Valid(ct) = acc.component_type else {
            return Err(err(&path, "invalid componentType".into()));
        };
        let ct = ct.0;
        check(ct).map_err(|m| err(&format!("{path}.componentType"), m))?;
        let n = ty.multiplicity() as u64;
        let cs = ct.size() as u64;
        let elem = n * cs;
        let count = acc.count.0;
        let normalized = acc.normalized;
        let total = count
            .checked_mul(n)
            .ok_or_else(|| err(&path, format!("count {count} is too large")))?;

        let mut out: Vec<T>;
        if let Some(v) = acc.buffer_view {
            let v = v.value();
            let bytes = self.view_bytes(v)?;
            let view = &self.root.buffer_views[v];
            let stride = view.byte_stride.map_or(elem, |s| s.0 as u64);
            let offset = acc.byte_offset.map_or(0, |o| o.0);
            if count > 0 {
                let need = stride
                    .checked_mul(count - 1)
                    .and_then(|x| x.checked_add(offset))
                    .and_then(|x| x.checked_add(elem));
                match need {
                    Some(need) if need <= bytes.len() as u64 => {}
                    _ => {
                        let need = need.map_or("more than 2^64".to_string(), |n| n.to_string());
                        return Err(err(
                            &path,
                            format!(
                                "accessor runs past the end of bufferViews[{v}]: it needs {need} bytes \
                                 (byteOffset {offset} + {} × stride {stride} + {elem}-byte element) \
                                 but the view has {} bytes",
                                count - 1,
                                bytes.len()
                            ),
                        ));
                    }
                }
            } else if offset > bytes.len() as u64 {
                return Err(err(
                    &path,
                    format!(
                        "byteOffset {offset} is past the end of bufferViews[{v}] ({} bytes)",
                        bytes.len()
                    ),
                ));
            }
            // In range: all the arithmetic below fits in usize.
            let (offset, stride, cs, count, n) = (
                offset as usize,
                stride as usize,
                cs as usize,
                count as usize,
                n as usize,
            );
            out = Vec::with_capacity(count * n);
            for e in 0..count {
                let base = offset + e * stride;
                for c in 0..n {
                    let at = base + c * cs;
                    out.push(decode(&bytes[at..at + cs], ct, normalized));
                }
            }
        } else {
            if total > MAX_IMPLICIT_COMPONENTS {
                return Err(err(
                    &path,
                    format!("count {count} is too large for an accessor without a bufferView"),
                ));
            }
            out = vec![T::default(); total as usize];
        }

        if let Some(sparse) = &acc.sparse {
            let sp = format!("{path}.sparse");
            let scount = sparse.count.0;
            if scount > count {
                return Err(err(
                    &format!("{sp}.count"),
                    format!("sparse count {scount} exceeds the accessor count {count}"),
                ));
            }
            let Checked::Valid(ict) = sparse.indices.component_type else {
                return Err(err(
                    &format!("{sp}.indices.componentType"),
                    "invalid componentType".into(),
                ));
            };
            let ict = ict.0;
            if !matches!(
                ict,
                ComponentType::U8 | ComponentType::U16 | ComponentType::U32
            ) {
                return Err(err(
                    &format!("{sp}.indices.componentType"),
                    format!("{} is not an index type", component_name(ict)),
                ));
            }
            let ics = ict.size() as u64;
            let iv = sparse.indices.buffer_view.value();
            let ibytes = self.view_bytes(iv)?;
            let ioff = sparse.indices.byte_offset.0;
            let vv = sparse.values.buffer_view.value();
            let vbytes = self.view_bytes(vv)?;
            let voff = sparse.values.byte_offset.0;
            for (what, view, off, size, bytes) in [
                ("indices", iv, ioff, ics, ibytes),
                ("values", vv, voff, elem, vbytes),
            ] {
                let need = scount.checked_mul(size).and_then(|x| x.checked_add(off));
                if need.is_none_or(|need| need > bytes.len() as u64) {
                    return Err(err(
                        &format!("{sp}.{what}"),
                        format!(
                            "sparse {what} run past the end of bufferViews[{view}] ({} bytes)",
                            bytes.len()
                        ),
                    ));
                }
            }
            let (ioff, voff, ics, cs, elem, n) = (
                ioff as usize,
                voff as usize,
                ics as usize,
                cs as usize,
                elem as usize,
                n as usize,
            );
            for k in 0..scount as usize {
                let at = ioff + k * ics;
                let target = decode_u32(&ibytes[at..at + ics], ict) as u64;
                if target >= count {
                    return Err(err(
                        &format!("{sp}.indices"),
                        format!("sparse index {target} is out of range (count {count})"),
                    ));
                }
                let target = target as usize;
                for c in 0..n {
                    let at = voff + k * elem + c * cs;
                    out[target * n + c] = decode(&vbytes[at..at + cs], ct, normalized);
                }
            }
        }
        Ok(out)
    }

    /// Reads a float attribute (any component type, normalised as flagged).
    pub(super) fn read_floats(
        &self,
        i: usize,
        usage: &str,
        expected: Type,
    ) -> Result<Vec<f32>, SceneError> {
        self.read_components(i, usage, expected, |_| Ok(()), decode_f32)
    }

    /// Reads triangle indices (SCALAR, unsigned integer components).
    pub(super) fn read_indices(&self, i: usize, usage: &str) -> Result<Vec<u32>, SceneError> {
        self.read_components(
            i,
            usage,
            Type::Scalar,
            |ct| match ct {
                ComponentType::U8 | ComponentType::U16 | ComponentType::U32 => Ok(()),
                other => Err(format!(
                    "indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, found {}",
                    component_name(other)
                )),
            },
            |b, ct, _| decode_u32(b, ct),
        )
    }

    /// Vec3 and Vec2 views of [`Self::read_floats`].
    pub(super) fn read_vec3(&self, i: usize, usage: &str) -> Result<Vec<glam::Vec3>, SceneError> {
        let f = self.read_floats(i, usage, Type::Vec3)?;
        Ok(f.chunks_exact(3)
            .map(|c| glam::Vec3::new(c[0], c[1], c[2]))
            .collect())
    }

    /// COLOR_0: VEC3 or VEC4 (float or normalised unsigned), alpha dropped.
    pub(super) fn read_colors(&self, i: usize, usage: &str) -> Result<Vec<glam::Vec3>, SceneError> {
        let vec4 = self
            .root
            .accessors
            .get(i)
            .is_some_and(|a| a.type_ == Checked::Valid(Type::Vec4));
        if !vec4 {
            return self.read_vec3(i, usage);
        }
        let f = self.read_floats(i, usage, Type::Vec4)?;
        Ok(f.chunks_exact(4)
            .map(|c| glam::Vec3::new(c[0], c[1], c[2]))
            .collect())
    }

    /// VEC4 floats (glTF TANGENT: xyz and the handedness w).
    pub(super) fn read_vec4(&self, i: usize, usage: &str) -> Result<Vec<glam::Vec4>, SceneError> {
        let f = self.read_floats(i, usage, Type::Vec4)?;
        Ok(f.chunks_exact(4).map(glam::Vec4::from_slice).collect())
    }

    pub(super) fn read_vec2(&self, i: usize, usage: &str) -> Result<Vec<glam::Vec2>, SceneError> {
        let f = self.read_floats(i, usage, Type::Vec2)?;
        Ok(f.chunks_exact(2)
            .map(|c| glam::Vec2::new(c[0], c[1]))
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalised_decoding() {
        assert_eq!(decode_f32(&[255], ComponentType::U8, true), 1.0);
        assert_eq!(decode_f32(&[255], ComponentType::U8, false), 255.0);
        assert_eq!(decode_f32(&[0x80], ComponentType::I8, true), -1.0);
        assert_eq!(
            decode_f32(&0x7fffi16.to_le_bytes(), ComponentType::I16, true),
            1.0
        );
        assert_eq!(
            decode_f32(&1.5f32.to_le_bytes(), ComponentType::F32, false),
            1.5
        );
        assert_eq!(decode_u32(&[7, 1], ComponentType::U16), 263);
    }
}
