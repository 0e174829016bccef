//! Whole-grid simulations on the CPU (survey §2.1–2.2): Gray–Scott and Swift–Hohenberg
//! reaction–diffusion, Life-like, elementary and cyclic cellular automata, on a torus.
//!
//! The parameters, their validation, the seeded initial states and the grey mapping live in
//! [`spectex_model::simulation`] (shared with the GPU stepper in `spectex-gpu`); this crate
//! steps them. Rows are stepped in parallel with rayon, each cell from the previous state
//! only, so the result is the same bytes at any thread count.
//!
//! * Gray–Scott: forward Euler with the 5-point Laplacian in f32 (`gray_scott.rs`; the WGSL
//!   twin `shaders/simulate.wgsl` evaluates the same expression in the same order). Its
//!   diffusion is small (Pearson's rates are 0.21 and 0.10 pixel² per step), so an explicit
//!   step is cheaper than a spectral one at any stable time step.
//! * Swift–Hohenberg: semi-implicit in Fourier space (`swift_hohenberg.rs`, f64 on rustfft via
//!   [`spectex_spectrum::Fft2`]): `û ← (û + dt·N̂(u)) / (1 + dt (1 − |q|²)²)` with
//!   `N(u) = r u + g u² − u³`, the stiff fourth-order operator exact and implicit
//!   (unconditionally stable), the nonlinearity explicit.
//! * Cellular automata (`automata.rs`): integer states, the same on the GPU bit for bit.
//!
//! ```
//! use spectex_model::simulation::{Simulation, SimulationSpec, LifeLike};
//! use spectex_simulate::Simulator;
//!
//! let spec = SimulationSpec::new(32, 32, 10, 1, Simulation::Life(LifeLike::conway()));
//! let mut sim = Simulator::new(&spec)?;
//! sim.run(Simulator::total_steps(&spec), &mut |_| {});
//! let grey = sim.grey();
//! assert_eq!(grey.len(), 32 * 32);
//! assert!(grey.iter().all(|&g| g == 0.0 || g == 1.0));
//! # Ok::<(), spectex_simulate::SimulateError>(())
//! ```

mod automata;
mod gray_scott;
mod swift_hohenberg;

use spectex_model::ModelError;
use spectex_model::simulation::{InitialState, Simulation, SimulationSpec};

pub use gray_scott::gray_scott_cell;

/// Why a simulation cannot run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimulateError {
    /// A parameter is out of range (the field is named).
    #[error(transparent)]
    Invalid(#[from] ModelError),
    /// The grid has more cells than this machine can address.
    #[error("the grid of {cells} cells is larger than this machine can address")]
    TooLarge {
        /// Cells asked for.
        cells: u64,
    },
}

/// The state of a running simulation.
#[derive(Debug, Clone)]
enum State {
    GrayScott(gray_scott::GrayScottState),
    SwiftHohenberg(Box<swift_hohenberg::SwiftHohenbergState>),
    Cells(automata::CellState),
}

/// A simulation being stepped on the CPU.
#[derive(Debug, Clone)]
pub struct Simulator {
    spec: SimulationSpec,
    state: State,
    steps_done: u64,
}

impl Simulator {
    /// The simulation `spec` at its initial state.
    ///
    /// # Errors
    /// [`SimulateError::Invalid`] naming the first parameter out of range.
    pub fn new(spec: &SimulationSpec) -> Result<Self, SimulateError> {
        spec.validate()?;
        Self::from_state(spec, spec.initial_state())
    }

