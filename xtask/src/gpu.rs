//! GPU speed: `cargo xtask bench gpu` (every testdata model on the GPU, kernel-only and end to
//! end, against the CPU on all threads, into `target/bench/gpu.md` and `gpu.svg`),
//! `cargo xtask gpu-report` (the same measured on a machine without Rust: a folder of stripped,
//! compressed binaries and one script), and `gpu-table` (the script's figures as one Markdown
//! table, run there by the xtask binary the folder carries).

use std::env;
use std::ffi::OsString;
use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result, bail};

use crate::json::compiler_artifacts;
use crate::system::ensure_lavapipe;
use crate::{Workspace, run_command, target_dir};

/// One model's figures, in Mpix/s.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ModelSpeed {
    pub name: String,
    pub evaluations: f64,
    pub kernel: Option<f64>,
    pub gpu: f64,
    pub cpu: f64,
    /// Tiles of the GPU render and bytes it read back per pixel, where printed.
    pub tiles: Option<(usize, f64)>,
    /// GPU end to end as 8-bit unorm (levels packed on the device), where printed.
    pub unorm8: Option<f64>,
    /// Host preparation per tile in ms (summed over the render's worker threads), where printed.
    pub host_ms: Option<f64>,
    /// The CLI's own figures on the GPU (end to end, kernels), where measured.
    pub cli: Option<(f64, Option<f64>)>,
}

/// A frame time of the LRP paper's Table 1, in ms.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct FrameTime {
    pub name: String,
    pub side: usize,
    pub kernel: Option<f64>,
    pub end_to_end: f64,
}

/// What the models bench and the report script print, parsed.
#[derive(Debug, Default)]
pub(crate) struct Figures {
    pub adapter: Option<String>,
    pub models: Vec<ModelSpeed>,
    pub frames: Vec<FrameTime>,
}

fn number(field: Option<&str>) -> Option<Option<f64>> {
    match field?.trim() {
        "-" => Some(None),
        text => text.parse().ok().map(Some),
    }
}

/// Parses the lines of the models bench (`adapter`, `model`, `frame`) and of the report
/// script's CLI runs (`cli <model> <end-to-end Mpix/s> <kernel Mpix/s or ->`); other lines are
/// ignored.
pub(crate) fn parse_figures(text: &str) -> Figures {
    let mut figures = Figures::default();
    let mut cli = Vec::new();
    for line in text.lines() {
        let fields: Vec<&str> = line.split('\t').collect();
        match fields.as_slice() {
            ["adapter", name, ..] => figures.adapter = Some((*name).to_owned()),
            ["model", name, evaluations, kernel, gpu, cpu, rest @ ..] if rest.len() <= 4 => {
                let parsed = (|| {
                    Some(ModelSpeed {
                        name: (*name).to_owned(),
                        evaluations: evaluations.trim().parse().ok()?,
                        kernel: number(Some(kernel))?,
                        gpu: number(Some(gpu))??,
                        cpu: number(Some(cpu))??,
                        tiles: match rest {
                            [tiles, bytes, ..] => {
                                Some((tiles.trim().parse().ok()?, bytes.trim().parse().ok()?))
                            }
                            _ => None,
                        },
                        unorm8: match rest {
                            [_, _, unorm8, ..] => number(Some(unorm8))?,
                            _ => None,
                        },
                        host_ms: match rest {
                            [_, _, _, host] => number(Some(host))?,
                            _ => None,
                        },
                        cli: None,
                    })
                })();
                figures.models.extend(parsed);
            }
            ["frame", name, side, kernel, end_to_end] => {
                let parsed = (|| {
                    Some(FrameTime {
                        name: (*name).to_owned(),
                        side: side.trim().parse().ok()?,
                        kernel: number(Some(kernel))?,
                        end_to_end: number(Some(end_to_end))??,
                    })
                })();
                figures.frames.extend(parsed);
            }
            ["cli", name, end_to_end, kernel] => {
                if let (Some(Some(e)), Some(k)) = (number(Some(end_to_end)), number(Some(kernel))) {
                    cli.push(((*name).to_owned(), (e, k)));
                }
            }
            _ => {}
        }
    }
    for (name, figures_cli) in cli {
        if let Some(m) = figures.models.iter_mut().find(|m| m.name == name) {
            m.cli = Some(figures_cli);
        }
    }
    figures
}

