//! Any accessor's elements as numbers: every component type, normalised or not (glTF 2.0
//! section 3.11 "Animation"/"Meshes" and `KHR_mesh_quantization` allow integer positions,
//! normals, tangents and texture coordinates), any `byteStride`, sparse substitution on top.
//! Bounds are checked first ([`super::super::data::check_accessor`]), so no read goes past
//! the end of a buffer.

use super::super::data::check_accessor;
use gltf::accessor::{DataType, Dimensions};
use gltf::Accessor;

/// Components per element of a vector or scalar accessor; matrices are refused (only
/// inverse bind matrices are matrices, and they are copied, never read).
pub(super) fn width(dimensions: Dimensions) -> Option<usize> {
    match dimensions {
        Dimensions::Scalar => Some(1),
        Dimensions::Vec2 => Some(2),
        Dimensions::Vec3 => Some(3),
        Dimensions::Vec4 => Some(4),
        _ => None,
    }
}

const ALL_TYPES: [DataType; 6] = [
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
    DataType::U32,
    DataType::F32,
];

/// The elements of `accessor` as `f32`, `width` per element, element-major. Normalised
/// integers map to `[0, 1]` or `[-1, 1]` (the spec's `max(c / 127, -1)` rule for signed
/// ones); other integers keep their value.
pub(super) fn read_f32(accessor: &Accessor, buffers: &[Vec<u8>]) -> Result<Vec<f32>, String> {
    let normalized = accessor.normalized();
    let data_type = accessor.data_type();
    let values = read_with(accessor, buffers, |bytes| {
        component(bytes, data_type, normalized)
    })?;
    Ok(values.into_iter().map(|v| v as f32).collect())
}

/// The elements of an integer accessor (indices, joints) as `u32`; a float accessor is refused.
pub(super) fn read_u32(accessor: &Accessor, buffers: &[Vec<u8>]) -> Result<Vec<u32>, String> {
    let data_type = accessor.data_type();
    if data_type == DataType::F32 || accessor.normalized() {
        return Err(format!(
            "accessor {} holds {}{data_type:?} values; integers are needed here",
            accessor.index(),
            if accessor.normalized() {
                "normalised "
            } else {
                ""
            }
        ));
    }
    let ints = read_with(accessor, buffers, |bytes| match data_type {
        DataType::I8 => bytes[0] as i8 as i64 as f64,
        DataType::U8 => bytes[0] as f64,
        DataType::I16 => i16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        DataType::U16 => u16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        _ => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
    })?;
    ints.into_iter()
        .map(|v| {
            if v < 0.0 {
                Err(format!(
                    "accessor {} holds the negative index {v}",
                    accessor.index()
                ))
            } else {
                Ok(v as u32)
            }
        })
        .collect()
}

/// One component's value (f64: exact for every integer type).
fn component(bytes: &[u8], data_type: DataType, normalized: bool) -> f64 {
    let v = match data_type {
        DataType::I8 => bytes[0] as i8 as f64,
        DataType::U8 => bytes[0] as f64,
        DataType::I16 => i16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        DataType::U16 => u16::from_le_bytes([bytes[0], bytes[1]]) as f64,
        DataType::U32 => u32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
        DataType::F32 => f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]]) as f64,
    };
    if !normalized {
        return v;
    }
    match data_type {
        DataType::I8 => (v / 127.0).max(-1.0),
        DataType::U8 => v / 255.0,
        DataType::I16 => (v / 32767.0).max(-1.0),
        DataType::U16 => v / 65535.0,
        _ => v,
    }
}

/// Reads every component through `value` (which gets the component's bytes), the buffer view
/// first (zeros without one), then the sparse values at their indices.
fn read_with(
    accessor: &Accessor,
    buffers: &[Vec<u8>],
    value: impl Fn(&[u8]) -> f64,
) -> Result<Vec<f64>, String> {
    let Some(n) = width(accessor.dimensions()) else {
        return Err(format!(
            "accessor {} is a {:?}; a vector or scalar is needed here",
            accessor.index(),
            accessor.dimensions()
        ));
    };
    check_accessor(accessor, accessor.dimensions(), &ALL_TYPES, buffers, true)?;
    let size = accessor.data_type().size();
    let count = accessor.count();
    let mut out = vec![0.0f64; count * n];
    let read_element = |dst: &mut [f64], bytes: &[u8]| {
        for (c, d) in dst.iter_mut().enumerate() {
            *d = value(&bytes[c * size..(c + 1) * size]);
        }
    };
    if let Some(view) = accessor.view() {
        let data = &buffers[view.buffer().index()][view.offset()..view.offset() + view.length()];
        let stride = view.stride().unwrap_or(n * size);
        for (e, dst) in out.chunks_mut(n).enumerate() {
            let at = accessor.offset() + e * stride;
            read_element(dst, &data[at..at + n * size]);
        }
    }
    if let Some(sparse) = accessor.sparse() {
        let indices = sparse.indices();
        let view = indices.view();
        let data = &buffers[view.buffer().index()][view.offset()..view.offset() + view.length()];
        use gltf::accessor::sparse::IndexType;
        let isize = match indices.index_type() {
            IndexType::U8 => 1,
            IndexType::U16 => 2,
            IndexType::U32 => 4,
        };
        let values = sparse.values();
        let vview = values.view();
        let vdata =
            &buffers[vview.buffer().index()][vview.offset()..vview.offset() + vview.length()];
        for k in 0..sparse.count() {
            let at = indices.offset() + k * isize;
            let b = &data[at..at + isize];
            let target = match isize {
                1 => b[0] as usize,
                2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
            };
            if target >= count {
                return Err(format!(
                    "accessor {}'s sparse index {target} is past its {count} elements",
                    accessor.index()
                ));
            }
            let vat = values.offset() + k * n * size;
            read_element(
                &mut out[target * n..(target + 1) * n],
                &vdata[vat..vat + n * size],
            );
        }
    }
    Ok(out)
}
