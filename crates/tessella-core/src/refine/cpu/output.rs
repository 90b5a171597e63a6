//! Where refined vertices are written: memory the caller owns, as separate arrays or as one
//! interleaved vertex buffer with a stride (what engines upload). OpenSubdiv's
//! `BufferDescriptor` (offset, length, stride) is the same idea.

use super::nontemporal;
use crate::error::RefineError;
use crate::stencil::BLOCK_LANES as LANES;

/// The layout of one interleaved vertex, in `f32`s: `stride` floats per vertex, the position
/// (3 floats) at `position`, the normal (3 floats) at `normal`, texture coordinates (2 floats)
/// at `uv`. Attributes left `None` are not written, and neither are the floats no attribute
/// covers (an engine's own attributes can live there).
///
/// ```
/// use tessella_core::refine::VertexFormat;
/// // position, normal, uv: 8 floats (32 bytes) per vertex
/// let f = VertexFormat { stride: 8, position: 0, normal: Some(3), uv: Some(6) };
/// assert!(f.validate().is_ok());
/// assert!(VertexFormat { stride: 5, ..f }.validate().is_err());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VertexFormat {
    pub stride: usize,
    pub position: usize,
    pub normal: Option<usize>,
    pub uv: Option<usize>,
}

impl VertexFormat {
    /// Positions and normals, 6 floats per vertex.
    pub const POSITION_NORMAL: VertexFormat = VertexFormat {
        stride: 6,
        position: 0,
        normal: Some(3),
        uv: None,
    };
    /// Positions, normals and texture coordinates, 8 floats per vertex.
    pub const POSITION_NORMAL_UV: VertexFormat = VertexFormat {
        stride: 8,
        position: 0,
        normal: Some(3),
        uv: Some(6),
    };

    /// Checks that every attribute fits in the stride and that no two overlap.
    pub fn validate(&self) -> Result<(), RefineError> {
        let mut spans: Vec<(&str, usize, usize)> = vec![("position", self.position, 3)];
        spans.extend(self.normal.map(|o| ("normal", o, 3)));
        spans.extend(self.uv.map(|o| ("uv", o, 2)));
        for &(name, offset, width) in &spans {
            if offset + width > self.stride {
                return Err(RefineError::BadVertexFormat(format!(
                    "the {name} at float {offset} needs {width} floats, past the stride of {}",
                    self.stride
                )));
            }
        }
        for (i, a) in spans.iter().enumerate() {
            for b in &spans[i + 1..] {
                if a.1 < b.1 + b.2 && b.1 < a.1 + a.2 {
                    return Err(RefineError::BadVertexFormat(format!(
                        "the {} (floats {}..{}) and the {} (floats {}..{}) overlap",
                        a.0,
                        a.1,
                        a.1 + a.2,
                        b.0,
                        b.1,
                        b.1 + b.2
                    )));
                }
            }
        }
        Ok(())
    }
}

/// Caller-owned memory for one frame's refined vertices (see [`crate::refine::Plan`] for the
/// order). Slices must hold at least the plan's vertex count (interleaved: that many strides);
/// anything past it is left alone.
#[derive(Debug)]
#[non_exhaustive]
pub enum VertexOutput<'a> {
    /// One array per attribute; `None` attributes are not computed.
    Separate {
        positions: &'a mut [[f32; 3]],
        normals: Option<&'a mut [[f32; 3]]>,
        uvs: Option<&'a mut [[f32; 2]]>,
    },
    /// One interleaved buffer (for bytes, `bytemuck::cast_slice_mut` gives the `f32`s).
    Interleaved {
        data: &'a mut [f32],
        format: VertexFormat,
    },
}

