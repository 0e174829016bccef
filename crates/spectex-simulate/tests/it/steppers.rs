//! The steppers against slow references (naive loops with explicit modulo indexing), known
//! patterns (glider, blinker, Sierpinski), exact solutions (uniform Gray–Scott states, linear
//! Swift–Hohenberg growth, the stripe amplitude near onset) and thread counts.

use spectex_model::simulation::{
    Cyclic, Elementary, GrayScott, GrayScottPreset, InitialState, LifeLike, Neighbourhood,
    Simulation, SimulationSpec, SwiftHohenberg,
};
use spectex_simulate::{Simulator, gray_scott_cell};

fn sim(spec: &SimulationSpec) -> Simulator {
    Simulator::new(spec).unwrap_or_else(|e| panic!("{spec:?}: {e}"))
}

fn at(w: usize, h: usize, x: isize, y: isize) -> usize {
    let (w, h) = (w as isize, h as isize);
    (y.rem_euclid(h) * w + x.rem_euclid(w)) as usize
}

/// The parallel Gray–Scott step equals a naive single loop over the torus, bit for bit, for
/// several sizes (odd, 1-wide) and seeds.
#[test]
fn gray_scott_matches_a_naive_torus_loop() {
    for (w, h, seed) in [(17usize, 9usize, 1u32), (32, 32, 2), (1, 5, 3), (40, 3, 4)] {
        let p = GrayScott::preset(GrayScottPreset::Spots);
        let spec = SimulationSpec::new(w as u32, h as u32, 0, seed, Simulation::GrayScott(p));
        let InitialState::Fields { mut u, mut v } = spec.initial_state() else {
            panic!("not a Gray–Scott state");
        };
        let mut s = sim(&spec);
        for step in 0..20 {
            s.step();
            let (mut u2, mut v2) = (u.clone(), v.clone());
            for y in 0..h as isize {
                for x in 0..w as isize {
                    let i = at(w, h, x, y);
                    let n = |f: &[f32]| {
                        (f[at(w, h, x - 1, y)] + f[at(w, h, x + 1, y)])
                            + (f[at(w, h, x, y - 1)] + f[at(w, h, x, y + 1)])
                    };
                    (u2[i], v2[i]) = gray_scott_cell(&p, u[i], v[i], n(&u), n(&v));
                }
            }
            (u, v) = (u2, v2);
            let fields = s.fields().unwrap_or_default();
            for (name, got, want) in [("u", &fields[0], &u), ("v", &fields[1], &v)] {
                if let Some(i) = (0..w * h).find(|&i| got[i].to_bits() != want[i].to_bits()) {
                    panic!(
                        "{w}×{h} seed {seed} step {step}: {name}[{i}] = {} != {}",
                        got[i], want[i]
                    );
                }
            }
        }
    }
}

/// `gray_scott_cell` is the forward Euler step of Pearson's equations: checked in f64 from the
/// equations written out here for a few states.
#[test]
fn gray_scott_cell_is_pearsons_equations() {
    let p = GrayScott::preset(GrayScottPreset::Mazes);
    for (u, v, nu, nv) in [
        (1.0f32, 0.0f32, 4.0f32, 0.0f32),
        (0.5, 0.25, 2.1, 0.9),
        (0.3, 0.4, 1.0, 1.9),
    ] {
        let (u64_, v64, nu64, nv64) = (f64::from(u), f64::from(v), f64::from(nu), f64::from(nv));
        let (du, dv, f, k, dt) = (
            f64::from(p.du),
            f64::from(p.dv),
            f64::from(p.feed),
            f64::from(p.kill),
            f64::from(p.dt),
        );
        let want_u = u64_ + dt * (du * (nu64 - 4.0 * u64_) - u64_ * v64 * v64 + f * (1.0 - u64_));
        let want_v = v64 + dt * (dv * (nv64 - 4.0 * v64) + u64_ * v64 * v64 - (f + k) * v64);
        let (got_u, got_v) = gray_scott_cell(&p, u, v, nu, nv);
        // About ten f32 roundings of values below 4: 10 · 4 · 2⁻²⁴.
        let tol = 10.0 * 4.0 * 2f64.powi(-24);
        assert!(
            (f64::from(got_u) - want_u).abs() < tol,
            "u: {got_u} vs {want_u}"
        );
        assert!(
            (f64::from(got_v) - want_v).abs() < tol,
            "v: {got_v} vs {want_v}"
        );
    }
}

