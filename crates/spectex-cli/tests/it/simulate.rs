//! `spectex simulate` end to end: every simulation with its defaults (a small `--size`), frames,
//! parameter files, the GPU stepper against the CPU, and bad input as one `error:` line with
//! no file left.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use crate::common::{s, scratch, spectex, spectex_ok};

#[test]
fn every_simulation_runs_with_its_defaults() {
    let dir = scratch("simulate-defaults");
    for name in [
        "gray-scott",
        "swift-hohenberg",
        "life",
        "elementary",
        "cyclic",
    ] {
        let out = dir.join(format!("{name}.png"));
        let o = spectex_ok(&["simulate", name, "-o", s(&out), "--size", "40x24"]);
        let img = spectex_testkit::image_files::open(&out).unwrap().to_luma8();
        assert_eq!(img.dimensions(), (40, 24), "{name}");
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            stdout.contains("wrote") && stdout.contains(name),
            "{stdout}"
        );
        // Not blank: a pattern has formed (or, for the automata, cells of both kinds).
        let (lo, hi) = img
            .pixels()
            .fold((255u8, 0u8), |(a, b), p| (a.min(p[0]), b.max(p[0])));
        assert!(hi - lo > 64, "{name}: values {lo}..{hi}");
    }
}

#[test]
fn frames_params_files_and_reruns() {
    let dir = scratch("simulate-frames");
    let frames = dir.join("frames");
    let out = dir.join("life.png");
    let params = dir.join("life.json");
    spectex_ok(&[
        "simulate",
        "life",
        "--rule",
        "B36/S23",
        "--size",
        "30x20",
        "--steps",
        "250",
        "-o",
        s(&out),
        "--frames",
        s(&frames),
        "--every",
        "100",
        "--save-params",
        s(&params),
    ]);
    let mut names: Vec<String> = std::fs::read_dir(&frames)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["frame_000000.png", "frame_000100.png", "frame_000200.png"]
    );
    let again = dir.join("again.png");
    spectex_ok(&["simulate", "file", s(&params), "-o", s(&again)]);
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&again).unwrap());
    let reseeded = dir.join("reseeded.png");
    spectex_ok(&[
        "simulate",
        "file",
        s(&params),
        "-o",
        s(&reseeded),
        "--seed",
        "9",
    ]);
    assert_ne!(
        std::fs::read(&out).unwrap(),
        std::fs::read(&reseeded).unwrap()
    );
    let json = std::fs::read_to_string(&params).unwrap();
    assert!(
        json.contains("\"B36/S23\"") && json.contains("\"schema_version\": 1"),
        "{json}"
    );
}

#[test]
fn bad_simulation_input_fails_cleanly() {
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["life", "--rule", "B9/S23"],
            &["simulation.life.rule", "B9/S23"],
        ),
        (
            &["gray-scott", "--feed", "0.5"],
            &["simulation.gray_scott.feed", "[0, 0.1]"],
        ),
        (
            &["gray-scott", "--du", "0.3"],
            &["simulation.gray_scott.du", "0.25/dt"],
        ),
        (
            &["elementary", "--rule", "256"],
            &["simulation.elementary.rule", "[0, 255]"],
        ),
        (
            &["cyclic", "--states", "1"],
            &["simulation.cyclic.states", "[2, 255]"],
        ),
        (&["life", "--every", "0", "--frames", "f"], &["--every"]),
        (&["life", "--size", "0x4"], &["width", "[1, 16384]"]),
    ];
    for (n, (args, needles)) in cases.iter().enumerate() {
        let dir = scratch(&format!("simulate-bad-{n}"));
        let out = dir.join("out.png");
        let mut all = vec!["simulate"];
        all.extend_from_slice(args);
        all.extend(["-o", s(&out)]);
        let o = spectex(&all);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {stderr}");
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        assert_eq!(lines.len(), 1, "{args:?}: {stderr}");
        assert!(lines[0].starts_with("error: "), "{stderr}");
        for needle in *needles {
            assert!(
                lines[0].contains(needle),
                "{args:?}: '{needle}' missing from {stderr}"
            );
        }
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            0,
            "{args:?}: file left"
        );
    }
}

#[test]
fn gpu_automata_write_the_cpus_bytes() {
    if let Err(e) = spectex_gpu::GpuContext::new() {
        assert!(
            !std::env::var("SPECTEX_REQUIRE_GPU").is_ok_and(|v| v == "1"),
            "SPECTEX_REQUIRE_GPU=1 but no GPU: {e}"
        );
        eprintln!("SKIPPED gpu_automata_write_the_cpus_bytes: {e}");
        return;
    }
    let dir = scratch("simulate-gpu");
    for name in ["life", "elementary", "cyclic"] {
        let (cpu, gpu) = (
            dir.join(format!("{name}-cpu.png")),
            dir.join(format!("{name}-gpu.png")),
        );
        spectex_ok(&[
            "simulate",
            name,
            "--size",
            "33x21",
            "--steps",
            "40",
            "-o",
            s(&cpu),
        ]);
        let o = spectex_ok(&[
            "simulate",
            name,
            "--size",
            "33x21",
            "--steps",
            "40",
            "-o",
            s(&gpu),
            "--gpu",
        ]);
        assert!(String::from_utf8_lossy(&o.stdout).contains("GPU"));
        assert_eq!(
            std::fs::read(&cpu).unwrap(),
            std::fs::read(&gpu).unwrap(),
            "{name}"
        );
    }
    let out = dir.join("sh.png");
    let o = spectex(&[
        "simulate",
        "swift-hohenberg",
        "--size",
        "16x16",
        "-o",
        s(&out),
        "--gpu",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("CPU"));
    assert!(!out.exists());
}
