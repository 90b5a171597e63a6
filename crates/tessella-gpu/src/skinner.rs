//! [`GpuSkinner`]: an animated mesh's coarse vertices posed on the GPU from the frame's deform
//! matrices and morph weights, so a frame uploads those alone (`shaders/skin.wgsl`).

use crate::coarse::{CoarseInput, CoarseStream};
use crate::context::{GpuContext, READ, UNIFORM, WRITE};
use crate::error::GpuError;
use crate::gpu_types::SkinParams;
use tessella_core::animation::Poser;

/// Threads per workgroup of `cs_skin`.
const WORKGROUP: u64 = 64;

/// Bytes per skinned vertex in the output buffer: position xyz, 0, normal xyz, 0.
pub const SKINNED_VERTEX_BYTES: u32 = 32;

/// Storage buffers `cs_skin` binds in the compute stage.
const STORAGE_BUFFERS: u32 = 4;

/// The compiled skinning kernel, shared through the context's cache.
#[derive(Clone)]
struct SkinPipeline {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

/// An animated mesh skinned and morphed on the GPU: the rest positions and normals, the
/// per-vertex influences ([`tessella_core::animation::DeformTable`]) and the morph deltas are
/// uploaded once by [`GpuSkinner::new`]; a frame uploads only the deform matrices and morph
/// weights ([`GpuSkinner::update`]: 64 bytes a matrix, 4 a weight) and [`GpuSkinner::record`]
/// dispatches one thread per vertex, which writes the vertex's posed position and normal into
/// the skinner's own buffer ([`GpuSkinner::output`], a [`CoarseInput`]), as
/// [`Poser::pose_into`] computes them.
///
/// Output layout: [`SKINNED_VERTEX_BYTES`] per vertex, position `x y z` at byte 0, normal
/// `x y z` at byte 16 (unit length), the padding words zero. The buffer's usage is
/// `STORAGE | VERTEX | COPY_SRC`: a vertex buffer, a [`CoarseInput`], or read back.
///
/// ```no_run
/// use tessella_core::animation::Poser;
/// use tessella_gpu::{AdapterChoice, GpuContext, GpuSkinner};
///
/// let ctx = GpuContext::new(AdapterChoice::Auto)?;
/// let poser = Poser::new(tessella_core::samples::animated_creature(1))?;
/// let mut skinner = GpuSkinner::new(&ctx, &poser)?;
/// let bytes = skinner.update(&poser, Some(0), 0.5)?; // the matrices and weights alone
/// assert_eq!(bytes, 64 * poser.deform_matrix_count() as u64 + 4 * poser.morph_weight_count() as u64);
/// let mut encoder = ctx.device.create_command_encoder(&Default::default());
/// skinner.record(&mut encoder)?;
/// ctx.submit(encoder)?;
/// let coarse = skinner.output(); // positions and normals for GPU-built nets
/// # let _ = coarse;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct GpuSkinner {
    ctx: GpuContext,
    vertex_count: usize,
    matrix_count: usize,
    weight_count: usize,
    /// Threads per row and rows of the dispatch, in workgroups.
    groups: (u32, u32),
    frame: wgpu::Buffer,
    output: wgpu::Buffer,
    group: wgpu::BindGroup,
    pipeline: wgpu::ComputePipeline,
    matrices: Vec<[f32; 16]>,
    weights: Vec<f32>,
    _buffers: [wgpu::Buffer; 3],
}

impl std::fmt::Debug for GpuSkinner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GpuSkinner")
            .field("vertices", &self.vertex_count)
            .field("matrices", &self.matrix_count)
            .field("weights", &self.weight_count)
            .finish()
    }
}

