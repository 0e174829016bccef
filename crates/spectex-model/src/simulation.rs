//! Whole-grid simulations (survey §2.1–2.2): their parameters, presets, validation, seeded
//! initial states and display mapping, shared by the CPU stepper (`spectex-simulate`) and the
//! GPU one (`spectex-gpu`), which therefore start from the same bits.
//!
//! Unlike a [`crate::Model`], a simulation is not pointwise: its state is a whole grid on a
//! torus (periodic boundaries), advanced step by step. A [`SimulationSpec`] (grid size, steps,
//! seed and one [`Simulation`]) is a versioned JSON file like a model file ([`spec_to_json`],
//! [`spec_from_json`]).
//!
//! * [`GrayScott`] (Pearson 1993, "Complex patterns in a simple system"):
//!   `∂u/∂t = D_u ∇²u − u v² + F (1 − u)`, `∂v/∂t = D_v ∇²v + u v² − (F + k) v` (the survey's
//!   eq. 2 prints the reaction signs of `v` reversed). Forward Euler with the 5-point
//!   Laplacian, in pixel units; the defaults are Pearson's `D_u = 2·10⁻⁵`, `D_v = 10⁻⁵` on his
//!   grid of 256 points over a side 2.5 (`D·(256/2.5)²` per pixel², time step 1).
//! * [`SwiftHohenberg`]: `∂u/∂t = r u − (1 + ∇²)² u + g u² − u³`, with lengths scaled so that
//!   the critical wavelength `2π` is [`SwiftHohenberg::wavelength`] pixels.
//! * [`LifeLike`]: a Life-like rule as a `B…/S…` string (Conway's is `B3/S23`), Moore
//!   neighbourhood.
//! * [`Elementary`]: Wolfram's elementary automata (rule 0–255), drawn as rows over time.
//! * [`Cyclic`]: Griffeath's cyclic cellular automaton (n states; a cell in state s moves to
//!   s + 1 mod n when at least `threshold` neighbours are in state s + 1 mod n).
//!
//! Randomness: the initial states draw from the randomness contract
//! ([`crate::random::cell_hash`]) with the layers named by the `LAYER_*` constants here, per
//! pixel, so they do not depend on thread count or tiling.
//!
//! ```
//! use spectex_model::simulation::{GrayScott, GrayScottPreset, Simulation, SimulationSpec};
//!
//! let spec = SimulationSpec::new(64, 64, 100, 7, Simulation::GrayScott(GrayScott::preset(GrayScottPreset::Spots)));
//! spec.validate()?;
//! let json = spectex_model::simulation::spec_to_json(&spec)?;
//! assert_eq!(spectex_model::simulation::spec_from_json(&json)?, spec);
//! # Ok::<(), spectex_model::ModelError>(())
//! ```

use serde::{Deserialize, Serialize};

use crate::error::{ModelError, check_range};
use crate::random::{Prng, cell_hash, layer_key, unit_f32};

/// Random layer of the Gray–Scott patch positions (a PRNG seeded with its layer key).
pub const LAYER_PATCHES: u32 = 0x5100;
/// Random layer of the per-pixel noise added to `u` (Gray–Scott, Swift–Hohenberg).
pub const LAYER_NOISE_U: u32 = 0x5101;
/// Random layer of the per-pixel noise added to `v` (Gray–Scott).
pub const LAYER_NOISE_V: u32 = 0x5102;
/// Random layer of the initial cells of the cellular automata.
pub const LAYER_CELLS: u32 = 0x5103;

/// Largest grid side.
pub const MAX_SIDE: u32 = 16_384;
/// Largest number of steps.
pub const MAX_STEPS: u32 = 10_000_000;

/// The `schema_version` of simulation files this build writes and reads.
pub const SIMULATION_SCHEMA_VERSION: u32 = 1;

/// A simulation run: grid size, steps, seed and the simulation's parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSpec {
    /// Grid width in cells (pixels), 1 to [`MAX_SIDE`].
    pub width: u32,
    /// Grid height in cells (for [`Elementary`], the number of generations drawn).
    pub height: u32,
    /// Steps to run (for [`Elementary`], generations run before the first row drawn).
    pub steps: u32,
    /// Seed of the initial state.
    pub seed: u32,
    /// What is simulated.
    pub simulation: Simulation,
}

