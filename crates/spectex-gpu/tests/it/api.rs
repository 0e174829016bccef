//! The public API's failure paths and limits: error messages that say what to do, invalid models
//! and windows rejected before any device work, and tiles that respect the device's limits.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common;

use spectex_gpu::{GpuError, GpuEvaluator, GpuWindow, OutputFormat};
use spectex_model::{LrpNoise, Model, Stratum};

fn lrp(window_width: f32) -> Model {
    Model::Lrp(LrpNoise {
        seed: 1,
        mean: 0.0,
        strata: vec![
            Stratum {
                window_width,
                amplitude: 1.0,
                sub_strata: vec![vec![[0.1, 0.2]]],
            };
            3
        ],
    })
}

#[test]
fn no_adapter_message_lists_adapters_and_says_how_to_get_lavapipe() {
    let e = GpuError::NoAdapter {
        found: vec![
            "Foo GPU (Vulkan, DiscreteGpu)".into(),
            "Bar (Gl, Cpu)".into(),
        ],
        wanted: Some("llvmpipe".into()),
    };
    let text = e.to_string();
    for needle in [
        "\"llvmpipe\"",
        "WGPU_ADAPTER_NAME",
        "Foo GPU (Vulkan, DiscreteGpu), Bar (Gl, Cpu)",
        "apt-get install mesa-vulkan-drivers libvulkan1",
    ] {
        assert!(text.contains(needle), "{needle:?} missing from: {text}");
    }
    let none = GpuError::NoAdapter {
        found: vec![],
        wanted: None,
    }
    .to_string();
    assert!(none.contains("adapters found: none"), "{none}");
}

#[test]
fn invalid_models_and_windows_are_typed_errors() {
    let Some(context) = common::gpu_or_skip("invalid_models_and_windows") else {
        return;
    };
    match GpuEvaluator::new(&context, &lrp(0.1)) {
        Err(GpuError::Model(e)) => assert!(e.to_string().contains("window_width"), "{e}"),
        other => panic!("expected a model error, got {other:?}"),
    }
    let gpu = GpuEvaluator::new(&context, &lrp(8.0)).unwrap();
    for (window, parameter) in [
        (GpuWindow::new(0, 4), "width"),
        (GpuWindow::new(4, 4).at([0.0, 0.0], -1.0), "scale"),
        (
            GpuWindow::new(4, 4).at([0.0, f64::INFINITY], 1.0),
            "offset y",
        ),
        (
            GpuWindow::new(4, 4).at([-2.0e9, 0.0], 1.0),
            "window position",
        ),
    ] {
        match gpu.render(&window) {
            Err(GpuError::Window { parameter: p, .. }) => assert_eq!(p, parameter),
            other => panic!("{window:?}: expected a window error, got {other:?}"),
        }
        match gpu.reserve(&window, OutputFormat::Unorm8) {
            Err(GpuError::Window { parameter: p, .. }) => assert_eq!(p, parameter),
            other => panic!("{window:?}: reserve: expected a window error, got {other:?}"),
        }
    }
}

/// The largest windows are split into tiles whose output and per-axis tables each fit one
/// storage binding and whose dispatch fits the workgroup-count limit.
#[test]
fn tiles_respect_the_device_limits() {
    let Some(context) = common::gpu_or_skip("tiles_respect_the_device_limits") else {
        return;
    };
    let limits = context.limits();
    let binding = limits
        .max_storage_buffer_binding_size
        .min(limits.max_buffer_size);
    let dispatch = u64::from(limits.max_compute_workgroups_per_dimension) * 8;
    let mut gpu = GpuEvaluator::new(&context, &lrp(8.0)).unwrap();
    gpu.set_max_tile(usize::MAX, usize::MAX);
    for window in [
        GpuWindow::new(65_536, 16_384),
        GpuWindow::new(16_384, 65_536),
        GpuWindow::new(65_536, 1),
        GpuWindow::new(1, 65_536),
    ] {
        let [w, h] = gpu.tile_size(&window).unwrap();
        let (w, h) = (w as u64, h as u64);
        assert!(w * h * 4 <= binding, "{window:?}: output {w}×{h}");
        assert!(3 * 20 * w.max(h) <= binding, "{window:?}: axis tables");
        assert!(w <= dispatch && h <= dispatch, "{window:?}: dispatch");
        assert!(w >= 1 && h >= 1);
    }
    eprintln!(
        "{}: storage binding {binding} bytes, {dispatch} invocations per dimension; \
         a 65536×16384 window renders in tiles of {:?}",
        context.adapter_name(),
        gpu.tile_size(&GpuWindow::new(65_536, 16_384)).unwrap()
    );
}