impl GpuSkinner {
    /// Uploads `poser`'s rest positions and normals, its per-vertex influences and morph
    /// deltas, and sizes the frame's matrices and weights. Refused: a model without normals
    /// ([`Poser::has_normals`]; pose it on the CPU, where `tessella_core::Mesh` computes
    /// them), one whose buffers exceed the device's binding limits
    /// ([`GpuError::TooLarge`]), a device with too few storage buffers.
    pub fn new(ctx: &GpuContext, poser: &Poser) -> Result<GpuSkinner, GpuError> {
        if !poser.has_normals() {
            return Err(GpuError::SkinNeedsNormals);
        }
        ctx.check_storage_buffers("GPU skinning", "compute", STORAGE_BUFFERS)?;
        let table = poser.deform_table();
        let model = poser.model();
        let n = poser.vertex_count();
        let limit = ctx.max_binding();
        let check = |what: &'static str, bytes: u64| {
            if bytes > limit {
                Err(GpuError::TooLarge { what, bytes, limit })
            } else {
                Ok(())
            }
        };
        let deltas = table.position_deltas.len() as u64;
        let rest_floats = 6 * n as u64 + 6 * deltas;
        let table_words = 2 * (n * table.slots) as u64 + 3 * n as u64;
        let frame_floats = 16 * table.matrix_count as u64 + table.weight_count as u64;
        check(
            "the skinning's rest vertices and morph deltas",
            4 * rest_floats,
        )?;
        check("the skinning's influence table", 4 * table_words)?;
        check("the skinning's matrices and weights", 4 * frame_floats)?;
        check(
            "the skinned vertices",
            u64::from(SKINNED_VERTEX_BYTES) * n as u64,
        )?;
        // Every index the shader computes is a u32 word index below these.
        if [rest_floats, table_words, frame_floats, 8 * n as u64]
            .iter()
            .any(|&words| words > u64::from(u32::MAX))
        {
            return Err(GpuError::TooLarge {
                what: "the skinning's buffers",
                bytes: 4 * rest_floats.max(table_words).max(frame_floats),
                limit: 4 * u64::from(u32::MAX),
            });
        }

        let mut rest: Vec<f32> = Vec::with_capacity(rest_floats as usize);
        for instance in &model.instances {
            let normals = instance.normals.as_deref().unwrap_or(&[]);
            for (p, nrm) in instance.positions.iter().zip(normals) {
                rest.extend(p);
                rest.extend(nrm);
            }
        }
        let deltas_at = rest.len() as u32;
        rest.extend(table.position_deltas.iter().flatten());
        let normal_deltas_at = rest.len() as u32;
        rest.extend(table.normal_deltas.iter().flatten());
        let (matrix_count, weight_count) = (table.matrix_count, table.weight_count);
        let mut words: Vec<u32> = Vec::with_capacity(table_words as usize);
        for (&m, &w) in table.matrices.iter().zip(&table.weights) {
            words.push(m);
            words.push(w.to_bits());
        }
        let morphs_at = words.len() as u32;
        words.extend(table.morphs.iter().flatten());

