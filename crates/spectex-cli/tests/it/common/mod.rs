//! Helpers shared by the CLI's tests and benches: running the binary, scratch directories,
//! and images as channel planes.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs the `spectex` binary with `args`.
pub fn spectex(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spectex"))
        .args(args)
        .output()
        .expect("the spectex binary runs")
}

/// Runs the `spectex` binary with `args` and asserts that it succeeded (the message shows the
/// arguments and its stderr).
pub fn spectex_ok(args: &[&str]) -> Output {
    let out = spectex(args);
    assert!(
        out.status.success(),
        "spectex {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A fresh directory under the target dir for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The value after `--z` in `args`, or `"0"`.
pub fn z_of<'a>(args: &[&'a str]) -> &'a str {
    args.iter()
        .position(|a| *a == "--z")
        .map_or("0", |i| args[i + 1])
}

/// An image as `(channels, height, width)` values in `[0, 1]` (as `spectex` reads exemplars).
pub use spectex_reproduce::planes;

/// An EXR file's display window size, data window `(x, y, w, h)`, and channels by name.
pub struct Exr {
    pub display: (usize, usize),
    pub data: (i32, i32, usize, usize),
    pub channels: Vec<(String, Vec<f32>)>,
}

pub fn read_exr(path: &Path) -> Exr {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let layer = &image.layer_data;
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let FlatSamples::F32(v) = &c.sample_data else {
                panic!("{}: channel {} is not f32", path.display(), c.name);
            };
            (c.name.to_string(), v.clone())
        })
        .collect();
    let display = image.attributes.display_window;
    Exr {
        display: (display.size.0, display.size.1),
        data: (
            layer.attributes.layer_position.0,
            layer.attributes.layer_position.1,
            layer.size.0,
            layer.size.1,
        ),
        channels,
    }
}

impl Exr {
    /// The channels' names, in the file's order.
    pub fn names(&self) -> Vec<&str> {
        self.channels.iter().map(|(n, _)| n.as_str()).collect()
    }

    pub fn channel(&self, name: &str) -> &[f32] {
        &self
            .channels
            .iter()
            .find(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("no channel {name}"))
            .1
    }
}