/// One of the simulations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum Simulation {
    /// Gray–Scott reaction–diffusion.
    GrayScott(GrayScott),
    /// Swift–Hohenberg equation.
    SwiftHohenberg(SwiftHohenberg),
    /// A Life-like cellular automaton.
    Life(LifeLike),
    /// An elementary (one-dimensional) cellular automaton.
    Elementary(Elementary),
    /// A cyclic cellular automaton.
    Cyclic(Cyclic),
}

impl Simulation {
    /// The name of the simulation (its JSON tag and `spectex simulate` subcommand, with `-`).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Simulation::GrayScott(_) => "gray-scott",
            Simulation::SwiftHohenberg(_) => "swift-hohenberg",
            Simulation::Life(_) => "life",
            Simulation::Elementary(_) => "elementary",
            Simulation::Cyclic(_) => "cyclic",
        }
    }
}

/// Gray–Scott parameters (pixel units, time step `dt`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GrayScott {
    /// Feed rate F, in [0, 0.1].
    pub feed: f32,
    /// Kill rate k, in [0, 0.1].
    pub kill: f32,
    /// Diffusion rate of u in pixels² per unit time; `du·dt` at most 0.25 (explicit stability).
    pub du: f32,
    /// Diffusion rate of v in pixels² per unit time; `dv·dt` at most 0.25.
    pub dv: f32,
    /// Time step, in (0, 2].
    pub dt: f32,
    /// Number of square patches set to Pearson's perturbed state (u = 1/2, v = 1/4), 0 to 65536.
    pub patches: u32,
    /// Side of a patch in pixels, 1 to 1024.
    pub patch_size: u32,
    /// Amplitude of the uniform noise added to u and v at every pixel (Pearson: 0.01), in [0, 0.5].
    pub noise: f32,
}

/// Named Gray–Scott parameter pairs: widely used (F, k) points inside Pearson's 1993 regions
/// (his Fig. 3 map), with his diffusion rates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GrayScottPreset {
    /// Self-replicating spots (Pearson's λ/κ boundary, "mitosis"): F = 0.0367, k = 0.0649.
    Spots,
    /// Stripes growing into coral-like bands (Pearson's μ region edge): F = 0.0545, k = 0.062.
    Stripes,
    /// Labyrinths (Pearson's κ/η): F = 0.029, k = 0.057.
    Mazes,
    /// Holes, negative spots in a v-rich sea (Pearson's ι region): F = 0.039, k = 0.058.
    Holes,
}

impl GrayScottPreset {
    /// Every preset with its name.
    pub const ALL: [(&'static str, GrayScottPreset); 4] = [
        ("spots", GrayScottPreset::Spots),
        ("stripes", GrayScottPreset::Stripes),
        ("mazes", GrayScottPreset::Mazes),
        ("holes", GrayScottPreset::Holes),
    ];

    /// (F, k) of the preset.
    #[must_use]
    pub fn feed_kill(self) -> (f32, f32) {
        match self {
            GrayScottPreset::Spots => (0.0367, 0.0649),
            GrayScottPreset::Stripes => (0.0545, 0.062),
            GrayScottPreset::Mazes => (0.029, 0.057),
            GrayScottPreset::Holes => (0.039, 0.058),
        }
    }
}

impl GrayScott {
    /// Pearson's diffusion rate of u per pixel²: `2·10⁻⁵ · (256 / 2.5)²`.
    pub const PEARSON_DU: f32 = 0.209_715_2;
    /// Pearson's diffusion rate of v per pixel²: `10⁻⁵ · (256 / 2.5)²`.
    pub const PEARSON_DV: f32 = 0.104_857_6;
    /// Default number of steps of `spectex simulate gray-scott`.
    pub const DEFAULT_STEPS: u32 = 8000;

    /// The preset's (F, k) with Pearson's diffusion rates and time step 1, 1 patch of 10×10
    /// pixels per 32×32 pixels of a 256² grid (64 patches), noise 0.01.
    #[must_use]
    pub fn preset(preset: GrayScottPreset) -> Self {
        let (feed, kill) = preset.feed_kill();
        GrayScott {
            feed,
            kill,
            du: Self::PEARSON_DU,
            dv: Self::PEARSON_DV,
            dt: 1.0,
            patches: 64,
            patch_size: 10,
            noise: 0.01,
        }
    }

