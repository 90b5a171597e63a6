//! What the native examples (`deform`, `engine`) both do as the application around tessella:
//! open a device, make single-sampled offscreen textures, draw a Lambert pipeline into them
//! and read the pictures back. Not part of tessella's API: each engine has its own.

/// The first adapter any backend offers (software included).
pub fn request_adapter() -> Result<wgpu::Adapter, Box<dyn std::error::Error>> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
        backends: wgpu::Backends::PRIMARY,
        ..wgpu::InstanceDescriptor::new_without_display_handle()
    });
    Ok(pollster::block_on(
        instance.request_adapter(&Default::default()),
    )?)
}

/// A bind group of one uniform buffer at binding 0, seen by the vertex and fragment stages:
/// the application's view.
pub fn view_group(
    device: &wgpu::Device,
    label: Option<&str>,
    uniforms: &wgpu::Buffer,
) -> (wgpu::BindGroupLayout, wgpu::BindGroup) {
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label,
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &layout,
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: uniforms.as_entire_binding(),
        }],
    });
    (layout, group)
}

/// Vertex attributes 0 (position) and 1 (normal), three floats each at these float offsets.
pub fn position_normal(position: usize, normal: usize) -> [wgpu::VertexAttribute; 2] {
    [
        wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Float32x3,
            offset: (position * 4) as u64,
            shader_location: 0,
        },
        wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Float32x3,
            offset: (normal * 4) as u64,
            shader_location: 1,
        },
    ]
}

/// The application's render pipeline: vertex entry `entry` (also the label) reading
/// `buffers`, fragment entry `fs` into `color`, back faces culled, depth tested into `depth`.
pub fn render_pipeline(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    entry: &str,
    buffers: &[Option<wgpu::VertexBufferLayout>],
    (color, depth): (wgpu::TextureFormat, wgpu::TextureFormat),
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: Some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: depth,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(color.into())],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A square single-sampled 2D texture of `size` pixels.
pub fn texture(
    device: &wgpu::Device,
    size: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: extent(size),
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

fn extent(size: u32) -> wgpu::Extent3d {
    wgpu::Extent3d {
        width: size,
        height: size,
        depth_or_array_layers: 1,
    }
}

/// Bytes of one picture row in a read-back buffer (copies pad rows to 256 bytes).
pub fn padded_row(size: u32) -> u64 {
    (size as u64 * 4).next_multiple_of(256)
}

/// Begins a single-sampled pass: colour cleared to white and kept, depth cleared to 1 and
/// discarded.
pub fn begin_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    color: &wgpu::TextureView,
    depth: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: color,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::WHITE),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: Some(tessella_gpu::cleared_depth(depth)),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Copies the square picture `color` (`size` pixels a side) into `buffer`, rows padded to
/// [`padded_row`].
pub fn copy_picture(
    encoder: &mut wgpu::CommandEncoder,
    color: &wgpu::Texture,
    buffer: &wgpu::Buffer,
    size: u32,
) {
    encoder.copy_texture_to_buffer(
        color.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded_row(size) as u32),
                rows_per_image: Some(size),
            },
        },
        extent(size),
    );
}

/// The RGBA pixels of a picture read back by [`copy_picture`], padding dropped.
pub fn unpad_rows(bytes: &[u8], size: u32) -> Vec<u8> {
    let row = padded_row(size) as usize;
    let mut pixels = Vec::with_capacity((size * size * 4) as usize);
    for y in 0..size as usize {
        let start = y * row;
        pixels.extend_from_slice(&bytes[start..start + size as usize * 4]);
    }
    pixels
}
