//! `spectex simulate`: whole-grid simulations (Gray–Scott, Swift–Hohenberg, Life-like,
//! elementary and cyclic automata) stepped by `spectex-simulate` on the CPU or by
//! `spectex-gpu` with `--gpu`, written as a final image and optionally as frames every N steps;
//! parameters can be saved to and read from a JSON file.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Subcommand, ValueEnum};
use ndarray::Array3;
use spectex_model::simulation::{
    Cyclic, Elementary, GrayScott, GrayScottPreset, LifeLike, Neighbourhood, Simulation,
    SimulationSpec, SwiftHohenberg, spec_from_json, spec_to_json,
};
use spectex_simulate::Simulator;

use crate::io::{self, BitDepth};
use crate::noise::{arg_of, model_of};

/// Arguments of `spectex simulate`.
/// Steps between frames unless `--every` is given: 100, a few dozen frames for the default
/// runs.
const DEFAULT_EVERY: u32 = 100;

#[derive(Debug, Args)]
pub struct SimulateCommand {
    #[command(subcommand)]
    kind: SimulationKind,
}

#[derive(Debug, Subcommand)]
enum SimulationKind {
    /// Gray–Scott reaction–diffusion (Pearson 1993); shows u.
    GrayScott(GrayScottArgs),
    /// Swift–Hohenberg equation, semi-implicit spectral steps.
    SwiftHohenberg(SwiftHohenbergArgs),
    /// Life-like cellular automaton given by a B/S rule (Moore neighbourhood).
    Life(LifeArgs),
    /// Elementary cellular automaton (Wolfram rule number), drawn as rows over time.
    Elementary(ElementaryArgs),
    /// Cyclic cellular automaton (Griffeath): n states and a threshold.
    Cyclic(CyclicArgs),
    /// Run the parameters of a JSON file written by --save-params.
    File(FileArgs),
}

/// What every simulation takes.
#[derive(Debug, Args)]
struct CommonArgs {
    /// Output image: .png (clamped to [0, 1]) or .exr (32-bit float).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,
    /// Grid size WIDTHxHEIGHT (for elementary, HEIGHT generations are drawn) [default: 256x256].
    #[arg(long, value_name = "WxH", value_parser = crate::args::parse_size)]
    size: Option<(usize, usize)>,
    /// Steps to run (elementary: generations before the first drawn row) [default: per
    /// simulation: gray-scott 8000, swift-hohenberg 400, life 200, elementary 0, cyclic 300].
    #[arg(long)]
    steps: Option<u32>,
    /// Seed of the initial state.
    #[arg(long)]
    seed: Option<u32>,
    /// Also write frames into DIR (created if missing): frame_000000.png at step 0, then every
    /// --every steps.
    #[arg(long, value_name = "DIR")]
    frames: Option<PathBuf>,
    /// Steps between frames.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_EVERY)]
    every: u32,
    /// Step on the GPU (Gray–Scott and the automata; the adapter named by WGPU_ADAPTER_NAME).
    #[arg(long)]
    gpu: bool,
    /// Write the run's parameters as JSON (read back with `spectex simulate file`).
    #[arg(long, value_name = "FILE")]
    save_params: Option<PathBuf>,
    /// Bits per channel of PNG outputs.
    #[arg(long, value_enum, default_value_t = BitDepth::DEFAULT)]
    bit_depth: BitDepth,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum PresetName {
    Spots,
    Stripes,
    Mazes,
    Holes,
}

#[derive(Debug, Args)]
struct GrayScottArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Pattern family: (F, k) inside Pearson's regions.
    #[arg(long, value_enum, default_value = "mazes")]
    preset: PresetName,
    /// Feed rate F (overrides the preset's), in [0, 0.1].
    #[arg(long)]
    feed: Option<f32>,
    /// Kill rate k (overrides the preset's), in [0, 0.1].
    #[arg(long)]
    kill: Option<f32>,
    /// Diffusion rate of u in pixels² per unit time [default: Pearson's, 0.2097].
    #[arg(long)]
    du: Option<f32>,
    /// Diffusion rate of v [default: Pearson's, 0.1049].
    #[arg(long)]
    dv: Option<f32>,
    /// Time step [default: 1].
    #[arg(long)]
    dt: Option<f32>,
    /// Number of initial square patches of Pearson's perturbed state [default: 64 per 256²].
    #[arg(long)]
    patches: Option<u32>,
    /// Side of a patch in pixels [default: 10].
    #[arg(long)]
    patch_size: Option<u32>,
}