        let groups = (n as u64).div_ceil(WORKGROUP);
        let max = u64::from(ctx.limits.max_compute_workgroups_per_dimension).max(1);
        let (x, y) = (groups.min(max), groups.div_ceil(max));
        if y > max {
            return Err(GpuError::TooLarge {
                what: "the skinned vertices' dispatch",
                bytes: u64::from(SKINNED_VERTEX_BYTES) * n as u64,
                limit: u64::from(SKINNED_VERTEX_BYTES) * max * max * WORKGROUP,
            });
        }
        ctx.scoped(|| -> Result<GpuSkinner, GpuError> {
            let SkinPipeline { pipeline, layout } = ctx.pipelines("skin", || compile(ctx))?;
            let output = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("skinned vertices"),
                size: (u64::from(SKINNED_VERTEX_BYTES) * n as u64).max(4),
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::VERTEX
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            // The shader writes the streams `output()` hands on, as their readers read them.
            let streams = coarse_input(&output);
            let align = ctx.limits.min_storage_buffer_offset_alignment;
            streams.positions.check("the skinned positions", n, align)?;
            streams.normals.check("the skinned normals", n, align)?;
            let [stride, position_first] = streams.positions.words();
            let [_, normal_first] = streams.normals.words();
            let params = SkinParams {
                vertex_count: n as u32,
                slots: table.slots as u32,
                weights_at: 16 * table.matrix_count as u32,
                morphs_at,
                deltas_at,
                normal_deltas_at,
                row: (x * WORKGROUP) as u32,
                out_stride: stride,
                position_first,
                normal_first,
                _pad: [0; 2],
            };
            let none = wgpu::BufferUsages::empty();
            let params = ctx.buffer_init(
                "skin params",
                bytemuck::bytes_of(&params),
                wgpu::BufferUsages::UNIFORM,
            );
            let rest = ctx.storage_buffer("skin rest", bytemuck::cast_slice(&rest), none);
            let words = ctx.storage_buffer("skin table", bytemuck::cast_slice(&words), none);
            let frame = ctx.storage_buffer(
                "skin frame",
                &vec![0u8; 4 * frame_floats as usize],
                wgpu::BufferUsages::COPY_DST,
            );
            let group =
                ctx.buffer_group("skin", &layout, &[&params, &rest, &words, &frame, &output]);
            Ok(GpuSkinner {
                ctx: ctx.clone(),
                vertex_count: n,
                matrix_count,
                weight_count,
                groups: (x as u32, y as u32),
                frame,
                output,
                group,
                pipeline,
                matrices: Vec::new(),
                weights: Vec::new(),
                _buffers: [params, rest, words],
            })
        })?
    }

    /// Computes the deform matrices and morph weights of `time` seconds of `clip` (`None`:
    /// the rest pose) on the CPU ([`Poser::deform_into`], no per-vertex work) and writes them
    /// (`queue.write_buffer`: they land before the next submission). Returns the bytes
    /// written: 64 per deform matrix (every skin's joints, one per unskinned instance), 4 per
    /// morph weight. `poser` is the one the skinner was made from (a poser of another
    /// shape is refused).
    pub fn update(
        &mut self,
        poser: &Poser,
        clip: Option<usize>,
        time: f32,
    ) -> Result<u64, GpuError> {
        if poser.vertex_count() != self.vertex_count || table_counts(poser) != self.counts() {
            return Err(GpuError::BadOption(format!(
                "this GPU skinner was made for {} vertices, {} deform matrices and {} morph \
                 weights; the poser has {}, {} and {}",
                self.vertex_count,
                self.matrix_count,
                self.weight_count,
                poser.vertex_count(),
                poser.deform_matrix_count(),
                poser.morph_weight_count()
            )));
        }
        let (mut matrices, mut weights) = (
            std::mem::take(&mut self.matrices),
            std::mem::take(&mut self.weights),
        );
        let result = poser
            .deform_into(clip, time, &mut matrices, &mut weights)
            .map_err(GpuError::from)
            .and_then(|()| self.update_matrices(&matrices, &weights));
        (self.matrices, self.weights) = (matrices, weights);
        result
    }

    /// Writes a frame's deform matrices (column-major, in [`Poser::deform_into`]'s order)
    /// and morph weights computed elsewhere (an engine's own animation system); returns the
    /// bytes written. Refused when the counts are not the model's.
    pub fn update_matrices(
        &self,
        matrices: &[[f32; 16]],
        weights: &[f32],
    ) -> Result<u64, GpuError> {
        if (matrices.len(), weights.len()) != self.counts() {
            return Err(GpuError::BadOption(format!(
                "GPU skinning takes {} deform matrices and {} morph weights a frame; got {} and {}",
                self.matrix_count,
                self.weight_count,
                matrices.len(),
                weights.len()
            )));
        }
        let matrix_bytes: &[u8] = bytemuck::cast_slice(matrices);
        let weight_bytes: &[u8] = bytemuck::cast_slice(weights);
        self.ctx.scoped(|| {
            let queue = &self.ctx.queue;
            if !matrix_bytes.is_empty() {
                queue.write_buffer(&self.frame, 0, matrix_bytes);
            }
            if !weight_bytes.is_empty() {
                queue.write_buffer(&self.frame, matrix_bytes.len() as u64, weight_bytes);
            }
        })?;
        Ok((matrix_bytes.len() + weight_bytes.len()) as u64)
    }

    /// Records into `encoder` the compute pass that skins every vertex into the output
    /// buffer, from the matrices and weights last written.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), GpuError> {
        if self.vertex_count == 0 {
            return Ok(());
        }
        self.ctx.scoped(|| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("tessella skin"),
                timestamp_writes: None,
            });
            self.dispatch(&mut pass);
        })
    }

    /// Records the skinning into a compute pass the caller began: many skinners in one pass
    /// (a crowd) cost one pass, where a pass each costs a software rasterizer a
    /// synchronisation each. Whatever reads [`GpuSkinner::output`] goes in a later pass.
    pub fn dispatch(&self, pass: &mut wgpu::ComputePass<'_>) {
        if self.vertex_count == 0 {
            return;
        }
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(self.groups.0, self.groups.1, 1);
    }

    /// The skinned positions (byte 0) and normals (byte 16) in the output buffer, stride
    /// [`SKINNED_VERTEX_BYTES`]: the coarse input of GPU-built control nets.
    pub fn output(&self) -> CoarseInput<'_> {
        coarse_input(&self.output)
    }

    /// The output buffer ([`SKINNED_VERTEX_BYTES`] per vertex).
    pub fn output_buffer(&self) -> &wgpu::Buffer {
        &self.output
    }

    /// The number of vertices skinned.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// The deform matrices and morph weights a frame takes.
    fn counts(&self) -> (usize, usize) {
        (self.matrix_count, self.weight_count)
    }
}