/// Same bytes on 1 and 2 threads, for every simulation.
#[test]
fn same_bytes_at_any_thread_count() {
    let specs = [
        Simulation::GrayScott(GrayScott::preset(GrayScottPreset::Holes)),
        Simulation::SwiftHohenberg(SwiftHohenberg::STRIPES),
        Simulation::Life(LifeLike::conway()),
        Simulation::Cyclic(Cyclic::SPIRALS),
    ];
    for simulation in specs {
        let spec = SimulationSpec::new(48, 40, 30, 9, simulation);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap_or_else(|e| panic!("pool: {e}"));
            pool.install(|| {
                let mut s = sim(&spec);
                s.run(u64::from(spec.steps), &mut |_| {});
                s.grey().iter().map(|g| g.to_bits()).collect::<Vec<_>>()
            })
        };
        assert_eq!(run(1), run(2), "{}", spec.simulation.name());
    }
}

/// A spatially uniform Gray–Scott state stays uniform and follows the reaction ODE, here
/// integrated by forward Euler in f64.
#[test]
fn uniform_gray_scott_follows_the_reaction() {
    let p = GrayScott::preset(GrayScottPreset::Spots);
    let spec = SimulationSpec::new(8, 8, 0, 0, Simulation::GrayScott(p));
    let state = InitialState::Fields {
        u: vec![0.5; 64],
        v: vec![0.25; 64],
    };
    let mut s = Simulator::from_state(&spec, state).unwrap_or_else(|e| panic!("{e}"));
    let (mut u, mut v) = (0.5f64, 0.25f64);
    let (f, k) = (f64::from(p.feed), f64::from(p.kill));
    for step in 0..200 {
        s.step();
        let uvv = u * v * v;
        (u, v) = (u + (-uvv + f * (1.0 - u)), v + (uvv - (f + k) * v));
        let fields = s.fields().unwrap_or_default();
        // f32 rounding accumulates at most ~8 · 2⁻²⁴ per step of a map whose Lipschitz
        // constant is below 1.2 here: 200 steps stay under 1e-4.
        for i in 0..64 {
            assert!(
                (f64::from(fields[0][i]) - u).abs() < 1e-4,
                "step {step}: u {}",
                fields[0][i]
            );
            assert!(
                (f64::from(fields[1][i]) - v).abs() < 1e-4,
                "step {step}: v {}",
                fields[1][i]
            );
        }
    }
}

fn life(rule: &str, w: u32, h: u32, cells: Vec<u32>) -> Simulator {
    let spec = SimulationSpec::new(
        w,
        h,
        0,
        0,
        Simulation::Life(LifeLike {
            rule: rule.to_owned(),
            density: 0.0,
        }),
    );
    Simulator::from_state(&spec, InitialState::Cells(cells)).unwrap_or_else(|e| panic!("{e}"))
}

/// A glider moves one cell diagonally every 4 generations, across the torus's edges; a
/// blinker has period 2.
#[test]
fn life_glider_and_blinker() {
    let (w, h) = (10usize, 8usize);
    let glider = [(1isize, 0isize), (2, 1), (0, 2), (1, 2), (2, 2)];
    let place = |dx: isize, dy: isize| {
        let mut c = vec![0u32; w * h];
        for (x, y) in glider {
            c[at(w, h, x + dx, y + dy)] = 1;
        }
        c
    };
    let mut s = life("B3/S23", w as u32, h as u32, place(0, 0));
    for n in 1..=40isize {
        s.run(4, &mut |_| {});
        assert_eq!(
            s.cells(),
            Some(&place(n, n)[..]),
            "after {} generations",
            4 * n
        );
    }
    let mut blinker = vec![0u32; 25];
    for x in 1..4 {
        blinker[2 * 5 + x] = 1;
    }
    let mut s = life("B3/S23", 5, 5, blinker.clone());
    s.step();
    assert_ne!(s.cells(), Some(&blinker[..]));
    s.step();
    assert_eq!(s.cells(), Some(&blinker[..]));
}

