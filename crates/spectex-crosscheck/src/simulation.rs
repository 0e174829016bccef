//! Cross-checking the simulations (`spectex-simulate` on the CPU against `spectex-gpu`'s
//! `GpuSimulator`), with the criterion each admits; every [`SimulationCheck`] names the one it
//! used:
//!
//! * **Exact** (cellular automata): integer states, the same rule: every cell equal after the
//!   spec's steps.
//! * **Pixelwise** (Gray–Scott, first [`PIXELWISE_STEPS`] steps): both start from the same
//!   bits; each step of each evaluator computes `u'` and `v'` with at most
//!   [`OPS_PER_CELL`] f32 operations whose intermediates are bounded by
//!   `B = 5·max(1, |u|, |v|)` (the neighbour sum is at most 4 max|u|; the reaction terms are
//!   smaller), so each evaluator is within `OPS_PER_CELL·B·2⁻²⁴` of the exact step from its
//!   own state, whatever it fuses: the two differ by at most `δ = 2·OPS_PER_CELL·B·2⁻²⁴` per
//!   step from equal states. The step map is Lipschitz in the max norm with constant
//!   `L = 1 + dt·(F + k + max(v² + 2|u v|))` (the row sums of its Jacobian's absolute values,
//!   with `4·D·dt ≤ 1`, which validation enforces), taken over states within the current
//!   bound of the CPU's. So `e₀ = 0`, `e_{n+1} = L_n e_n + δ_n` bounds `max |u_cpu − u_gpu|`
//!   and the same for `v`, computed along the CPU run.
//! * **Statistical** (Gray–Scott after the spec's steps, where chaos has separated the runs):
//!   the dominant wavelength from the peak ring of the radially summed power spectrum of `v`
//!   (the two peaks may differ by [`PEAK_RING_TOLERANCE`] ring: two realisations of one
//!   pattern family put their peak on the same or an adjacent integer ring of the DFT), and
//!   the fraction of area with `v` above [`AREA_THRESHOLD`], whose sampling spread for `M`
//!   independent pattern cells (`M = W·H / λ²`, λ the CPU's wavelength) is
//!   `σ = √(p(1 − p)/M)`: the GPU's fraction must be within `4σ + 1/M` of the CPU's.

use spectex_gpu::GpuContext;
use spectex_gpu::simulate::GpuSimulator;
use spectex_model::simulation::{Simulation, SimulationSpec};
use spectex_simulate::Simulator;

use crate::CrosscheckError;

/// Steps compared pixel by pixel.
pub const PIXELWISE_STEPS: u64 = 16;
/// f32 operations per Gray–Scott cell update (3 neighbour additions, then `− 4u`, `u·v·v`,
/// `du·lap`, `− uvv`, `1 − u`, `F·(…)`, `+`, `dt·(…)`, `u + …`: 14 for `u`, as many for `v`).
pub const OPS_PER_CELL: f64 = 14.0;
/// Rings the spectrum peaks may differ by.
pub const PEAK_RING_TOLERANCE: usize = 1;
/// Threshold of `v` for the area fraction (between Pearson's background v = 0 and pattern
/// values v ≈ 0.25–0.5).
pub const AREA_THRESHOLD: f32 = 0.2;

/// One check of a simulation: which criterion, whether it passed, and the numbers.
#[derive(Debug, Clone)]
pub struct SimulationCheck {
    /// `exact`, `pixelwise` or `statistical`.
    pub criterion: &'static str,
    /// Whether the GPU met the criterion.
    pub passed: bool,
    /// The measured values and their tolerances, in words.
    pub detail: String,
}

fn gpu_err(e: spectex_gpu::GpuError) -> CrosscheckError {
    CrosscheckError::Gpu(e)
}

fn sim_err(e: spectex_simulate::SimulateError) -> CrosscheckError {
    CrosscheckError::Simulation(e)
}

