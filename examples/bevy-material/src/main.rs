//! A spectex model in a Bevy `Material2d`: loads a module written by
//! `spectex export MODEL.json --wgsl OUT`, registers it under the import path
//! `spectex::model`, and draws a full-window rectangle whose fragment shader
//! (`assets/spectex_material.wgsl`) calls `spectex_sample` at every pixel.
//!
//! Headless (no window, no winit): the camera renders into an `Rgba16Float` image, one frame is
//! captured with Bevy's `Screenshot`, written as raw little-endian f32 values (RGB per pixel,
//! row-major from the top) and the app exits. `cargo xtask bevy-check` runs it on lavapipe and
//! compares the frame with `spectex render`.
//!
//! Usage: `spectex-bevy-material MODULE OUT.f32 WIDTH HEIGHT OFFSET_X OFFSET_Y SCALE`

use std::time::Duration;

use bevy::app::ScheduleRunnerPlugin;
use bevy::camera::Hdr;
use bevy::camera::RenderTarget;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;
use bevy::render::render_resource::{AsBindGroup, TextureFormat};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};
use bevy::shader::ShaderRef;
use bevy::sprite_render::{Material2d, Material2dPlugin};
use bevy::window::ExitCondition;

/// The material: where the window starts and how many model pixels a framebuffer pixel spans.
#[derive(Asset, TypePath, AsBindGroup, Debug, Clone)]
struct SpectexMaterial {
    /// (offset x, offset y, scale, unused).
    #[uniform(0)]
    view: Vec4,
}

impl Material2d for SpectexMaterial {
    fn fragment_shader() -> ShaderRef {
        "spectex_material.wgsl".into()
    }
}

/// The command line.
#[derive(Resource, Clone)]
struct Settings {
    module: String,
    output: String,
    width: u32,
    height: u32,
    view: Vec4,
}

/// Keeps the exported module's shader asset alive (imports resolve against loaded shaders).
#[derive(Resource)]
#[allow(dead_code)]
struct ModelShader(Handle<Shader>);

/// Frames since start-up, and whether a screenshot is in flight.
#[derive(Resource, Default)]
struct Frames {
    count: u32,
    pending: bool,
}

/// Frames to wait for the material's pipeline before giving up: Bevy compiles pipelines in
/// the background, and on lavapipe (an LLVM compile per shader) the first frames show only
/// the clear colour.
const MAX_FRAMES: u32 = 6000;

fn parse() -> Result<Settings, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 7 {
        return Err(
            "usage: spectex-bevy-material MODEL.wgsl OUT.f32 WIDTH HEIGHT OFFSET_X OFFSET_Y SCALE"
                .into(),
        );
    }
    let num = |i: usize| {
        args[i]
            .parse::<f32>()
            .map_err(|e| format!("{}: {e}", args[i]))
    };
    let module = std::fs::read_to_string(&args[0]).map_err(|e| format!("{}: {e}", args[0]))?;
    Ok(Settings {
        module,
        output: args[1].clone(),
        width: args[2].parse().map_err(|e| format!("{}: {e}", args[2]))?,
        height: args[3].parse().map_err(|e| format!("{}: {e}", args[3]))?,
        view: Vec4::new(num(4)?, num(5)?, num(6)?, 0.0),
    })
}

fn main() -> std::process::ExitCode {
    let settings = match parse() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return std::process::ExitCode::FAILURE;
        }
    };
    let exit = App::new()
        .add_plugins((
            DefaultPlugins.set(WindowPlugin {
                primary_window: None,
                exit_condition: ExitCondition::DontExit,
                ..default()
            }),
            ScheduleRunnerPlugin::run_loop(Duration::from_millis(5)),
            Material2dPlugin::<SpectexMaterial>::default(),
        ))
        .insert_resource(settings)
        .insert_resource(ClearColor(Color::NONE))
        .init_resource::<Frames>()
        .add_systems(Startup, setup)
        .add_systems(Update, capture)
        .run();
    match exit {
        AppExit::Success => std::process::ExitCode::SUCCESS,
        AppExit::Error(_) => std::process::ExitCode::FAILURE,
    }
}

fn setup(
    mut commands: Commands,
    settings: Res<Settings>,
    mut shaders: ResMut<Assets<Shader>>,
    mut images: ResMut<Assets<Image>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<SpectexMaterial>>,
) {
    // The exported module, importable as `spectex::model` (naga_oil's import path).
    let source = format!("#define_import_path spectex::model\n{}", settings.module);
    let handle = shaders.add(Shader::from_wgsl(source, "spectex_model.wgsl"));
    commands.insert_resource(ModelShader(handle));

    let target = images.add(Image::new_target_texture(
        settings.width,
        settings.height,
        TextureFormat::Rgba16Float,
        None,
    ));
    commands.insert_resource(Target(target.clone()));
    commands.spawn((
        Camera2d,
        RenderTarget::Image(target.into()),
        Hdr,
        Tonemapping::None,
        DebandDither::Disabled,
        Msaa::Off,
    ));
    commands.spawn((
        Mesh2d(meshes.add(Rectangle::new(
            settings.width as f32 * 2.0,
            settings.height as f32 * 2.0,
        ))),
        MeshMaterial2d(materials.add(SpectexMaterial {
            view: settings.view,
        })),
    ));
}