#[derive(Debug, Args)]
struct SwiftHohenbergArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Bifurcation parameter r [default: 0.3].
    #[arg(long)]
    r: Option<f32>,
    /// Quadratic coefficient g (0: stripes; about 1: hexagonal spots) [default: 0].
    #[arg(long)]
    g: Option<f32>,
    /// Pattern wavelength in pixels [default: 12].
    #[arg(long)]
    wavelength: Option<f32>,
    /// Time step [default: 0.5].
    #[arg(long)]
    dt: Option<f32>,
}

#[derive(Debug, Args)]
struct LifeArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Rule B<digits>/S<digits>.
    #[arg(long, default_value_t = LifeLike::conway().rule)]
    rule: String,
    /// Share of live cells at start.
    #[arg(long, default_value_t = LifeLike::conway().density)]
    density: f32,
}

#[derive(Debug, Args)]
struct ElementaryArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Wolfram rule number, 0 to 255.
    #[arg(long, default_value_t = Elementary::RULE_30.rule)]
    rule: u32,
    /// Start from one live cell in the middle instead of a random row.
    #[arg(long)]
    single: bool,
    /// Share of live cells in a random first row.
    #[arg(long, default_value_t = Elementary::RULE_30.density)]
    density: f32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum NeighbourhoodArg {
    Moore,
    VonNeumann,
}

/// The neighbourhoods by name, for the conversions both ways.
const NEIGHBOURHOODS: [(NeighbourhoodArg, Neighbourhood); 2] = [
    (NeighbourhoodArg::Moore, Neighbourhood::Moore),
    (NeighbourhoodArg::VonNeumann, Neighbourhood::VonNeumann),
];

#[derive(Debug, Args)]
struct CyclicArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Number of states.
    #[arg(long, default_value_t = Cyclic::SPIRALS.states)]
    states: u32,
    /// Neighbours in the successor state needed to advance.
    #[arg(long, default_value_t = Cyclic::SPIRALS.threshold)]
    threshold: u32,
    /// Which neighbours count.
    #[arg(long, value_enum, default_value_t = arg_of(&NEIGHBOURHOODS, &Cyclic::SPIRALS.neighbourhood))]
    neighbourhood: NeighbourhoodArg,
}

#[derive(Debug, Args)]
struct FileArgs {
    /// Parameter file (JSON, from --save-params).
    params: PathBuf,
    #[command(flatten)]
    common: CommonArgs,
}

