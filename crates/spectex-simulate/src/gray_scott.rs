//! Gray–Scott reaction–diffusion (Pearson 1993): forward Euler, 5-point Laplacian, f32, on a
//! torus; rows in parallel.

use rayon::prelude::*;
use spectex_model::simulation::GrayScott;

/// One cell's explicit Gray–Scott step: `(u, v)` at the cell, `nu`/`nv` the sums of its four
/// side neighbours. The order of operations is the contract `shaders/simulate.wgsl` follows:
///
/// ```text
/// lap_u = nu − 4u,  lap_v = nv − 4v,  uvv = (u·v)·v
/// u' = u + dt·((du·lap_u − uvv) + F·(1 − u))
/// v' = v + dt·((dv·lap_v + uvv) − (F + k)·v)
/// ```
#[must_use]
#[inline]
pub fn gray_scott_cell(p: &GrayScott, u: f32, v: f32, nu: f32, nv: f32) -> (f32, f32) {
    let lap_u = nu - 4.0 * u;
    let lap_v = nv - 4.0 * v;
    let uvv = u * v * v;
    let u2 = u + p.dt * ((p.du * lap_u - uvv) + p.feed * (1.0 - u));
    let v2 = v + p.dt * ((p.dv * lap_v + uvv) - (p.feed + p.kill) * v);
    (u2, v2)
}

/// Both concentrations and the buffers of the next step.
#[derive(Debug, Clone)]
pub(crate) struct GrayScottState {
    p: GrayScott,
    width: usize,
    height: usize,
    pub(crate) u: Vec<f32>,
    pub(crate) v: Vec<f32>,
    next_u: Vec<f32>,
    next_v: Vec<f32>,
}

impl GrayScottState {
    pub(crate) fn new(p: GrayScott, width: usize, height: usize, u: Vec<f32>, v: Vec<f32>) -> Self {
        let n = u.len();
        GrayScottState {
            p,
            width,
            height,
            u,
            v,
            next_u: vec![0.0; n],
            next_v: vec![0.0; n],
        }
    }

    pub(crate) fn step(&mut self) {
        let (w, h, p) = (self.width, self.height, self.p);
        let (u, v) = (&self.u, &self.v);
        self.next_u
            .par_chunks_mut(w)
            .zip(self.next_v.par_chunks_mut(w))
            .enumerate()
            .for_each(|(y, (out_u, out_v))| {
                let (up, down) = ((y + h - 1) % h, (y + 1) % h);
                let (uc, ut, ub) = (row(u, y, w), row(u, up, w), row(u, down, w));
                let (vc, vt, vb) = (row(v, y, w), row(v, up, w), row(v, down, w));
                // The wrapped columns, then the interior with equal-length slices (no
                // modulo, no bounds checks: it vectorises). Same expression either way.
                let edges: &[usize] = if w < 3 { &[0, 1][..w] } else { &[0, w - 1] };
                for &x in edges {
                    let (l, r) = ((x + w - 1) % w, (x + 1) % w);
                    // The WGSL sums neighbours in this order too: (left + right) + (up + down).
                    let nu = (uc[l] + uc[r]) + (ut[x] + ub[x]);
                    let nv = (vc[l] + vc[r]) + (vt[x] + vb[x]);
                    (out_u[x], out_v[x]) = gray_scott_cell(&p, uc[x], vc[x], nu, nv);
                }
                if w >= 3 {
                    let n = w - 2;
                    let (ul, um, ur) = (&uc[..n], &uc[1..=n], &uc[2..n + 2]);
                    let (vl, vm, vr) = (&vc[..n], &vc[1..=n], &vc[2..n + 2]);
                    let (ut, ub, vt, vb) = (&ut[1..=n], &ub[1..=n], &vt[1..=n], &vb[1..=n]);
                    let (ou, ov) = (&mut out_u[1..=n], &mut out_v[1..=n]);
                    for i in 0..n {
                        let nu = (ul[i] + ur[i]) + (ut[i] + ub[i]);
                        let nv = (vl[i] + vr[i]) + (vt[i] + vb[i]);
                        (ou[i], ov[i]) = gray_scott_cell(&p, um[i], vm[i], nu, nv);
                    }
                }
            });
        std::mem::swap(&mut self.u, &mut self.next_u);
        std::mem::swap(&mut self.v, &mut self.next_v);
    }
}

/// Row `y` of a row-major field `w` wide.
fn row(f: &[f32], y: usize, w: usize) -> &[f32] {
    &f[y * w..(y + 1) * w]
}