    fn validate(&self, at: &str) -> Result<(), ModelError> {
        let f = |name: &str| format!("{at}.{name}");
        check_range(|| f("feed"), f64::from(self.feed), 0.0, 0.1, "[0, 0.1]")?;
        check_range(|| f("kill"), f64::from(self.kill), 0.0, 0.1, "[0, 0.1]")?;
        check_range(|| f("dt"), f64::from(self.dt), 1e-6, 2.0, "(0, 2]")?;
        let dt = f64::from(self.dt);
        check_range(
            || f("du"),
            f64::from(self.du),
            0.0,
            0.25 / dt,
            "[0, 0.25/dt] (explicit stability)",
        )?;
        check_range(
            || f("dv"),
            f64::from(self.dv),
            0.0,
            0.25 / dt,
            "[0, 0.25/dt] (explicit stability)",
        )?;
        check_range(
            || f("patches"),
            f64::from(self.patches),
            0.0,
            65_536.0,
            "[0, 65536]",
        )?;
        check_range(
            || f("patch_size"),
            f64::from(self.patch_size),
            1.0,
            1024.0,
            "[1, 1024]",
        )?;
        check_range(|| f("noise"), f64::from(self.noise), 0.0, 0.5, "[0, 0.5]")
    }
}

/// Swift–Hohenberg parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SwiftHohenberg {
    /// Bifurcation parameter r, in [−1, 1]: patterns grow for r > 0.
    pub r: f32,
    /// Quadratic coefficient g, in [−2, 2] (0: stripes; about 1 with small r: hexagonal spots).
    pub g: f32,
    /// Critical wavelength in pixels, in [2, 1024].
    pub wavelength: f32,
    /// Time step, in (0, 10]; the linear operator is implicit, the nonlinearity explicit.
    pub dt: f32,
    /// Amplitude of the uniform initial noise of u, in (0, 1].
    pub noise: f32,
}

impl SwiftHohenberg {
    /// Default number of steps of `spectex simulate swift-hohenberg`.
    pub const DEFAULT_STEPS: u32 = 400;
    /// Stripes: r = 0.3, g = 0, wavelength 12, dt = 0.5, noise 0.1.
    pub const STRIPES: SwiftHohenberg = SwiftHohenberg {
        r: 0.3,
        g: 0.0,
        wavelength: 12.0,
        dt: 0.5,
        noise: 0.1,
    };

    fn validate(&self, at: &str) -> Result<(), ModelError> {
        let f = |name: &str| format!("{at}.{name}");
        check_range(|| f("r"), f64::from(self.r), -1.0, 1.0, "[-1, 1]")?;
        check_range(|| f("g"), f64::from(self.g), -2.0, 2.0, "[-2, 2]")?;
        check_range(
            || f("wavelength"),
            f64::from(self.wavelength),
            2.0,
            1024.0,
            "[2, 1024]",
        )?;
        check_range(|| f("dt"), f64::from(self.dt), 1e-6, 10.0, "(0, 10]")?;
        check_range(|| f("noise"), f64::from(self.noise), 1e-6, 1.0, "(0, 1]")
    }
}

/// A Life-like rule.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LifeLike {
    /// The rule, `B<digits>/S<digits>` with digits 0–8 (e.g. `B3/S23`, `B36/S23`).
    pub rule: String,
    /// Share of live cells in the initial state, in [0, 1].
    pub density: f32,
}

impl LifeLike {
    /// Default number of steps of `spectex simulate life`.
    pub const DEFAULT_STEPS: u32 = 200;
    /// Conway's Game of Life, initial density 0.35.
    #[must_use]
    pub fn conway() -> Self {
        LifeLike {
            rule: "B3/S23".to_owned(),
            density: 0.35,
        }
    }

    /// The birth and survival masks: bit `n` set when `n` live neighbours give birth (survival).
    ///
    /// # Errors
    /// [`ModelError::SimulationRule`] for a string not of the form `B<digits 0-8>/S<digits 0-8>`.
    pub fn masks(&self) -> Result<(u16, u16), ModelError> {
        parse_bs(&self.rule).ok_or_else(|| ModelError::SimulationRule {
            field: "simulation.life.rule".to_owned(),
            value: self.rule.clone(),
            expected: "B<digits 0-8>/S<digits 0-8>, e.g. B3/S23",
        })
    }
}

fn parse_bs(rule: &str) -> Option<(u16, u16)> {
    let (b, s) = rule.trim().split_once('/')?;
    let digits = |part: &str, letter: char| -> Option<u16> {
        let rest = part
            .strip_prefix(letter)
            .or_else(|| part.strip_prefix(letter.to_ascii_lowercase()))?;
        let mut mask = 0u16;
        for c in rest.chars() {
            let d = c.to_digit(10).filter(|d| *d <= 8)?;
            if mask & (1 << d) != 0 {
                return None;
            }
            mask |= 1 << d;
        }
        Some(mask)
    };
    Some((digits(b, 'B')?, digits(s, 'S')?))
}