/// Runs `spec` on the CPU and on `context`'s GPU and judges them by the criteria above.
///
/// # Errors
/// A spec out of range, Swift–Hohenberg (no GPU stepper), or a device failure.
pub fn check_simulation(
    context: &GpuContext,
    spec: &SimulationSpec,
) -> Result<Vec<SimulationCheck>, CrosscheckError> {
    let mut cpu = Simulator::new(spec).map_err(sim_err)?;
    let mut gpu = GpuSimulator::new(context, spec).map_err(gpu_err)?;
    let total = Simulator::total_steps(spec);
    let Simulation::GrayScott(p) = spec.simulation else {
        cpu.run(total, &mut |_| {});
        gpu.run(total, &mut |_| {}).map_err(gpu_err)?;
        let (a, b) = (
            cpu.cells().unwrap_or_default().to_vec(),
            gpu.cells().map_err(gpu_err)?.unwrap_or_default(),
        );
        let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        let first = a.iter().zip(&b).position(|(x, y)| x != y);
        return Ok(vec![SimulationCheck {
            criterion: "exact",
            passed: differing == 0 && a.len() == b.len() && !a.is_empty(),
            detail: format!(
                "{} cells after {total} steps, {differing} differ{}",
                a.len(),
                first.map_or(String::new(), |i| format!(" (first at index {i})"))
            ),
        }]);
    };
    // Pixelwise: the per-cell bounds (e_u, e_v) along the CPU run.
    let pixel_steps = PIXELWISE_STEPS.min(total);
    let (w, h) = (spec.width as usize, spec.height as usize);
    let mut bound_u = vec![0.0f64; w * h];
    let mut bound_v = vec![0.0f64; w * h];
    for _ in 0..pixel_steps {
        let fields = cpu.fields().unwrap_or_default();
        (bound_u, bound_v) = step_bounds(&p, w, h, &fields[0], &fields[1], &bound_u, &bound_v);
        cpu.step();
    }
    let bound = bound_u
        .iter()
        .chain(&bound_v)
        .fold(0.0f64, |m, &e| m.max(e));
    gpu.run(pixel_steps, &mut |_| {}).map_err(gpu_err)?;
    let (a, b) = (
        cpu.fields().unwrap_or_default(),
        gpu.fields().map_err(gpu_err)?.unwrap_or_default(),
    );
    let max_err = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| {
            m.max((f64::from(*x) - f64::from(*y)).abs())
        });
    // Each cell against its own bound.
    let within = a.len() == b.len()
        && a.iter()
            .zip(&b)
            .zip([&bound_u, &bound_v])
            .all(|((x, y), e)| {
                x.iter()
                    .zip(y)
                    .zip(e)
                    .all(|((x, y), e)| (f64::from(*x) - f64::from(*y)).abs() <= *e)
            });
    let mut checks = vec![SimulationCheck {
        criterion: "pixelwise",
        passed: within,
        detail: format!(
            "first {pixel_steps} steps: max |cpu − gpu| = {max_err:.3e} over u and v, derived bound {bound:.3e}"
        ),
    }];
    // Statistical, after the whole run.
    cpu.run(total - pixel_steps, &mut |_| {});
    gpu.run(total - pixel_steps, &mut |_| {}).map_err(gpu_err)?;
    let cpu_v = cpu.fields().unwrap_or_default().swap_remove(1);
    let gpu_v = gpu
        .fields()
        .map_err(gpu_err)?
        .unwrap_or_default()
        .swap_remove(1);
    let (ring_cpu, ring_gpu) = (peak_ring(&cpu_v, w, h), peak_ring(&gpu_v, w, h));
    let wavelength = w.min(h) as f64 / ring_cpu.max(1) as f64;
    let area =
        |v: &[f32]| v.iter().filter(|&&x| x > AREA_THRESHOLD).count() as f64 / v.len() as f64;
    let (p_cpu, p_gpu) = (area(&cpu_v), area(&gpu_v));
    let cells = ((w * h) as f64 / (wavelength * wavelength)).max(1.0);
    let tolerance = 4.0 * (p_cpu * (1.0 - p_cpu) / cells).sqrt() + 1.0 / cells;
    checks.push(SimulationCheck {
        criterion: "statistical",
        passed: ring_cpu.abs_diff(ring_gpu) <= PEAK_RING_TOLERANCE
            && (p_cpu - p_gpu).abs() <= tolerance,
        detail: format!(
            "after {total} steps: spectrum peak ring {ring_cpu} (CPU) vs {ring_gpu} (GPU), \
             tolerance {PEAK_RING_TOLERANCE} (wavelength {wavelength:.1} px); area with v > \
             {AREA_THRESHOLD}: {p_cpu:.4} vs {p_gpu:.4}, tolerance {tolerance:.4}"
        ),
    });
    Ok(checks)
}