impl<'a> VertexOutput<'a> {
    /// Checks sizes and the format, and turns the output into a sink of exactly `vertices`
    /// slots. `has_uvs`: whether the mesh has texture coordinates to write.
    pub(crate) fn sink(self, vertices: usize, has_uvs: bool) -> Result<Sink<'a>, RefineError> {
        let short = |what: &str, got: usize, need: usize| {
            Err(RefineError::OutputTooSmall {
                what: what.to_string(),
                got,
                need,
            })
        };
        let wants_uvs = match &self {
            VertexOutput::Separate { uvs, .. } => uvs.is_some(),
            VertexOutput::Interleaved { format, .. } => format.uv.is_some(),
        };
        if wants_uvs && !has_uvs {
            return Err(RefineError::NoUvs);
        }
        match self {
            VertexOutput::Separate {
                positions,
                normals,
                uvs,
            } => {
                if positions.len() < vertices {
                    return short("positions", positions.len(), vertices);
                }
                if let Some(n) = &normals {
                    if n.len() < vertices {
                        return short("normals", n.len(), vertices);
                    }
                }
                if let Some(u) = &uvs {
                    if u.len() < vertices {
                        return short("uvs", u.len(), vertices);
                    }
                }
                let arrays = 1 + usize::from(normals.is_some());
                let bytes = vertices.saturating_mul(arrays * std::mem::size_of::<[f32; 3]>());
                Ok(Sink::Separate {
                    positions: &mut positions[..vertices],
                    normals: normals.map(|n| &mut n[..vertices]),
                    uvs: uvs.map(|u| &mut u[..vertices]),
                    stream: (bytes > nontemporal::STREAM_ABOVE_BYTES).then(Streams::new),
                })
            }
            VertexOutput::Interleaved { data, format } => {
                format.validate()?;
                let need = vertices.saturating_mul(format.stride);
                if data.len() < need {
                    return short("the interleaved buffer (floats)", data.len(), need);
                }
                Ok(Sink::Interleaved {
                    data: &mut data[..need],
                    format,
                })
            }
        }
    }
}

/// A run of output slots the evaluator writes into; split into disjoint runs for threads.
#[derive(Debug)]
pub(crate) enum Sink<'a> {
    Separate {
        positions: &'a mut [[f32; 3]],
        normals: Option<&'a mut [[f32; 3]]>,
        uvs: Option<&'a mut [[f32; 2]]>,
        /// Present when tiles go out with streaming stores ([`nontemporal`]): the whole
        /// output is larger than the last-level cache. The sink writes what it holds back when
        /// it is dropped.
        stream: Option<Streams>,
    },
    Interleaved {
        data: &'a mut [f32],
        format: VertexFormat,
    },
}

/// The lines a streaming [`Sink`] holds back, one per streamed array.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Streams {
    positions: nontemporal::LineCarry,
    normals: nontemporal::LineCarry,
    /// Lines were streamed since the last [`nontemporal::fence`]: a plain store to a slot
    /// must wait for them (streaming stores may pass later plain ones).
    unfenced: bool,
}

impl Streams {
    fn new() -> Streams {
        Streams {
            positions: nontemporal::LineCarry::new(),
            normals: nontemporal::LineCarry::new(),
            unfenced: false,
        }
    }

    /// Makes a plain store to `array` safe: writes its held-back line, and orders the
    /// streamed lines before the store.
    fn before_plain_store(
        carry: &mut nontemporal::LineCarry,
        unfenced: &mut bool,
        array: &mut [f32],
    ) {
        carry.flush(array);
        if std::mem::take(unfenced) {
            nontemporal::fence();
        }
    }
    fn is_empty(&self) -> bool {
        self.positions.is_empty() && self.normals.is_empty()
    }
}

impl Drop for Sink<'_> {
    /// Writes the lines held back and orders the streamed stores before the sink's slots are
    /// read by anyone (the thread that joins this task, or the caller).
    fn drop(&mut self) {
        if let Sink::Separate {
            positions,
            normals,
            stream: Some(streams),
            ..
        } = self
        {
            streams.positions.flush(positions.as_flattened_mut());
            if let Some(normals) = normals {
                streams.normals.flush(normals.as_flattened_mut());
            }
            // Only after streaming stores: the shells `split_at` empties streamed nothing.
            if streams.unfenced {
                nontemporal::fence();
            }
        }
    }
}

impl<'a> Sink<'a> {
    /// Number of vertex slots.
    pub fn len(&self) -> usize {
        match self {
            Sink::Separate { positions, .. } => positions.len(),
            Sink::Interleaved { data, format } => data.len() / format.stride,
        }
    }
    pub fn wants_normals(&self) -> bool {
        match self {
            Sink::Separate { normals, .. } => normals.is_some(),
            Sink::Interleaved { format, .. } => format.normal.is_some(),
        }
    }
    pub fn wants_uvs(&self) -> bool {
        match self {
            Sink::Separate { uvs, .. } => uvs.is_some(),
            Sink::Interleaved { format, .. } => format.uv.is_some(),
        }
    }

