//! Cellular automata on a torus: Life-like (B/S rules, Moore neighbourhood), elementary
//! (Wolfram rule numbers, drawn as rows over time) and cyclic (Griffeath). Integer states, so
//! the GPU (`shaders/simulate.wgsl`) must give the same cells exactly.

use rayon::prelude::*;
use spectex_model::simulation::{Neighbourhood, Simulation, cell_grey};

use crate::SimulateError;

#[derive(Debug, Clone)]
enum Rule {
    Life {
        birth: u16,
        survive: u16,
    },
    Elementary {
        rule: u32,
        row: Vec<u32>,
        next: Vec<u32>,
        generation: u64,
        first_drawn: u64,
    },
    Cyclic {
        states: u32,
        threshold: u32,
        moore: bool,
    },
}

/// The cells (for an elementary automaton: the image of drawn generations) and the rule.
#[derive(Debug, Clone)]
pub(crate) struct CellState {
    rule: Rule,
    width: usize,
    height: usize,
    cells: Vec<u32>,
    next: Vec<u32>,
}

/// The new state of an elementary cell from its left, own and right states (Wolfram's numbering).
#[must_use]
pub(crate) fn elementary_cell(rule: u32, l: u32, c: u32, r: u32) -> u32 {
    (rule >> (4 * l + 2 * c + r)) & 1
}

impl CellState {
    pub(crate) fn new(
        sim: &Simulation,
        width: usize,
        height: usize,
        steps: u32,
        initial: Vec<u32>,
    ) -> Result<Self, SimulateError> {
        let n = width * height;
        let (rule, cells) = match sim {
            Simulation::Life(p) => {
                let (birth, survive) = p.masks()?;
                (Rule::Life { birth, survive }, initial)
            }
            Simulation::Elementary(p) => {
                let mut cells = vec![0; n];
                if steps == 0 {
                    cells[..width].copy_from_slice(&initial);
                }
                let rule = Rule::Elementary {
                    rule: p.rule,
                    next: vec![0; width],
                    row: initial,
                    generation: 0,
                    first_drawn: u64::from(steps),
                };
                (rule, cells)
            }
            Simulation::Cyclic(p) => (
                Rule::Cyclic {
                    states: p.states,
                    threshold: p.threshold,
                    moore: p.neighbourhood == Neighbourhood::Moore,
                },
                initial,
            ),
            Simulation::GrayScott(_) | Simulation::SwiftHohenberg(_) => {
                return Err(crate::state_mismatch());
            }
        };
        Ok(CellState {
            rule,
            width,
            height,
            next: vec![0; cells.len()],
            cells,
        })
    }

    pub(crate) fn cells(&self) -> &[u32] {
        &self.cells
    }

    pub(crate) fn grey(&self, sim: &Simulation) -> Vec<f32> {
        self.cells.iter().map(|&c| cell_grey(sim, c)).collect()
    }

    pub(crate) fn step(&mut self) {
        let (w, h) = (self.width, self.height);
        match &mut self.rule {
            Rule::Elementary {
                rule,
                row,
                next,
                generation,
                first_drawn,
            } => {
                for x in 0..w {
                    let (l, r) = (row[(x + w - 1) % w], row[(x + 1) % w]);
                    next[x] = elementary_cell(*rule, l, row[x], r);
                }
                std::mem::swap(row, next);
                *generation += 1;
                if let Some(y) = generation.checked_sub(*first_drawn)
                    && (y as usize) < h
                {
                    let y = y as usize;
                    self.cells[y * w..(y + 1) * w].copy_from_slice(row);
                }
                return;
            }
            Rule::Life { .. } | Rule::Cyclic { .. } => {}
        }
        let cells = &self.cells;
        let rule = &self.rule;
        self.next
            .par_chunks_mut(w)
            .enumerate()
            .for_each(|(y, out)| {
                let (up, down) = ((y + h - 1) % h, (y + 1) % h);
                let row = |y: usize| &cells[y * w..(y + 1) * w];
                let (t, c, b) = (row(up), row(y), row(down));
                for x in 0..w {
                    let (l, r) = ((x + w - 1) % w, (x + 1) % w);
                    let sides = [c[l], c[r], t[x], b[x]];
                    let corners = [t[l], t[r], b[l], b[r]];
                    out[x] = match *rule {
                        Rule::Life { birth, survive } => {
                            let n: u32 = sides.iter().chain(&corners).sum();
                            let mask = if c[x] == 1 { survive } else { birth };
                            (u32::from(mask) >> n) & 1
                        }
                        Rule::Cyclic {
                            states,
                            threshold,
                            moore,
                        } => {
                            let succ = (c[x] + 1) % states;
                            let mut n = sides.iter().filter(|&&s| s == succ).count();
                            if moore {
                                n += corners.iter().filter(|&&s| s == succ).count();
                            }
                            if n as u32 >= threshold { succ } else { c[x] }
                        }
                        Rule::Elementary { .. } => c[x],
                    };
                }
            });
        std::mem::swap(&mut self.cells, &mut self.next);
    }
}