/// An elementary cellular automaton.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Elementary {
    /// Wolfram's rule number, 0 to 255: bit `4l + 2c + r` is the new state of a cell whose
    /// left, own and right states are `l`, `c`, `r`.
    pub rule: u32,
    /// Start from one live cell in the middle of the first row instead of a random row.
    pub single: bool,
    /// Share of live cells in a random first row, in [0, 1].
    pub density: f32,
}

impl Elementary {
    /// Rule 30 from a random row of density 1/2.
    pub const RULE_30: Elementary = Elementary {
        rule: 30,
        single: false,
        density: 0.5,
    };
}

/// Neighbourhood of a cyclic automaton.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Neighbourhood {
    /// The 8 cells around.
    Moore,
    /// The 4 cells sharing a side.
    VonNeumann,
}

/// A cyclic cellular automaton (Griffeath).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cyclic {
    /// Number of states, 2 to 255.
    pub states: u32,
    /// Neighbours in the successor state needed to advance, 1 to the neighbourhood's size.
    pub threshold: u32,
    /// Which neighbours count.
    pub neighbourhood: Neighbourhood,
}

impl Cyclic {
    /// Default number of steps of `spectex simulate cyclic`.
    pub const DEFAULT_STEPS: u32 = 300;
    /// Griffeath's "313" rule: 3 states, threshold 3, Moore neighbourhood (spirals).
    pub const SPIRALS: Cyclic = Cyclic {
        states: 3,
        threshold: 3,
        neighbourhood: Neighbourhood::Moore,
    };
}

impl SimulationSpec {
    /// A spec; check it with [`SimulationSpec::validate`].
    #[must_use]
    pub fn new(width: u32, height: u32, steps: u32, seed: u32, simulation: Simulation) -> Self {
        SimulationSpec {
            width,
            height,
            steps,
            seed,
            simulation,
        }
    }