    /// Slots `..mid` and `mid..`. Only before anything was written (a sink holds back
    /// nothing then).
    pub fn split_at(mut self, mid: usize) -> (Sink<'a>, Sink<'a>) {
        match &mut self {
            Sink::Separate {
                positions,
                normals,
                uvs,
                stream,
            } => {
                assert!(
                    stream.as_ref().is_none_or(Streams::is_empty),
                    "split before writing"
                );
                let streaming = stream.is_some();
                let (p0, p1) = std::mem::take(positions).split_at_mut(mid);
                let (n0, n1) = split_option(normals.take(), mid);
                let (u0, u1) = split_option(uvs.take(), mid);
                let stream = || streaming.then(Streams::new);
                (
                    Sink::Separate {
                        positions: p0,
                        normals: n0,
                        uvs: u0,
                        stream: stream(),
                    },
                    Sink::Separate {
                        positions: p1,
                        normals: n1,
                        uvs: u1,
                        stream: stream(),
                    },
                )
            }
            Sink::Interleaved { data, format } => {
                let format = *format;
                let (d0, d1) = std::mem::take(data).split_at_mut(mid * format.stride);
                (
                    Sink::Interleaved { data: d0, format },
                    Sink::Interleaved { data: d1, format },
                )
            }
        }
    }

    /// Whether [`Sink::put_tile`] writes with streaming stores.
    #[cfg(test)]
    pub fn streams(&self) -> bool {
        matches!(
            self,
            Sink::Separate {
                stream: Some(_),
                ..
            }
        )
    }

    /// The same slots, streamed or not whatever their size (tests of both paths on small data).
    #[cfg(test)]
    pub fn streaming(mut self, on: bool) -> Self {
        if let Sink::Separate { stream, .. } = &mut self {
            assert!(stream.as_ref().is_none_or(Streams::is_empty));
            *stream = on.then(Streams::new);
        }
        self
    }