/// One step of the per-cell bounds on `|cpu − gpu|` (module doc): from the CPU's state
/// `(u, v)` and the bounds `(eu, ev)` before the step, the bounds after it,
///
/// ```text
/// eu' = |1 − 4 du dt − dt (v² + F)| eu + du dt Σ eu_nbr + 2 dt |u v| ev + δ
/// ev' = |1 − 4 dv dt + dt (2 u v − F − k)| ev + dv dt Σ ev_nbr + dt v² eu + δ
/// ```
///
/// the absolute row sums of the step's Jacobian, evaluated with `|u| + eu` and `|v| + ev` (the
/// mean-value point lies between the two states), and `δ = 2·OPS_PER_CELL·B·2⁻²⁴` with
/// `B = 5·max(1, |u| + eu, |v| + ev)` the magnitude of the step's intermediates.
fn step_bounds(
    p: &spectex_model::simulation::GrayScott,
    w: usize,
    h: usize,
    u: &[f32],
    v: &[f32],
    eu: &[f64],
    ev: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let (du, dv, dt) = (f64::from(p.du), f64::from(p.dv), f64::from(p.dt));
    let (f, k) = (f64::from(p.feed), f64::from(p.kill));
    let mut next_u = vec![0.0; w * h];
    let mut next_v = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let nbrs = [
                y * w + (x + w - 1) % w,
                y * w + (x + 1) % w,
                ((y + h - 1) % h) * w + x,
                ((y + 1) % h) * w + x,
            ];
            let su: f64 = nbrs.iter().map(|&j| eu[j]).sum();
            let sv: f64 = nbrs.iter().map(|&j| ev[j]).sum();
            let uu = f64::from(u[i]).abs() + eu[i];
            let vv = f64::from(v[i]).abs() + ev[i];
            let delta = 2.0 * OPS_PER_CELL * 5.0 * uu.max(vv).max(1.0) * 2f64.powi(-24);
            next_u[i] = (1.0 - 4.0 * du * dt - dt * (vv * vv + f)).abs() * eu[i]
                + du * dt * su
                + 2.0 * dt * uu * vv * ev[i]
                + delta;
            next_v[i] = (1.0 - 4.0 * dv * dt + dt * (2.0 * uu * vv - f - k)).abs() * ev[i]
                + dv * dt * sv
                + dt * vv * vv * eu[i]
                + delta;
        }
    }
    (next_u, next_v)
}

/// The ring (radius in DFT indices of the shorter side, rounded, 1 or more) holding the most
/// power of `field − mean` (its 2D DFT, f64).
#[must_use]
pub fn peak_ring(field: &[f32], width: usize, height: usize) -> usize {
    let mean = field.iter().map(|&x| f64::from(x)).sum::<f64>() / field.len().max(1) as f64;
    let mut data = ndarray::Array2::from_shape_fn((height, width), |(y, x)| {
        num_complex::Complex::new(f64::from(field[y * width + x]) - mean, 0.0)
    });
    spectex_spectrum::Fft2::<f64>::new().forward(&mut data);
    let spectrum: Vec<f64> = data.iter().map(num_complex::Complex::norm_sqr).collect();
    let side = width.min(height);
    let mut rings = vec![0.0f64; side / 2 + 1];
    for ky in 0..height {
        for kx in 0..width {
            let fx = spectex_spectrum::signed_frequency(kx, width);
            let fy = spectex_spectrum::signed_frequency(ky, height);
            let r = ((fx * fx + fy * fy).sqrt() * side as f64).round() as usize;
            if (1..rings.len()).contains(&r) {
                rings[r] += spectrum[ky * width + kx];
            }
        }
    }
    (1..rings.len())
        .max_by(|&a, &b| rings[a].total_cmp(&rings[b]))
        .unwrap_or(1)
}
