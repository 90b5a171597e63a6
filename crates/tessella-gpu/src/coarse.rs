//! Coarse vertices that already live on the GPU: where a frame's positions and normals are
//! read from when the control nets are built on the GPU ([`crate::GpuNetBuilder`]), whether
//! an engine's own skinning wrote them or tessella's ([`crate::GpuSkinner`]).

use crate::error::GpuError;

/// One attribute (three `f32`, x y z) of every coarse vertex in a storage buffer: vertex `v`'s
/// `x` is at byte `offset + v * stride + first`, its `y` and `z` after it.
///
/// The buffer needs `wgpu::BufferUsages::STORAGE`; `offset` is a multiple of the device's
/// `min_storage_buffer_offset_alignment` (256 on most), `stride` and `first` of 4.
#[derive(Debug, Clone, Copy)]
pub struct CoarseStream<'a> {
    pub buffer: &'a wgpu::Buffer,
    /// Bytes before vertex 0.
    pub offset: u64,
    /// Bytes from one vertex to the next.
    pub stride: u32,
    /// Bytes from a vertex's start to this attribute's `x`.
    pub first: u32,
}

/// A frame's coarse positions and normals on the GPU, one per vertex of the mesh the nets are
/// built for, in its vertex order. The normals need not be unit length (they are normalised
/// as `tessella_core::Mesh` normalises given normals), nor zero.
#[derive(Debug, Clone, Copy)]
pub struct CoarseInput<'a> {
    pub positions: CoarseStream<'a>,
    pub normals: CoarseStream<'a>,
}

impl CoarseStream<'_> {
    /// Refuses a stream that cannot hold `vertices` vertices or breaks the alignment rules;
    /// `what` names it in the error ("the coarse positions").
    pub(crate) fn check(
        &self,
        what: &str,
        vertices: usize,
        offset_alignment: u32,
    ) -> Result<(), GpuError> {
        let bad = |why: String| Err(GpuError::BadOption(format!("{what}: {why}")));
        if !self.buffer.usage().contains(wgpu::BufferUsages::STORAGE) {
            return bad(format!(
                "the buffer's usage {:?} lacks STORAGE",
                self.buffer.usage()
            ));
        }
        if !self
            .offset
            .is_multiple_of(u64::from(offset_alignment.max(4)))
        {
            return bad(format!(
                "offset {} is not a multiple of the device's storage offset alignment {}",
                self.offset, offset_alignment
            ));
        }
        if !self.stride.is_multiple_of(4) || !self.first.is_multiple_of(4) {
            return bad(format!(
                "stride {} and first {} must be multiples of 4 bytes",
                self.stride, self.first
            ));
        }
        if u64::from(self.first) + 12 > u64::from(self.stride) {
            return bad(format!(
                "x y z at byte {} do not fit a stride of {} bytes",
                self.first, self.stride
            ));
        }
        let end = match vertices {
            0 => self.offset,
            n => self.offset + (n as u64 - 1) * u64::from(self.stride) + u64::from(self.first) + 12,
        };
        if end > self.buffer.size() {
            return bad(format!(
                "{vertices} vertices need {end} bytes, the buffer has {}",
                self.buffer.size()
            ));
        }
        Ok(())
    }

    /// The stream as the shaders read it: the stride and first `x`, in floats.
    pub(crate) fn words(&self) -> [u32; 2] {
        [self.stride / 4, self.first / 4]
    }
}