fn cell(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_owned(), |v| format!("{v:.2}"))
}

/// The Markdown table of `figures` for windows of `side`² pixels.
pub(crate) fn markdown(figures: &Figures, side: Option<usize>) -> String {
    let mut md = String::new();
    if let Some(adapter) = &figures.adapter {
        let _ = writeln!(md, "GPU: {adapter}.\n");
    }
    let size = side.map_or_else(String::new, |s| format!(", {s}² windows"));
    let with_cli = figures.models.iter().any(|m| m.cli.is_some());
    let with_tiles = figures.models.iter().any(|m| m.tiles.is_some());
    let with_unorm8 = figures.models.iter().any(|m| m.unorm8.is_some());
    let with_host = figures.models.iter().any(|m| m.host_ms.is_some());
    let _ = writeln!(
        md,
        "Mpix/s{size}; GPU / CPU is end to end against end to end.\n"
    );
    md.push_str("| model | evaluations/px | GPU kernel-only | GPU end to end | CPU all threads | GPU / CPU |");
    if with_tiles {
        md.push_str(" kernel share | tiles | bytes read back / px |");
    }
    if with_unorm8 {
        md.push_str(" GPU end to end, 8-bit |");
    }
    if with_host {
        md.push_str(" host ms / tile |");
    }
    if with_cli {
        md.push_str(" CLI GPU end to end | CLI GPU kernels |");
    }
    md.push_str("\n| --- | ---: | ---: | ---: | ---: | ---: |");
    if with_tiles {
        md.push_str(" ---: | ---: | ---: |");
    }
    if with_unorm8 {
        md.push_str(" ---: |");
    }
    if with_host {
        md.push_str(" ---: |");
    }
    if with_cli {
        md.push_str(" ---: | ---: |");
    }
    md.push('\n');
    for m in &figures.models {
        let _ = write!(
            md,
            "| {} | {:.1} | {} | {:.2} | {:.2} | {:.2} |",
            m.name,
            m.evaluations,
            cell(m.kernel),
            m.gpu,
            m.cpu,
            m.gpu / m.cpu.max(f64::MIN_POSITIVE)
        );
        if with_tiles {
            // Kernel-only time over end-to-end time: the share of the render the device computes.
            let share = m.kernel.map(|k| m.gpu / k.max(f64::MIN_POSITIVE));
            let (tiles, bytes) = m.tiles.map_or((None, None), |(t, b)| (Some(t), Some(b)));
            let _ = write!(
                md,
                " {} | {} | {} |",
                cell(share),
                tiles.map_or_else(|| "—".to_owned(), |t| t.to_string()),
                cell(bytes)
            );
        }
        if with_unorm8 {
            let _ = write!(md, " {} |", cell(m.unorm8));
        }
        if with_host {
            let host = m
                .host_ms
                .map_or_else(|| "—".to_owned(), |h| format!("{h:.3}"));
            let _ = write!(md, " {host} |");
        }
        if with_cli {
            let (e, k) = m.cli.map_or((None, None), |(e, k)| (Some(e), k));
            let _ = write!(md, " {} | {} |", cell(e), cell(k));
        }
        md.push('\n');
    }
    if !figures.frames.is_empty() {
        md.push_str("\nLRP paper, Table 1 texture frame (GPU, ms; the paper's GTX 780 took 0.43–0.57 ms):\n\n");
        md.push_str("| texture | side | kernel-only (ms) | end to end (ms) |\n| --- | ---: | ---: | ---: |\n");
        for f in &figures.frames {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.3} |",
                f.name,
                f.side,
                f.kernel
                    .map_or_else(|| "—".to_owned(), |k| format!("{k:.3}")),
                f.end_to_end
            );
        }
    }
    md
}