/// The output buffer's positions (byte 0) and normals (byte 16).
fn coarse_input(output: &wgpu::Buffer) -> CoarseInput<'_> {
    let stream = |first| CoarseStream {
        buffer: output,
        offset: 0,
        stride: SKINNED_VERTEX_BYTES,
        first,
    };
    CoarseInput {
        positions: stream(0),
        normals: stream(16),
    }
}

fn table_counts(poser: &Poser) -> (usize, usize) {
    (poser.deform_matrix_count(), poser.morph_weight_count())
}

/// Compiles `cs_skin` with the generated normal function.
fn compile(ctx: &GpuContext) -> SkinPipeline {
    let compute = wgpu::ShaderStages::COMPUTE;
    let layout = ctx.buffer_layout(
        "skin",
        &[
            (compute, UNIFORM),
            (compute, READ),
            (compute, READ),
            (compute, READ),
            (compute, WRITE),
        ],
    );
    let source = source();
    let module = ctx
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("skin.wgsl"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
    let pipeline_layout = ctx
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("skin"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
    let pipeline = ctx
        .device
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("cs_skin"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some("cs_skin"),
            compilation_options: Default::default(),
            cache: None,
        });
    SkinPipeline { pipeline, layout }
}

/// The skinning kernel's WGSL: the core's generated normal function, `SkinParams`, then
/// `skin.wgsl`.
pub(crate) fn source() -> String {
    [
        tessella_core::shader::skin_normal(tessella_core::shader::Lang::Wgsl),
        SkinParams::wgsl(),
        include_str!("shaders/skin.wgsl").to_string(),
    ]
    .concat()
}

#[cfg(test)]
mod tests {
    /// The skinning shader (the generated normal function and `skin.wgsl`) parses and
    /// validates.
    #[test]
    fn the_skinning_shader_validates() {
        use wgpu::naga;
        let source = super::source();
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::empty(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{e:?}"));
    }
}