/// Other rules against a naive loop: HighLife, Seeds, Day & Night from random states.
#[test]
fn life_like_rules_match_a_naive_loop() {
    for (rule, birth, survive) in [
        ("B36/S23", &[3usize, 6][..], &[2usize, 3][..]),
        ("B2/S", &[2][..], &[][..]),
        ("B3678/S34678", &[3, 6, 7, 8][..], &[3, 4, 6, 7, 8][..]),
    ] {
        let (w, h) = (23usize, 19usize);
        let spec = SimulationSpec::new(
            w as u32,
            h as u32,
            0,
            5,
            Simulation::Life(LifeLike {
                rule: rule.to_owned(),
                density: 0.4,
            }),
        );
        let mut s = sim(&spec);
        let InitialState::Cells(mut c) = spec.initial_state() else {
            panic!("cells");
        };
        for step in 0..25 {
            s.step();
            let mut n = c.clone();
            for y in 0..h as isize {
                for x in 0..w as isize {
                    let mut live = 0;
                    for dy in -1..=1 {
                        for dx in -1..=1 {
                            if (dx, dy) != (0, 0) {
                                live += c[at(w, h, x + dx, y + dy)] as usize;
                            }
                        }
                    }
                    let i = at(w, h, x, y);
                    let keep = if c[i] == 1 { survive } else { birth };
                    n[i] = u32::from(keep.contains(&live));
                }
            }
            c = n;
            assert_eq!(s.cells(), Some(&c[..]), "{rule} step {step}");
        }
    }
}

/// Rule 90 from one cell draws Pascal's triangle mod 2: generation t at offset x from the
/// start cell is C(t, (t + x)/2) mod 2 for t + x even and |x| ≤ t, else 0 (while the triangle
/// fits in the row). Drawn as Wolfram does: live cells black (grey 0).
#[test]
fn rule_90_draws_pascals_triangle_mod_2() {
    let (w, h) = (129usize, 60usize);
    let spec = SimulationSpec::new(
        w as u32,
        h as u32,
        0,
        0,
        Simulation::Elementary(Elementary {
            rule: 90,
            single: true,
            density: 0.5,
        }),
    );
    let mut s = sim(&spec);
    s.run(Simulator::total_steps(&spec), &mut |_| {});
    let grey = s.grey();
    let binom_odd = |n: usize, k: usize| (k & !n) == 0; // Lucas: C(n, k) odd iff k ⊆ n bitwise
    for t in 0..h {
        for col in 0..w {
            let x = col as isize - (w / 2) as isize;
            let live = x.unsigned_abs() <= t
                && (t as isize + x) % 2 == 0
                && binom_odd(t, ((t as isize + x) / 2) as usize);
            assert_eq!(
                grey[t * w + col],
                if live { 0.0 } else { 1.0 },
                "t {t} x {x}"
            );
        }
    }
}

/// Warm-up generations: `steps = s` draws generations s … s + height − 1, the same rows a
/// longer run draws from row s on.
#[test]
fn elementary_warm_up_shifts_the_drawn_rows() {
    let spec = |steps, height| {
        SimulationSpec::new(
            50,
            height,
            steps,
            4,
            Simulation::Elementary(Elementary::RULE_30),
        )
    };
    let run = |spec: SimulationSpec| {
        let mut s = sim(&spec);
        s.run(Simulator::total_steps(&spec), &mut |_| {});
        s.cells().map(<[u32]>::to_vec).unwrap_or_default()
    };
    let long = run(spec(0, 30));
    let late = run(spec(10, 20));
    assert_eq!(&long[10 * 50..], &late[..]);
}

/// The cyclic automaton against a naive loop, both neighbourhoods.
#[test]
fn cyclic_matches_a_naive_loop() {
    for (states, threshold, neighbourhood) in [
        (3u32, 3u32, Neighbourhood::Moore),
        (14, 1, Neighbourhood::VonNeumann),
        (5, 2, Neighbourhood::Moore),
    ] {
        let (w, h) = (21usize, 17usize);
        let spec = SimulationSpec::new(
            w as u32,
            h as u32,
            0,
            3,
            Simulation::Cyclic(Cyclic {
                states,
                threshold,
                neighbourhood,
            }),
        );
        let mut s = sim(&spec);
        let InitialState::Cells(mut c) = spec.initial_state() else {
            panic!("cells");
        };
        assert!(c.iter().all(|&x| x < states));
        for step in 0..30 {
            s.step();
            let mut n = c.clone();
            for y in 0..h as isize {
                for x in 0..w as isize {
                    let i = at(w, h, x, y);
                    let succ = (c[i] + 1) % states;
                    let mut count = 0;
                    for dy in -1isize..=1 {
                        for dx in -1isize..=1 {
                            let side = dx == 0 || dy == 0;
                            let counted = (dx, dy) != (0, 0)
                                && (side || neighbourhood == Neighbourhood::Moore);
                            if counted && c[at(w, h, x + dx, y + dy)] == succ {
                                count += 1;
                            }
                        }
                    }
                    n[i] = if count >= threshold { succ } else { c[i] };
                }
            }
            c = n;
            assert_eq!(s.cells(), Some(&c[..]), "{states}/{threshold} step {step}");
        }
    }
}