/// A horizontal bar chart of the models' three figures (log scale).
fn chart(path: &Path, figures: &Figures, side: usize) -> Result<()> {
    use plotters::prelude::*;
    use plotters::style::text_anchor::{HPos, Pos, VPos};

    let models = &figures.models;
    let n = models.len().max(1);
    let height = 110 + 40 * u32::try_from(n).context("too many models")?;
    let root = SVGBackend::new(path, (1000, height)).into_drawing_area();
    root.fill(&WHITE)?;
    let values = models
        .iter()
        .flat_map(|m| [m.kernel.unwrap_or(m.gpu), m.gpu, m.cpu]);
    let max = values.clone().fold(1.0f64, f64::max) * 3.0;
    let min = values.fold(f64::INFINITY, f64::min).min(1.0) / 2.0;
    let adapter = figures.adapter.as_deref().unwrap_or("GPU");
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("spectex, {side}² renders on {adapter} and the CPU (Mpix/s, log scale)"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(230)
        .build_cartesian_2d((min..max).log_scale(), 0f64..n as f64)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_label_formatter(&|_| String::new())
        .x_desc("Mpix/s")
        .draw()?;
    type Figure = fn(&ModelSpeed) -> Option<f64>;
    let series: [(&str, RGBColor, Figure); 3] = [
        ("GPU kernel-only", RGBColor(39, 174, 96), |m| m.kernel),
        ("GPU end to end", RGBColor(41, 128, 185), |m| Some(m.gpu)),
        ("CPU all threads", RGBColor(230, 126, 34), |m| Some(m.cpu)),
    ];
    for (k, (label, colour, get)) in series.into_iter().enumerate() {
        let bars = models.iter().enumerate().filter_map(|(i, m)| {
            let top = (n - 1 - i) as f64;
            let y0 = top + 0.1 + 0.27 * (2 - k) as f64;
            Some(Rectangle::new(
                [(min, y0), (get(m)?, y0 + 0.25)],
                colour.filled(),
            ))
        });
        chart
            .draw_series(bars)?
            .label(label)
            .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], colour.filled()));
    }
    let name_style =
        TextStyle::from(("sans-serif", 13).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
    for (i, m) in models.iter().enumerate() {
        let (x, y) = chart.backend_coord(&(min, (n - 1 - i) as f64 + 0.5));
        let name = format!("{} ({:.0}/px)", m.name, m.evaluations);
        root.draw(&Text::new(name, (x - 8, y), name_style.clone()))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// The `--size` among the bench's arguments, else `default`.
fn size_arg(args: &[OsString], default: usize) -> usize {
    args.windows(2)
        .find(|w| w[0] == "--size")
        .and_then(|w| w[1].to_str()?.parse().ok())
        .unwrap_or(default)
}

/// `cargo xtask bench gpu [--size N] [--repeat R] [--only S]`: the models bench on the adapter
/// `WGPU_ADAPTER_NAME` names, lavapipe when unset (default size 64 there: lavapipe runs the
/// heaviest kinds at a few kpix/s), into `target/bench/gpu.md` and `gpu.svg`.
pub(crate) fn bench_gpu(ws: &Workspace, extra: &[OsString]) -> Result<()> {
    let out = target_dir(ws).join("bench");
    fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let mut command = ws.cargo(&[
        "bench",
        "-p",
        "spectex-crosscheck",
        "--bench",
        "models",
        "--",
        "--bench",
    ]);
    let on_lavapipe = env::var_os("WGPU_ADAPTER_NAME").is_none();
    let mut args = extra.to_vec();
    if on_lavapipe {
        ensure_lavapipe(ws)?.apply(&mut command);
        if !args.iter().any(|a| a == "--size") {
            args.extend(["--size".into(), "64".into()]);
        }
    }
    let side = size_arg(&args, 256);
    command.args(&args).stdout(Stdio::piped());
    eprintln!("xtask: bench gpu: {command:?}");
    let output = command
        .spawn()
        .context("starting cargo bench")?
        .wait_with_output()
        .context("running the models bench")?;
    let text = String::from_utf8_lossy(&output.stdout);
    print!("{text}");
    if !output.status.success() {
        bail!("the models bench failed ({})", output.status);
    }
    let figures = parse_figures(&text);
    if figures.models.is_empty() {
        bail!("the models bench printed no model line");
    }
    let md = markdown(&figures, Some(side));
    fs::write(out.join("gpu.md"), &md)?;
    chart(&out.join("gpu.svg"), &figures, side)?;
    println!(
        "\n{md}\nxtask: wrote {} and gpu.svg",
        out.join("gpu.md").display()
    );
    Ok(())
}

/// `xtask gpu-table FILE… [--size N]`: the figures in FILEs (the models bench's lines and the
/// report script's `cli` lines) as one Markdown table on standard output.
pub(crate) fn gpu_table(args: &[OsString]) -> Result<()> {
    let mut text = String::new();
    let mut files = Vec::new();
    let mut iter = args.iter();
    let mut side = None;
    while let Some(arg) = iter.next() {
        if arg == "--size" {
            side = iter.next().and_then(|s| s.to_str()?.parse().ok());
        } else {
            files.push(PathBuf::from(arg));
        }
    }
    if files.is_empty() {
        bail!("usage: xtask gpu-table FILE… [--size N]");
    }
    for file in files {
        text.push_str(
            &fs::read_to_string(&file).with_context(|| format!("reading {}", file.display()))?,
        );
        text.push('\n');
    }
    let figures = parse_figures(&text);
    if figures.models.is_empty() {
        bail!("no `model` line in the files: did the models bench run?");
    }
    print!("{}", markdown(&figures, side));
    Ok(())
}

/// The Debian packages the device machine's Vulkan loader needs (it has the NVIDIA ICD only).
const VULKAN_DEBS: &[&str] = &[
    "libvulkan1",
    "libegl1",
    "libglvnd0",
    "libopengl0",
    "libgl1",
    "libglx0",
    "libgles2",
];

/// The script the report folder carries: unpacks, runs the models bench and the CLI on every
/// model, prints the table, then the CLI's PNG renders and the exported modules' bench (compute
/// and render pipeline at 1920×1080 and 3840×2160, with the LRP J = 50 row). `$1` is the window
/// side (default 4096).
const REPORT_SCRIPT: &str = r#"#!/usr/bin/env bash
# spectex GPU report: spectex-gpu's tests and the CPU/GPU cross-check on this GPU, every testdata
# model through the CLI (GPU end to end and kernel-only) and the models bench (GPU kernel-only,
# end to end, CPU all threads), then one Markdown table.
# Run from the repository root: bash target/gpu-report/run.sh [SIDE]
# (EXPORT_SIZES="WxH …" changes the export bench's grids; SPECTEX_BENCH_MODELS=a,b its models;
# TESTS=0 skips the tests.)
set -uo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
side="${1:-4096}"
out="${OUT:-$here/out}"
mkdir -p "$out"
work="$(mktemp -d)"
for deb in "$here"/debs/*.deb; do [ -e "$deb" ] && dpkg -x "$deb" / ; done
ldconfig 2>/dev/null || true
export XDG_RUNTIME_DIR="$work/xdg"; mkdir -m 700 -p "$XDG_RUNTIME_DIR"
tar -xJf "$here/bin.tar.xz" -C "$work"
models="$(pwd)/testdata/models"
[ -d "$models" ] || { echo "run from the repository root (testdata/models missing)"; exit 1; }
if [ "${TESTS:-1}" = 1 ]; then
  echo "== spectex-gpu's tests and the cross-check, on this machine's GPU =="
  # The test binaries read files under the building machine's repository root (their
  # CARGO_MANIFEST_DIR): that path is made to lead here.
  root="$(cat "$work/build-root")"
  if [ "$root" != "$(pwd)" ] && [ ! -e "$root" ]; then
    mkdir -p "$(dirname "$root")" && ln -s "$(pwd)" "$root"
  fi
  for t in gpu-tests crosscheck-tests; do
    SPECTEX_REQUIRE_GPU=1 timeout 240 "$work/$t" > "$out/$t.txt" 2>&1
    echo "$t: exit $? ($(grep -c '^test .* ok$' "$out/$t.txt") ok lines); $(grep -E '^test result' "$out/$t.txt" | tail -n 1)"
    grep -E 'panicked at|FAILED' "$out/$t.txt" | head -n 20
  done
fi
echo "== models bench, ${side}² =="
timeout 240 "$work/models" --bench --size "$side" --repeat 2 --models "$models" | tee "$out/models.tsv"
echo "== CLI, ${side}² =="
: > "$out/cli.tsv"
for m in "$models"/*.json; do
  name="$(basename "$m" .json)"
  line="$(timeout 60 "$work/spectex" render "$m" --size "${side}x${side}" --device gpu -o "$work/x.exr" 2>&1 | grep -o '[0-9.]* Mpix/s.*')"
  e2e="$(echo "$line" | grep -o '^[0-9.]*')"
  kernel="$(echo "$line" | grep -o '[0-9.]* Mpix/s in the kernels' | grep -o '^[0-9.]*')"
  printf 'cli\t%s\t%s\t%s\n' "$name" "${e2e:--}" "${kernel:--}" | tee -a "$out/cli.tsv"
done
"$work/xtask" gpu-table "$out/models.tsv" "$out/cli.tsv" --size "$side" | tee "$out/gpu.md"
echo "== CLI, ${side}², 8-bit PNG (levels packed on the device) =="
for m in classic-perlin-fbm lrp-ring; do
  timeout 60 "$work/spectex" render "$models/$m.json" --size "${side}x${side}" --device gpu -o "$work/x.png" 2>&1 | grep -o '[0-9.]* Mpix/s.*' | sed "s/^/$m: /" | tee -a "$out/cli-png.txt"
done
echo "== exported modules: compute shader and render pipeline, 1920x1080 and 3840x2160 =="
for size in ${EXPORT_SIZES:-1920x1080 3840x2160}; do
  for render in 0 1; do
    SPECTEX_BENCH_SIZE="$size" SPECTEX_BENCH_RENDER="$render" SPECTEX_BENCH_MODELS_DIR="$models" \
      CARGO_TARGET_DIR="$out/export-$size-$render" timeout 90 "$work/export" --bench \
      | tee "$out/export-$size-$render.txt"
  done
done
"#;

/// `cargo xtask gpu-report`: builds what the GPU machine needs (it has no Rust) into
/// `target/gpu-report/`: the release CLI, the models bench and this xtask, stripped and
/// compressed (`bin.tar.xz`), the Vulkan loader's Debian packages (`debs/`), and `run.sh`.
pub(crate) fn gpu_report(ws: &Workspace) -> Result<()> {
    let target = target_dir(ws);
    let dir = target.join("gpu-report");
    let stage = dir.join("stage");
    if dir.exists() {
        fs::remove_dir_all(&dir).with_context(|| format!("clearing {}", dir.display()))?;
    }
    fs::create_dir_all(&stage)?;
    run_command(&mut ws.cargo(&["build", "--release", "-p", "spectex-cli", "-p", "xtask"]))?;
    let binaries = [
        (target.join("release/spectex"), "spectex"),
        (target.join("release/xtask"), "xtask"),
        (bench_executable(ws, "models")?, "models"),
        (bench_executable(ws, "export")?, "export"),
        (test_executable(ws, "spectex-gpu")?, "gpu-tests"),
        (
            test_executable(ws, "spectex-crosscheck")?,
            "crosscheck-tests",
        ),
    ];
    for (from, name) in &binaries {
        let to = stage.join(name);
        fs::copy(from, &to).with_context(|| format!("copying {}", from.display()))?;
        // Stripping only shrinks the folder: without `strip` the binaries still work.
        let _ = Command::new("strip").arg(&to).status();
    }
    // Where the test binaries look for the repository's files (see the script).
    fs::write(stage.join("build-root"), ws.root.display().to_string())?;
    run_command(
        Command::new("tar")
            .arg("-cJf")
            .arg(dir.join("bin.tar.xz"))
            .arg("-C")
            .arg(&stage)
            .args(binaries.iter().map(|(_, name)| name))
            .arg("build-root"),
    )?;
    fs::remove_dir_all(&stage)?;
    let debs = dir.join("debs");
    fs::create_dir_all(&debs)?;
    let downloaded = Command::new("apt-get")
        .arg("download")
        .args(VULKAN_DEBS)
        .current_dir(&debs)
        .status()
        .is_ok_and(|s| s.success());
    if !downloaded {
        eprintln!(
            "xtask: gpu-report: could not `apt-get download` {} (run `apt-get update` first); \
             the folder works where the GPU machine has its Vulkan loader",
            VULKAN_DEBS.join(" ")
        );
    }
    let script = dir.join("run.sh");
    fs::File::create(&script)?.write_all(REPORT_SCRIPT.as_bytes())?;
    let size: u64 = fs::read_dir(&dir)?
        .flatten()
        .map(|e| folder_bytes(&e.path()))
        .sum();
    println!(
        "xtask: wrote {} ({:.1} MiB): carry it to the GPU machine and run `bash {}/run.sh [SIDE]` \
         from the repository root",
        dir.display(),
        size as f64 / (1 << 20) as f64,
        dir.strip_prefix(&ws.root).unwrap_or(&dir).display()
    );
    Ok(())
}

fn folder_bytes(path: &Path) -> u64 {
    if path.is_dir() {
        fs::read_dir(path)
            .map(|d| d.flatten().map(|e| folder_bytes(&e.path())).sum())
            .unwrap_or(0)
    } else {
        path.metadata().map_or(0, |m| m.len())
    }
}

/// Builds `package`'s integration test binary `it` (the test profile, as CI builds it) and
/// returns its executable.
fn test_executable(ws: &Workspace, package: &str) -> Result<PathBuf> {
    let what = format!("{package}'s tests");
    built_executable(ws, &["test", "-p", package, "--test", "it"], "it", &what)
}

/// Builds spectex-crosscheck's bench `name` (release profile) and returns its executable.
fn bench_executable(ws: &Workspace, name: &str) -> Result<PathBuf> {
    let args = ["bench", "-p", "spectex-crosscheck", "--bench", name];
    built_executable(ws, &args, name, &format!("the {name} bench"))
}

/// Runs `cargo <args> --no-run` and returns the executable of its target `target` (`what`
/// names it in errors).
fn built_executable(ws: &Workspace, args: &[&str], target: &str, what: &str) -> Result<PathBuf> {
    let mut args = args.to_vec();
    args.extend(["--no-run", "--message-format=json"]);
    let output = ws
        .cargo(&args)
        .stderr(Stdio::inherit())
        .output()
        .with_context(|| format!("building {what}"))?;
    if !output.status.success() {
        bail!("building {what} failed");
    }
    compiler_artifacts(&String::from_utf8_lossy(&output.stdout))
        .filter(|a| a.target.name == target)
        .find_map(|a| a.executable)
        .with_context(|| format!("cargo did not name {what}'s executable"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bench_and_cli_lines_make_one_table() {
        let text = "adapter\tNVIDIA H200\tkernel-only\t16 CPU threads\n\
                    model\tlrp-ring\t45.0\t2000.50\t1000.25\t200.00\t4\t4.00\t1800.75\t0.125\n\
                    model\tclassic-perlin-fbm\t5.0\t-\t94.00\t907.00\n\
                    model\tbroken\tx\t1\t2\t3\n\
                    frame\ttexture-synthetic-grey\t128\t0.050\t0.400\n\
                    cli\tlrp-ring\t900.5\t1900.0\n\
                    cli\tclassic-perlin-fbm\t90.0\t-\n";
        let figures = parse_figures(text);
        assert_eq!(figures.adapter.as_deref(), Some("NVIDIA H200"));
        assert_eq!(figures.models.len(), 2);
        assert_eq!(figures.models[0].kernel, Some(2000.5));
        assert_eq!(figures.models[0].cli, Some((900.5, Some(1900.0))));
        assert_eq!(figures.models[1].kernel, None);
        assert_eq!(figures.models[1].cli, Some((90.0, None)));
        assert_eq!(figures.frames[0].kernel, Some(0.05));
        assert_eq!(figures.models[0].tiles, Some((4, 4.0)));
        assert_eq!(figures.models[0].unorm8, Some(1800.75));
        assert_eq!(figures.models[1].unorm8, None);
        assert_eq!(figures.models[0].host_ms, Some(0.125));
        let md = markdown(&figures, Some(4096));
        assert!(
            md.contains(
                "| lrp-ring | 45.0 | 2000.50 | 1000.25 | 200.00 | 5.00 | 0.50 | 4 | 4.00 | 1800.75 | 0.125 | 900.50 | 1900.00 |"
            ),
            "{md}"
        );
        assert!(
            md.contains(
                "| classic-perlin-fbm | 5.0 | — | 94.00 | 907.00 | 0.10 | — | — | — | — | — | 90.00 | — |"
            ),
            "{md}"
        );
        assert!(
            md.contains("| texture-synthetic-grey | 128 | 0.050 | 0.400 |"),
            "{md}"
        );
    }
}
