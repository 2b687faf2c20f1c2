//! A texture level copied into a mappable buffer (rows padded to
//! `COPY_BYTES_PER_ROW_ALIGNMENT`) and read back, unpadded, after the
//! frame is submitted: the colour target, the AOVs, the AO term, the
//! prefiltered environment levels.

use crate::context::{GpuContext, GpuError};

/// One level of one texture, `texel_bytes` per texel.
#[derive(Debug)]
pub struct TextureReadback {
    buffer: wgpu::Buffer,
    bytes_per_row: u32,
    texel_bytes: u32,
    width: u32,
    height: u32,
}

impl TextureReadback {
    pub fn new(device: &wgpu::Device, width: u32, height: u32, texel_bytes: u32) -> Self {
        let align = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let bytes_per_row = (width * texel_bytes).div_ceil(align) * align;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: bytes_per_row as u64 * height as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self {
            buffer,
            bytes_per_row,
            texel_bytes,
            width,
            height,
        }
    }

    /// Records the copy of `level` of `texture` (its size at that level
    /// must be the readback's).
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, texture: &wgpu::Texture, level: u32) {
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture,
                mip_level: level,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyBufferInfo {
                buffer: &self.buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(self.bytes_per_row),
                    rows_per_image: Some(self.height),
                },
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }

    /// The texels of a submitted copy, row-major, row 0 = top.
    pub fn read(&self, ctx: &GpuContext) -> Result<Vec<u8>, GpuError> {
        let bytes = crate::renderer::map_read(ctx, &self.buffer)?;
        let (row, used) = (
            self.bytes_per_row as usize,
            (self.width * self.texel_bytes) as usize,
        );
        let mut out = Vec::with_capacity(used * self.height as usize);
        for y in 0..self.height as usize {
            out.extend_from_slice(&bytes[y * row..][..used]);
        }
        Ok(out)
    }

    /// [`Self::read`] as `f32` values (for float formats).
    pub fn read_f32(&self, ctx: &GpuContext) -> Result<Vec<f32>, GpuError> {
        Ok(bytemuck::pod_collect_to_vec(&self.read(ctx)?))
    }
}