    /// Checks every field, naming the first one out of range.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::SimulationRule`] with the field's path.
    pub fn validate(&self) -> Result<(), ModelError> {
        let side = |v: u32, name: &'static str| {
            check_range(
                || name.to_owned(),
                f64::from(v),
                1.0,
                f64::from(MAX_SIDE),
                "[1, 16384]",
            )
        };
        side(self.width, "width")?;
        side(self.height, "height")?;
        check_range(
            || "steps".to_owned(),
            f64::from(self.steps),
            0.0,
            f64::from(MAX_STEPS),
            "[0, 10000000]",
        )?;
        match &self.simulation {
            Simulation::GrayScott(p) => p.validate("simulation.gray_scott"),
            Simulation::SwiftHohenberg(p) => p.validate("simulation.swift_hohenberg"),
            Simulation::Life(p) => {
                p.masks()?;
                check_range(
                    || "simulation.life.density".to_owned(),
                    f64::from(p.density),
                    0.0,
                    1.0,
                    "[0, 1]",
                )
            }
            Simulation::Elementary(p) => {
                check_range(
                    || "simulation.elementary.rule".to_owned(),
                    f64::from(p.rule),
                    0.0,
                    255.0,
                    "[0, 255]",
                )?;
                check_range(
                    || "simulation.elementary.density".to_owned(),
                    f64::from(p.density),
                    0.0,
                    1.0,
                    "[0, 1]",
                )
            }
            Simulation::Cyclic(p) => {
                check_range(
                    || "simulation.cyclic.states".to_owned(),
                    f64::from(p.states),
                    2.0,
                    255.0,
                    "[2, 255]",
                )?;
                let (max, range) = match p.neighbourhood {
                    Neighbourhood::Moore => (8.0, "[1, 8] (Moore)"),
                    Neighbourhood::VonNeumann => (4.0, "[1, 4] (von Neumann)"),
                };
                check_range(
                    || "simulation.cyclic.threshold".to_owned(),
                    f64::from(p.threshold),
                    1.0,
                    max,
                    range,
                )
            }
        }
    }

    /// Cells in the grid.
    #[must_use]
    pub fn cells(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The initial state, as both steppers start from it (row-major, `width` per row).
    /// For [`Elementary`] it is the first row only (`width` cells).
    #[must_use]
    pub fn initial_state(&self) -> InitialState {
        let (w, h, seed) = (self.width, self.height, self.seed);
        let unit =
            |x: u32, y: u32, layer: u32| unit_f32(cell_hash(x as i32, y as i32, layer, seed));
        let grid = |f: &dyn Fn(u32, u32) -> f32| -> Vec<f32> {
            (0..h)
                .flat_map(|y| (0..w).map(move |x| (x, y)))
                .map(|(x, y)| f(x, y))
                .collect()
        };
        match &self.simulation {
            Simulation::GrayScott(p) => {
                let mut inside = vec![false; self.cells()];
                let mut prng = Prng::new(layer_key(LAYER_PATCHES, seed));
                for _ in 0..p.patches {
                    let x0 = prng.next_u32() % w;
                    let y0 = prng.next_u32() % h;
                    for dy in 0..p.patch_size.min(h) {
                        for dx in 0..p.patch_size.min(w) {
                            let (x, y) = ((x0 + dx) % w, (y0 + dy) % h);
                            inside[(y * w + x) as usize] = true;
                        }
                    }
                }
                let noise = |x, y, layer| p.noise * (2.0 * unit(x, y, layer) - 1.0);
                let at = |x: u32, y: u32| inside[(y * w + x) as usize];
                let u = grid(&|x, y| {
                    let base = if at(x, y) { 0.5 } else { 1.0 };
                    (base + noise(x, y, LAYER_NOISE_U)).clamp(0.0, 1.0)
                });
                let v = grid(&|x, y| {
                    let base = if at(x, y) { 0.25 } else { 0.0 };
                    (base + noise(x, y, LAYER_NOISE_V)).clamp(0.0, 1.0)
                });
                InitialState::Fields { u, v }
            }
            Simulation::SwiftHohenberg(p) => {
                let u = grid(&|x, y| p.noise * (2.0 * unit(x, y, LAYER_NOISE_U) - 1.0));
                InitialState::Field(u)
            }
            Simulation::Life(p) => InitialState::Cells(
                (0..h)
                    .flat_map(|y| (0..w).map(move |x| (x, y)))
                    .map(|(x, y)| u32::from(unit(x, y, LAYER_CELLS) < p.density))
                    .collect(),
            ),
            Simulation::Elementary(p) => InitialState::Cells(
                (0..w)
                    .map(|x| {
                        u32::from(if p.single {
                            x == w / 2
                        } else {
                            unit(x, 0, LAYER_CELLS) < p.density
                        })
                    })
                    .collect(),
            ),
            Simulation::Cyclic(p) => InitialState::Cells(
                (0..h)
                    .flat_map(|y| (0..w).map(move |x| (x, y)))
                    .map(|(x, y)| {
                        let bits = cell_hash(x as i32, y as i32, LAYER_CELLS, seed);
                        ((u64::from(bits) * u64::from(p.states)) >> 32) as u32
                    })
                    .collect(),
            ),
        }
    }
}

/// A simulation's initial state.
#[derive(Debug, Clone, PartialEq)]
pub enum InitialState {
    /// Gray–Scott's two concentrations.
    Fields {
        /// Concentration of U.
        u: Vec<f32>,
        /// Concentration of V.
        v: Vec<f32>,
    },
    /// Swift–Hohenberg's field.
    Field(Vec<f32>),
    /// Cell states of a cellular automaton.
    Cells(Vec<u32>),
}

/// The grey value shown for a Swift–Hohenberg value `u`: `0.5 + u / (2 A)` with
/// `A = 2 √(r/3)`, the amplitude of stripes near onset (g = 0), so stripes span about [0, 1].
#[must_use]
pub fn swift_hohenberg_grey(p: &SwiftHohenberg, u: f32) -> f32 {
    let amplitude = 2.0 * (p.r.max(1e-3) / 3.0).sqrt();
    0.5 + u / (2.0 * amplitude)
}

