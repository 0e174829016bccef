//! spectex inside your own wgpu renderer: the renderer's device and queue become a
//! `GpuContext`, spectex renders a window straight into the renderer's storage buffer (nothing
//! read back), and the renderer copies that buffer into its texture in the same frame. Here the
//! texture is then read back once, only to show that it holds the CPU's values. Without a GPU
//! adapter it says why and exits successfully (`WGPU_ADAPTER_NAME=llvmpipe` picks lavapipe).
//!
//! ```sh
//! cargo run --example 05_gpu_in_your_renderer -- [OUT_DIR]
//! ```

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use spectex_cpu::Evaluator;
use spectex_gpu::{GpuContext, GpuEvaluator, GpuWindow, OutputFormat, wgpu};
use spectex_model::{ClassicNoise, Model};

const SIDE: u32 = 256;

fn main() -> Result<()> {
    let out_dir = std::env::args()
        .nth(1)
        .map_or_else(std::env::temp_dir, PathBuf::from);

    // 1. Your renderer's device and queue (Bevy: `RenderDevice::wgpu_device()` and
    //    `RenderQueue`). Ask for TIMESTAMP_QUERY where the adapter has it to get kernel times.
    let Some((device, queue)) = renderer_device() else {
        println!("no GPU adapter (try WGPU_ADAPTER_NAME=llvmpipe with lavapipe); nothing written");
        return Ok(());
    };
    let context = GpuContext::from_device(device.clone(), queue.clone());

    // 2. A model prepared once on that device.
    let model: Model = ClassicNoise::fbm().octaves(5).seed(11).build()?.into();
    let noise = GpuEvaluator::new(&context, &model)?;

    // 3. Each frame: spectex fills your buffer, you copy it into your texture.
    let window = GpuWindow::new(SIDE as usize, SIDE as usize).at([5.0e6, -3.0e6], 0.5);
    let bytes = u64::from(SIDE * SIDE * 4);
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("my noise buffer"),
        size: bytes,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("my noise texture"),
        size: wgpu::Extent3d {
            width: SIDE,
            height: SIDE,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_DST
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let stats = noise.render_to_buffer(&window, OutputFormat::F32, &buffer, 0)?;
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_buffer_to_texture(
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(SIDE * 4),
                rows_per_image: Some(SIDE),
            },
        },
        texture.as_image_copy(),
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    // ... your render pass samples `texture` here.

    // Only for this example: read the texture back and compare it with the CPU render.
    let values = read_texture(&device, &queue, &texture)?;
    let reference = Evaluator::new(&model)?.render(&window)?;
    let largest_difference = values
        .iter()
        .zip(&reference)
        .map(|(g, c)| (g - c).abs())
        .fold(0.0f32, f32::max);
    std::fs::create_dir_all(&out_dir)?;
    let out = out_dir.join("05_gpu_in_your_renderer.png");
    let grey: Vec<u8> = values
        .iter()
        .map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8)
        .collect();
    image::save_buffer(&out, &grey, SIDE, SIDE, image::ColorType::L8)?;
    println!(
        "wrote {} ({SIDE}×{SIDE} into a texture on {}, {} bytes read back by spectex; largest \
         difference from the CPU {largest_difference:e})",
        out.display(),
        noise.adapter_name(),
        stats.bytes_read_back
    );
    Ok(())
}

/// A device and queue as a renderer would open them, or `None` without an adapter.
fn renderer_device() -> Option<(wgpu::Device, wgpu::Queue)> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
    let wanted = std::env::var(spectex_gpu::ADAPTER_NAME_ENV).unwrap_or_default();
    let adapter = adapters.into_iter().find(|a| {
        a.get_info()
            .name
            .to_lowercase()
            .contains(&wanted.to_lowercase())
    })?;
    pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("my renderer"),
        required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
        ..Default::default()
    }))
    .ok()
}

/// The texture's f32 texels, row-major.
fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
) -> Result<Vec<f32>> {
    let row = SIDE * 4; // a multiple of 256, as texel copies require
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(row * SIDE),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    encoder.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(SIDE),
            },
        },
        texture.size(),
    );
    queue.submit([encoder.finish()]);
    let (sender, receiver) = std::sync::mpsc::channel();
    staging
        .slice(..)
        .map_async(wgpu::MapMode::Read, move |r| drop(sender.send(r)));
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| anyhow!("waiting for the device: {e}"))?;
    receiver.recv()??;
    let values = bytemuck::pod_collect_to_vec(&staging.slice(..).get_mapped_range()?);
    staging.unmap();
    Ok(values)
}