fn swift(p: SwiftHohenberg, w: u32, h: u32, u: Vec<f32>) -> Simulator {
    let spec = SimulationSpec::new(w, h, 0, 0, Simulation::SwiftHohenberg(p));
    Simulator::from_state(&spec, InitialState::Field(u)).unwrap_or_else(|e| panic!("{e}"))
}

/// A small single Fourier mode u = a cos(2π m x / W) grows by the scheme's factor
/// (1 + dt r) / (1 + dt (1 − q²)²) per step, q = m λ / W (the cubic term is a³ ≈ 1e-18 here),
/// and over time by about exp((r − (1 − q²)²) t), the linear growth rate of the equation.
#[test]
fn swift_hohenberg_linear_modes_grow_at_the_equations_rate() {
    let (w, a) = (64u32, 1e-6f64);
    for (m, lambda) in [(4u32, 16.0f32), (5, 16.0), (3, 16.0)] {
        let p = SwiftHohenberg {
            r: 0.2,
            g: 0.0,
            wavelength: lambda,
            dt: 0.05,
            noise: 0.1,
        };
        let u = (0..w * 2)
            .map(|i| {
                let x = f64::from(i % w);
                (a * (std::f64::consts::TAU * f64::from(m) * x / f64::from(w)).cos()) as f32
            })
            .collect();
        let mut s = swift(p, w, 2, u);
        let steps = 100;
        s.run(steps, &mut |_| {});
        let q2 = (f64::from(m) * f64::from(lambda) / f64::from(w)).powi(2);
        let (r, dt) = (f64::from(p.r), f64::from(p.dt));
        let factor = ((1.0 + dt * r) / (1.0 + dt * (1.0 - q2).powi(2))).powi(steps as i32);
        let continuous = ((r - (1.0 - q2).powi(2)) * dt * steps as f64).exp();
        let got = f64::from(s.fields().unwrap_or_default()[0][0]) / a;
        assert!(
            (got - factor).abs() < 1e-5 * factor.max(1.0),
            "m {m}: {got} vs scheme {factor}"
        );
        // First order in dt: the schemes agree with the equation to O(dt·t·rate²).
        assert!(
            (got / continuous - 1.0).abs() < 0.03,
            "m {m}: {got} vs exp {continuous}"
        );
    }
}

/// Near onset (small r, g = 0) stripes saturate at the amplitude of the amplitude equation,
/// u ≈ A cos(x) with A² = 4r/3 (weakly nonlinear theory): checked to 10 %.
#[test]
fn swift_hohenberg_stripes_saturate_at_the_weakly_nonlinear_amplitude() {
    let w = 64u32;
    let p = SwiftHohenberg {
        r: 0.05,
        g: 0.0,
        wavelength: 16.0,
        dt: 1.0,
        noise: 0.1,
    };
    let u = (0..w * 4)
        .map(|i| {
            (0.01 * (std::f64::consts::TAU * 4.0 * f64::from(i % w) / f64::from(w)).cos()) as f32
        })
        .collect();
    let mut s = swift(p, w, 4, u);
    s.run(2000, &mut |_| {});
    let field = &s.fields().unwrap_or_default()[0];
    let max = field.iter().fold(0.0f32, |m, &x| m.max(x.abs()));
    let want = (4.0 * f64::from(p.r) / 3.0).sqrt();
    assert!(
        (f64::from(max) / want - 1.0).abs() < 0.1,
        "amplitude {max} vs {want}"
    );
}

/// Bad parameters and mismatched states are typed errors naming the field.
#[test]
fn bad_input_is_a_named_error() {
    let mut p = SwiftHohenberg::STRIPES;
    p.wavelength = 1.0;
    let spec = SimulationSpec::new(8, 8, 0, 0, Simulation::SwiftHohenberg(p));
    let e = Simulator::new(&spec)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        e.contains("simulation.swift_hohenberg.wavelength") && e.contains("[2, 1024]"),
        "{e}"
    );
    let spec = SimulationSpec::new(8, 8, 0, 0, Simulation::Life(LifeLike::conway()));
    let e = Simulator::from_state(&spec, InitialState::Cells(vec![0; 63]))
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("initial state"), "{e}");
}