/// The grey value shown for a cell state: elementary automata as Wolfram draws them (live
/// cells black on white), Life live cells white, a cyclic state `s` as `s / (n − 1)`.
#[must_use]
pub fn cell_grey(simulation: &Simulation, state: u32) -> f32 {
    match simulation {
        Simulation::Elementary(_) => 1.0 - state as f32,
        Simulation::Cyclic(p) => state as f32 / (p.states - 1) as f32,
        _ => state as f32,
    }
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecFile {
    schema_version: u32,
    #[serde(flatten)]
    spec: SimulationSpec,
}

/// A spec as a versioned JSON file (validated first).
///
/// # Errors
/// A field out of range.
pub fn spec_to_json(spec: &SimulationSpec) -> Result<String, ModelError> {
    spec.validate()?;
    Ok(serde_json::to_string_pretty(&SpecFile {
        schema_version: SIMULATION_SCHEMA_VERSION,
        spec: spec.clone(),
    })?)
}

/// Reads a spec file: `schema_version` first, then the shape, then every value.
///
/// # Errors
/// Malformed JSON, an unsupported `schema_version`, an unknown field, or a value out of range.
pub fn spec_from_json(text: &str) -> Result<SimulationSpec, ModelError> {
    let value: serde_json::Value = serde_json::from_str(text)?;
    let version = value
        .get("schema_version")
        .and_then(serde_json::Value::as_u64);
    if version != Some(u64::from(SIMULATION_SCHEMA_VERSION)) {
        return Err(ModelError::SchemaVersion {
            found: version.map_or_else(|| "missing".to_owned(), |v| v.to_string()),
            supported: SIMULATION_SCHEMA_VERSION.to_string(),
        });
    }
    let mut map = value;
    if let Some(obj) = map.as_object_mut() {
        obj.remove("schema_version");
    }
    let spec: SimulationSpec = serde_json::from_value(map)?;
    spec.validate()?;
    Ok(spec)
}

#[cfg(feature = "unit-tests")]
#[doc(hidden)]
#[allow(clippy::unwrap_used, reason = "a test fails loudly")]
pub mod tests {
    use super::*;

    pub fn bs_rules_parse_and_bad_ones_name_the_field() {
        let life = |rule: &str| LifeLike {
            rule: rule.to_owned(),
            density: 0.5,
        };
        assert_eq!(
            life("B3/S23").masks().ok(),
            Some((1 << 3, (1 << 2) | (1 << 3)))
        );
        assert_eq!(life("b36/s23").masks().ok(), Some((0b1001000, 0b1100)));
        assert_eq!(life("B/S").masks().ok(), Some((0, 0)));
        for bad in ["B9/S23", "B3S23", "S23/B3", "B33/S2", "", "B3/S2x"] {
            let e = life(bad)
                .masks()
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default();
            assert!(e.contains("simulation.life.rule"), "{bad}: {e}");
        }
    }

    pub fn out_of_range_fields_are_named() {
        let mut gs = GrayScott::preset(GrayScottPreset::Spots);
        gs.du = 0.3;
        let spec = SimulationSpec::new(8, 8, 1, 0, Simulation::GrayScott(gs));
        let e = spec
            .validate()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(
            e.contains("simulation.gray_scott.du") && e.contains("0.25/dt"),
            "{e}"
        );
        let spec = SimulationSpec::new(0, 8, 1, 0, Simulation::Cyclic(Cyclic::SPIRALS));
        let e = spec
            .validate()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.contains("width"), "{e}");
        let mut c = Cyclic::SPIRALS;
        c.neighbourhood = Neighbourhood::VonNeumann;
        c.threshold = 5;
        let spec = SimulationSpec::new(8, 8, 1, 0, Simulation::Cyclic(c));
        let e = spec
            .validate()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(
            e.contains("simulation.cyclic.threshold") && e.contains("[1, 4]"),
            "{e}"
        );
    }

    pub fn files_round_trip_and_check_their_version() {
        let spec = SimulationSpec::new(
            16,
            9,
            5,
            3,
            Simulation::Life(LifeLike {
                rule: "B36/S23".to_owned(),
                density: 0.25,
            }),
        );
        let json = spec_to_json(&spec).unwrap_or_default();
        assert_eq!(spec_from_json(&json).ok(), Some(spec));
        let old = json.replace("\"schema_version\": 1", "\"schema_version\": 7");
        assert!(matches!(
            spec_from_json(&old),
            Err(ModelError::SchemaVersion { .. })
        ));
    }

    /// Pearson's rates: `D·(256/2.5)²`, computed here in f64.
    pub fn pearson_rates_per_pixel() {
        let scale = (256.0f64 / 2.5).powi(2);
        assert!((f64::from(GrayScott::PEARSON_DU) - 2e-5 * scale).abs() < 1e-7);
        assert!((f64::from(GrayScott::PEARSON_DV) - 1e-5 * scale).abs() < 1e-7);
    }
}