    /// Consecutive runs of `size` slots (the last may be shorter), for parallel work.
    pub fn chunks(self, size: usize) -> Vec<Sink<'a>> {
        let size = size.max(1);
        let mut out = Vec::with_capacity(self.len().div_ceil(size));
        let mut rest = self;
        while rest.len() > size {
            let (head, tail) = rest.split_at(size);
            out.push(head);
            rest = tail;
        }
        if rest.len() > 0 {
            out.push(rest);
        }
        out
    }

    /// Writes `n` points given as component arrays (`pos[c][from + i]`, and normals likewise)
    /// to slots `first + i`, or `first - i` when `reverse`. One match for the whole run, then a
    /// plain loop: the per-point attribute writes of [`Sink::set_position`] cost more than the
    /// arithmetic once the sums are vectorised. A streaming sink interleaves into `stage` (in
    /// L1) and streams that out.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn put_tile<const T: usize>(
        &mut self,
        first: usize,
        reverse: bool,
        n: usize,
        from: usize,
        pos: &[[f32; T]; 3],
        normals: Option<&[[f32; T]; 3]>,
        stage: &mut [[f32; 3]; T],
    ) {
        let n = n.min(T - from);
        let at = |a: &[[f32; T]; 3], i: usize| [a[0][from + i], a[1][from + i], a[2][from + i]];
        // The slots as one ascending range, and where point i goes within it.
        let lo = if reverse { first + 1 - n } else { first };
        let index = |i: usize| if reverse { n - 1 - i } else { i };
        match self {
            Sink::Separate {
                positions,
                normals: out_normals,
                stream: None,
                ..
            } => {
                interleave(&mut positions[lo..lo + n], pos, from, reverse);
                if let (Some(out), Some(nrm)) = (out_normals, normals) {
                    interleave(&mut out[lo..lo + n], nrm, from, reverse);
                }
            }
            Sink::Separate {
                positions,
                normals: out_normals,
                stream: Some(streams),
                ..
            } => {
                // Whole vectors into the stage (the tile is padded to them), so no scalar
                // remainder; reversed, the run's points are the stage's last `n`.
                let m = n.next_multiple_of(LANES).min(T - from);
                let points = if reverse { m - n..m } else { 0..n };
                streams.unfenced = true;
                interleave(&mut stage[..m], pos, from, reverse);
                let flat = stage[points.clone()].as_flattened();
                streams
                    .positions
                    .write(positions.as_flattened_mut(), 3 * lo, flat);
                if let (Some(out), Some(nrm)) = (out_normals, normals) {
                    interleave(&mut stage[..m], nrm, from, reverse);
                    let flat = stage[points].as_flattened();
                    streams.normals.write(out.as_flattened_mut(), 3 * lo, flat);
                }
            }
            Sink::Interleaved { data, format } => {
                let stride = format.stride;
                let data = &mut data[lo * stride..(lo + n) * stride];
                for i in 0..n {
                    let v = &mut data[index(i) * stride..][..stride];
                    v[format.position..format.position + 3].copy_from_slice(&at(pos, i));
                    if let (Some(offset), Some(nrm)) = (format.normal, normals) {
                        v[offset..offset + 3].copy_from_slice(&at(nrm, i));
                    }
                }
            }
        }
    }

    #[inline(always)]
    pub fn set_position(&mut self, i: usize, p: [f32; 3]) {
        match self {
            Sink::Separate {
                positions, stream, ..
            } => {
                if let Some(st) = stream {
                    let array = positions.as_flattened_mut();
                    Streams::before_plain_store(&mut st.positions, &mut st.unfenced, array);
                }
                positions[i] = p;
            }
            Sink::Interleaved { data, format } => {
                let at = i * format.stride + format.position;
                data[at..at + 3].copy_from_slice(&p);
            }
        }
    }
    #[inline(always)]
    pub fn set_normal(&mut self, i: usize, n: [f32; 3]) {
        match self {
            Sink::Separate {
                normals: Some(normals),
                stream,
                ..
            } => {
                if let Some(st) = stream {
                    let array = normals.as_flattened_mut();
                    Streams::before_plain_store(&mut st.normals, &mut st.unfenced, array);
                }
                normals[i] = n;
            }
            Sink::Interleaved {
                data,
                format:
                    VertexFormat {
                        stride,
                        normal: Some(offset),
                        ..
                    },
            } => {
                let at = i * *stride + *offset;
                data[at..at + 3].copy_from_slice(&n);
            }
            _ => {}
        }
    }
    #[inline(always)]
    pub fn set_uv(&mut self, i: usize, uv: [f32; 2]) {
        match self {
            Sink::Separate { uvs: Some(uvs), .. } => uvs[i] = uv,
            Sink::Interleaved {
                data,
                format:
                    VertexFormat {
                        stride,
                        uv: Some(offset),
                        ..
                    },
            } => {
                let at = i * *stride + *offset;
                data[at..at + 2].copy_from_slice(&uv);
            }
            _ => {}
        }
    }
}

/// Writes component arrays `a[c][from + i]` as the points `out[i]` (`out[len - 1 - i]` when
/// `reverse`). A loop per direction with plain indices, so the compiler turns it into vector
/// shuffles and stores (one loop with a computed index stays scalar: 16 instructions a point).
#[inline(always)]
fn interleave<const T: usize>(out: &mut [[f32; 3]], a: &[[f32; T]; 3], from: usize, reverse: bool) {
    let n = out.len().min(T - from);
    let out = &mut out[..n];
    let (x, y, z) = (
        &a[0][from..from + n],
        &a[1][from..from + n],
        &a[2][from..from + n],
    );
    if reverse {
        for i in 0..n {
            out[n - 1 - i] = [x[i], y[i], z[i]];
        }
    } else {
        for i in 0..n {
            out[i] = [x[i], y[i], z[i]];
        }
    }
}

fn split_option<T>(s: Option<&mut [T]>, mid: usize) -> (Option<&mut [T]>, Option<&mut [T]>) {
    match s {
        Some(s) => {
            let (a, b) = s.split_at_mut(mid);
            (Some(a), Some(b))
        }
        None => (None, None),
    }
}