    /// The simulation `spec` from a given initial state (tests, cross-checks: a single mode, a
    /// glider); the state must be of the simulation's kind with `width × height` values
    /// (`width` for an elementary automaton).
    ///
    /// # Errors
    /// [`SimulateError::Invalid`] naming the first parameter out of range, or for a state of
    /// another kind or size.
    pub fn from_state(spec: &SimulationSpec, initial: InitialState) -> Result<Self, SimulateError> {
        spec.validate()?;
        let cells = spec.width as u64 * spec.height as u64;
        if usize::try_from(cells.saturating_mul(16)).is_err() {
            return Err(SimulateError::TooLarge { cells });
        }
        let (w, h) = (spec.width as usize, spec.height as usize);
        let expected = match spec.simulation {
            Simulation::Elementary(_) => w,
            _ => w * h,
        };
        let len = match &initial {
            InitialState::Fields { u, v } if u.len() == v.len() => u.len(),
            InitialState::Fields { .. } => usize::MAX,
            InitialState::Field(u) => u.len(),
            InitialState::Cells(c) => c.len(),
        };
        if len != expected {
            return Err(state_mismatch());
        }
        let state = match (&spec.simulation, initial) {
            (Simulation::GrayScott(p), InitialState::Fields { u, v }) => {
                State::GrayScott(gray_scott::GrayScottState::new(*p, w, h, u, v))
            }
            (Simulation::SwiftHohenberg(p), InitialState::Field(u)) => State::SwiftHohenberg(
                Box::new(swift_hohenberg::SwiftHohenbergState::new(*p, w, h, &u)),
            ),
            (sim, InitialState::Cells(cells)) => {
                State::Cells(automata::CellState::new(sim, w, h, spec.steps, cells)?)
            }
            _ => return Err(state_mismatch()),
        };
        Ok(Simulator {
            spec: spec.clone(),
            state,
            steps_done: 0,
        })
    }

    /// The spec this simulator runs.
    #[must_use]
    pub fn spec(&self) -> &SimulationSpec {
        &self.spec
    }

    /// Steps run so far.
    #[must_use]
    pub fn steps_done(&self) -> u64 {
        self.steps_done
    }

    /// Steps a full run takes: the spec's `steps`, and for an elementary automaton also the
    /// `height − 1` generations drawn after them.
    #[must_use]
    pub fn total_steps(spec: &SimulationSpec) -> u64 {
        match spec.simulation {
            Simulation::Elementary(_) => u64::from(spec.steps) + u64::from(spec.height) - 1,
            _ => u64::from(spec.steps),
        }
    }

    /// Advances one step.
    pub fn step(&mut self) {
        match &mut self.state {
            State::GrayScott(s) => s.step(),
            State::SwiftHohenberg(s) => s.step(),
            State::Cells(s) => s.step(),
        }
        self.steps_done += 1;
    }

    /// Advances `steps` steps, calling `on_step` with the number done after each.
    pub fn run(&mut self, steps: u64, on_step: &mut dyn FnMut(u64)) {
        for i in 0..steps {
            self.step();
            on_step(i + 1);
        }
    }

    /// The image shown for the current state, row-major, `width × height` values in `[0, 1]`
    /// (Swift–Hohenberg may exceed it slightly: [`spectex_model::simulation::swift_hohenberg_grey`]).
    /// Gray–Scott shows `u`.
    #[must_use]
    pub fn grey(&self) -> Vec<f32> {
        match &self.state {
            State::GrayScott(s) => s.u.clone(),
            State::SwiftHohenberg(s) => s.grey(),
            State::Cells(s) => s.grey(&self.spec.simulation),
        }
    }

    /// The raw floating-point fields (Gray–Scott: `u` then `v`; Swift–Hohenberg: `u` as f32),
    /// or `None` for a cellular automaton.
    #[must_use]
    pub fn fields(&self) -> Option<Vec<Vec<f32>>> {
        match &self.state {
            State::GrayScott(s) => Some(vec![s.u.clone(), s.v.clone()]),
            State::SwiftHohenberg(s) => Some(vec![s.u.iter().map(|&u| u as f32).collect()]),
            State::Cells(_) => None,
        }
    }

    /// The cell states of a cellular automaton (an elementary one: the image of drawn rows),
    /// or `None` for a reaction–diffusion.
    #[must_use]
    pub fn cells(&self) -> Option<&[u32]> {
        match &self.state {
            State::Cells(s) => Some(s.cells()),
            _ => None,
        }
    }
}

/// An initial state of another simulation than the spec's (from [`Simulator::from_state`];
/// `SimulationSpec::initial_state` always matches), reported rather than panicking.
fn state_mismatch() -> SimulateError {
    SimulateError::Invalid(ModelError::OutOfRange {
        field: "initial state".to_owned(),
        value: f64::NAN,
        range: "a state of the simulation's own kind and grid size",
    })
}