/// Runs `spectex simulate`.
pub fn simulate(cmd: &SimulateCommand) -> Result<()> {
    let (common, spec) = match &cmd.kind {
        SimulationKind::GrayScott(a) => {
            let preset = match a.preset {
                PresetName::Spots => GrayScottPreset::Spots,
                PresetName::Stripes => GrayScottPreset::Stripes,
                PresetName::Mazes => GrayScottPreset::Mazes,
                PresetName::Holes => GrayScottPreset::Holes,
            };
            let mut p = GrayScott::preset(preset);
            let (w, h) = size(&a.common)?;
            // 64 patches per 256² (one per 32² pixels on average), at least one.
            p.patches = ((u64::from(w) * u64::from(h)) / 1024).clamp(1, 65_536) as u32;
            set(&mut p.feed, a.feed);
            set(&mut p.kill, a.kill);
            set(&mut p.du, a.du);
            set(&mut p.dv, a.dv);
            set(&mut p.dt, a.dt);
            set(&mut p.patches, a.patches);
            set(&mut p.patch_size, a.patch_size);
            let spec = spec_for(
                &a.common,
                GrayScott::DEFAULT_STEPS,
                Simulation::GrayScott(p),
            )?;
            (&a.common, spec)
        }
        SimulationKind::SwiftHohenberg(a) => {
            let mut p = SwiftHohenberg::STRIPES;
            set(&mut p.r, a.r);
            set(&mut p.g, a.g);
            set(&mut p.wavelength, a.wavelength);
            set(&mut p.dt, a.dt);
            let sim = Simulation::SwiftHohenberg(p);
            (
                &a.common,
                spec_for(&a.common, SwiftHohenberg::DEFAULT_STEPS, sim)?,
            )
        }
        SimulationKind::Life(a) => {
            let sim = Simulation::Life(LifeLike {
                rule: a.rule.clone(),
                density: a.density,
            });
            (
                &a.common,
                spec_for(&a.common, LifeLike::DEFAULT_STEPS, sim)?,
            )
        }
        SimulationKind::Elementary(a) => {
            let sim = Simulation::Elementary(Elementary {
                rule: a.rule,
                single: a.single,
                density: a.density,
            });
            (&a.common, spec_for(&a.common, 0, sim)?)
        }
        SimulationKind::Cyclic(a) => {
            let sim = Simulation::Cyclic(Cyclic {
                states: a.states,
                threshold: a.threshold,
                neighbourhood: model_of(&NEIGHBOURHOODS, &a.neighbourhood),
            });
            (&a.common, spec_for(&a.common, Cyclic::DEFAULT_STEPS, sim)?)
        }
        SimulationKind::File(a) => {
            let text = std::fs::read_to_string(&a.params)
                .with_context(|| format!("cannot read '{}'", a.params.display()))?;
            let mut spec = spec_from_json(&text).with_context(|| {
                format!("'{}' is not a valid parameter file", a.params.display())
            })?;
            if let Some((w, h)) = a.common.size {
                (spec.width, spec.height) = (side(w, "width")?, side(h, "height")?);
            }
            set(&mut spec.steps, a.common.steps);
            set(&mut spec.seed, a.common.seed);
            (&a.common, spec)
        }
    };
    run(common, &spec)
}

fn set<T: Copy>(field: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *field = v;
    }
}

fn side(v: usize, name: &str) -> Result<u32> {
    u32::try_from(v)
        .ok()
        .filter(|v| (1..=spectex_model::simulation::MAX_SIDE).contains(v))
        .ok_or_else(|| anyhow!("--size: {name} {v} is outside [1, 16384]"))
}

fn size(common: &CommonArgs) -> Result<(u32, u32)> {
    let (w, h) = common.size.unwrap_or((256, 256));
    Ok((side(w, "width")?, side(h, "height")?))
}

fn spec_for(common: &CommonArgs, default_steps: u32, sim: Simulation) -> Result<SimulationSpec> {
    let (w, h) = size(common)?;
    Ok(SimulationSpec::new(
        w,
        h,
        common.steps.unwrap_or(default_steps),
        common.seed.unwrap_or(spectex_model::DEFAULT_SEED),
        sim,
    ))
}

