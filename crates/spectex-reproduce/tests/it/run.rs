//! Every paper reproduced at [`Effort::Tiny`]: the three report files are written whole, every
//! figure's files exist and are linked from `index.html`, `claims.json` parses and holds every
//! claim, and the claims that do not depend on image size hold. The statistical claims are
//! judged at `--quick` and full sizes (`cargo xtask reproduce`), not here: at 128² they are
//! noise.

#![allow(
    clippy::unwrap_used,
    reason = "a test fails loudly on the first unexpected None or Err"
)]

use std::path::PathBuf;
use std::process::Command;

use spectex_reproduce::lrp::ring_comparison;
use spectex_reproduce::{Config, Effort, Paper, Verdict, run, write_report};

fn out_dir(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// Claims whose measurement does not depend on the render size: they must hold at any effort.
const EXACT: &[&str] = &[
    "lrp-kb-integral",
    "lrp-envelope",
    "lrp-r0-procedural",
    "lrp-r1-copy",
    "rpn-modulus",
    "rpn-colour-phases",
    "rpn-spot-extension-variance",
    "rpn-periodic-component",
    "rpn-smooth-part",
    "phasor-fig13-harmonics",
];

#[test]
fn every_paper_reproduces_on_tiny_sizes() {
    let dir = out_dir("reproduce-tiny");
    let mut config = Config::new(Paper::ALL.to_vec(), Effort::Tiny, dir.clone());
    // No shared textures (as in CI without ../shared) and no GPU timing: the built-in
    // exemplar covers every path.
    config.shared_textures = None;
    config.gpu = false;
    let mut steps = Vec::new();
    let report = run(&config, &mut |s| steps.push(s.to_owned())).unwrap();
    write_report(&report, &dir).unwrap();
    assert!(steps.len() >= 12, "progress steps: {steps:?}");

    for paper in Paper::ALL {
        assert!(
            report.claims.iter().any(|c| c.paper == paper),
            "{} has no claim",
            paper.name()
        );
        assert!(
            report.figures.iter().any(|f| f.paper == paper),
            "{} has no figure",
            paper.name()
        );
    }
    for id in EXACT {
        let claim = report.claims.iter().find(|c| c.id == *id).unwrap();
        assert_eq!(
            claim.verdict(),
            Verdict::Reproduced,
            "{id}: {} (paper {})",
            claim.ours,
            claim.paper_value
        );
    }
    // The documented typo stays documented: the printed series does not give 0.1126.
    let typo = report
        .claims
        .iter()
        .find(|c| c.id == "lrp-kb-printed-series")
        .unwrap();
    assert!(
        matches!(typo.verdict(), Verdict::Differs(_)),
        "{}",
        typo.ours
    );

    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for figure in &report.figures {
        for panel in &figure.panels {
            let path = dir.join(&panel.file);
            let len = std::fs::metadata(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
                .len();
            assert!(len > 100, "{} has {len} bytes", path.display());
            assert!(
                html.contains(&format!("src=\"{}\"", panel.file)),
                "{}",
                panel.file
            );
            if panel.file.ends_with(".svg") {
                let svg = std::fs::read_to_string(&path).unwrap();
                assert!(
                    svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"),
                    "{}",
                    panel.file
                );
            }
        }
    }
    for claim in &report.claims {
        assert!(
            html.contains(claim.id) && md.contains(claim.id),
            "{}",
            claim.id
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("claims.json")).unwrap()).unwrap();
    let claims = json["claims"].as_array().unwrap();
    assert_eq!(claims.len(), report.claims.len());
    for c in claims {
        for key in [
            "paper",
            "id",
            "section",
            "statement",
            "paper_value",
            "ours",
            "command",
            "verdict",
        ] {
            assert!(
                c[key].as_str().is_some_and(|v| !v.is_empty()),
                "{key} of {c}"
            );
        }
    }
}

/// Fig. 10's measurement (once a CLI fidelity test): both models converge with J.
#[test]
fn ring_comparison_converges_with_the_budget() {
    let c = ring_comparison(256, &[1, 5]).unwrap();
    assert!(
        c.lrp[1].0 < c.lrp[0].0 && c.gabor[1].0 < c.gabor[0].0,
        "LRP {:?}, Gabor {:?}",
        c.lrp,
        c.gabor
    );
    // Few impulses are heavy-tailed, many cosines are not.
    assert!(
        c.gabor[0].2 > 1.0 && c.lrp[1].2.abs() < 0.5,
        "LRP {:?}, Gabor {:?}",
        c.lrp,
        c.gabor
    );
}

#[test]
fn bad_arguments_are_one_error_line_and_exit_1() {
    for args in [&["nosuchpaper"][..], &["--frobnicate"], &["lrp", "--out"]] {
        let out = Command::new(env!("CARGO_BIN_EXE_spectex-reproduce"))
            .args(args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}