/// The render target.
#[derive(Resource)]
struct Target(Handle<Image>);

/// Requests a screenshot every few frames until one shows the material over the whole target:
/// the clear colour is transparent and the material writes alpha 1, so a frame with alpha 1
/// everywhere is one the material drew (its pipeline had compiled); that one is written.
fn capture(
    mut commands: Commands,
    mut frames: ResMut<Frames>,
    target: Option<Res<Target>>,
    settings: Res<Settings>,
    mut exit: MessageWriter<AppExit>,
) {
    frames.count += 1;
    let Some(target) = target else { return };
    if frames.count > MAX_FRAMES {
        eprintln!("error: the material did not draw within {MAX_FRAMES} frames");
        exit.write(AppExit::error());
        return;
    }
    if frames.pending || !frames.count.is_multiple_of(10) {
        return;
    }
    frames.pending = true;
    let settings = settings.clone();
    commands.spawn(Screenshot::image(target.0.clone())).observe(
        move |captured: On<ScreenshotCaptured>,
              mut frames: ResMut<Frames>,
              mut exit: MessageWriter<AppExit>| {
            frames.pending = false;
            match drawn(&captured.image, &settings) {
                Ok(false) => {}
                Ok(true) => {
                    let result = write_frame(&captured.image, &settings);
                    if let Err(e) = &result {
                        eprintln!("error: {e}");
                    }
                    exit.write(match result {
                        Ok(()) => AppExit::Success,
                        Err(_) => AppExit::error(),
                    });
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    exit.write(AppExit::error());
                }
            }
        },
    );
}

/// The screenshot's bytes, bytes per texel and bytes per row, checked against the settings.
fn texels<'a>(image: &'a Image, settings: &Settings) -> Result<(&'a [u8], usize, usize), String> {
    let data = image.data.as_ref().ok_or("the screenshot has no data")?;
    let (w, h) = (settings.width as usize, settings.height as usize);
    let texel = match image.texture_descriptor.format {
        TextureFormat::Rgba16Float => 8,
        TextureFormat::Rgba32Float => 16,
        other => return Err(format!("unexpected screenshot format {other:?}")),
    };
    if data.len() < w * h * texel {
        return Err(format!("screenshot holds {} bytes for {w}x{h}", data.len()));
    }
    Ok((data, texel, data.len() / h))
}

/// Channel `c` of the texel at byte `at`.
fn channel(data: &[u8], texel: usize, at: usize, c: usize) -> f32 {
    if texel == 8 {
        let b = &data[at + 2 * c..at + 2 * c + 2];
        f16_to_f32(u16::from_le_bytes([b[0], b[1]]))
    } else {
        let b = &data[at + 4 * c..at + 4 * c + 4];
        f32::from_le_bytes([b[0], b[1], b[2], b[3]])
    }
}

/// Whether every pixel has alpha 1 (the material drew it; the clear colour has alpha 0).
fn drawn(image: &Image, settings: &Settings) -> Result<bool, String> {
    let (data, texel, row) = texels(image, settings)?;
    Ok((0..settings.height as usize).all(|j| {
        (0..settings.width as usize).all(|i| channel(data, texel, j * row + i * texel, 3) == 1.0)
    }))
}

/// Writes the frame's RGB as little-endian f32, row-major.
fn write_frame(image: &Image, settings: &Settings) -> Result<(), String> {
    let (data, texel, row) = texels(image, settings)?;
    let (w, h) = (settings.width as usize, settings.height as usize);
    let mut out = Vec::with_capacity(w * h * 12);
    for j in 0..h {
        for i in 0..w {
            for c in 0..3 {
                out.extend_from_slice(&channel(data, texel, j * row + i * texel, c).to_le_bytes());
            }
        }
    }
    std::fs::write(&settings.output, out).map_err(|e| format!("{}: {e}", settings.output))?;
    println!(
        "wrote {} ({w}x{h}, {:?})",
        settings.output, image.texture_descriptor.format
    );
    Ok(())
}

/// IEEE binary16 to f32 (exact).
fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = i32::from((h >> 10) & 0x1f);
    let frac = f32::from(h & 0x3ff);
    sign * match exp {
        0 => frac * 2f32.powi(-24),
        31 => f32::INFINITY,
        e => (1.0 + frac / 1024.0) * 2f32.powi(e - 15),
    }
}