fn run(common: &CommonArgs, spec: &SimulationSpec) -> Result<()> {
    spec.validate().map_err(|e| anyhow!("{e}"))?;
    let format = io::check_output(&common.output, common.bit_depth)?;
    if common.every == 0 {
        bail!("--every 0 is outside [1, 10000000]; give the steps between frames");
    }
    if let Some(path) = &common.save_params {
        let json = spec_to_json(spec).map_err(|e| anyhow!("{e}"))?;
        io::write_text_atomically(path, &json)?;
    }
    let frame_format = match &common.frames {
        Some(dir) => {
            std::fs::create_dir_all(dir).with_context(|| {
                format!("cannot create the frame directory '{}'", dir.display())
            })?;
            Some(io::check_output(
                &dir.join("frame_000000.png"),
                common.bit_depth,
            )?)
        }
        None => None,
    };
    let mut sim = if common.gpu {
        let context = spectex_gpu::GpuContext::new()
            .map_err(|e| anyhow!("--gpu: {e}; or leave out --gpu to step on the CPU"))?;
        Stepper::Gpu(Box::new(
            spectex_gpu::simulate::GpuSimulator::new(&context, spec)
                .map_err(|e| anyhow!("--gpu: {e}"))?,
        ))
    } else {
        Stepper::Cpu(Box::new(Simulator::new(spec).map_err(|e| anyhow!("{e}"))?))
    };
    let total = Simulator::total_steps(spec);
    let bar = crate::progress::progress_bar(total, "simulating");
    let start = std::time::Instant::now();
    let write_frame = |sim: &Stepper| -> Result<()> {
        if let (Some(dir), Some(format)) = (&common.frames, frame_format) {
            let path = dir.join(format!("frame_{:06}.png", sim.steps_done()));
            save(&path, spec, &sim.grey()?, format)?;
        }
        Ok(())
    };
    write_frame(&sim)?;
    let every = u64::from(common.every);
    while sim.steps_done() < total {
        let chunk = (every - sim.steps_done() % every).min(total - sim.steps_done());
        sim.run(chunk, &|n| bar.set_position(n))?;
        if sim.steps_done() % every == 0 {
            write_frame(&sim)?;
        }
    }
    let grey = sim.grey()?;
    bar.finish_and_clear();
    let seconds = start.elapsed().as_secs_f64();
    let report = save(&common.output, spec, &grey, format)?;
    #[allow(clippy::print_stdout)] // reason: the command's result summary
    {
        println!(
            "wrote {} ({}×{}, {} {} steps, seed {}, {}: {:.1} steps/s)",
            common.output.display(),
            spec.width,
            spec.height,
            total,
            spec.simulation.name(),
            spec.seed,
            sim.device(),
            total as f64 / seconds.max(1e-9)
        );
    }
    crate::progress::note_clipping(report);
    Ok(())
}

fn save(
    path: &Path,
    spec: &SimulationSpec,
    grey: &[f32],
    format: io::Format,
) -> Result<io::WriteReport> {
    let (w, h) = (spec.width as usize, spec.height as usize);
    let pixels = Array3::from_shape_fn((1, h, w), |(_, y, x)| f64::from(grey[y * w + x]));
    io::save(path, &pixels, format)
}

/// The stepper `--gpu` chose.
enum Stepper {
    Cpu(Box<Simulator>),
    Gpu(Box<spectex_gpu::simulate::GpuSimulator>),
}

impl Stepper {
    fn steps_done(&self) -> u64 {
        match self {
            Stepper::Cpu(s) => s.steps_done(),
            Stepper::Gpu(s) => s.steps_done(),
        }
    }

    /// Runs `steps` steps, reporting the total done so far.
    fn run(&mut self, steps: u64, progress: &dyn Fn(u64)) -> Result<()> {
        match self {
            Stepper::Cpu(s) => {
                let before = s.steps_done();
                s.run(steps, &mut |n| progress(before + n));
                Ok(())
            }
            Stepper::Gpu(s) => {
                let before = s.steps_done();
                s.run(steps, &mut |n| progress(before + n))
                    .map_err(|e| anyhow!("--gpu: {e}"))
            }
        }
    }

    fn grey(&self) -> Result<Vec<f32>> {
        match self {
            Stepper::Cpu(s) => Ok(s.grey()),
            Stepper::Gpu(s) => s.grey().map_err(|e| anyhow!("--gpu: {e}")),
        }
    }

    fn device(&self) -> String {
        match self {
            Stepper::Cpu(_) => "CPU".to_owned(),
            Stepper::Gpu(s) => format!("GPU {}", s.adapter_name()),
        }
    }
}
