//! `spectex-reproduce [PAPER…] [--quick] [--out DIR] [--no-gpu]`: regenerates the papers'
//! figures and claims into `DIR` (`index.html`, the Markdown report, `claims.json`); exits 1 when a
//! claim recorded as reproduced no longer holds. Run through `cargo xtask reproduce`.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use spectex_reproduce::{Config, Effort, Paper, run, write_report};

const USAGE: &str = "usage: spectex-reproduce [PAPER…] [--quick | --tiny] [--out DIR] [--no-gpu]\n\
                     papers: lrp, rpn, phasor, survey, gabor-example, tiling (all when none is named)";

fn main() -> ExitCode {
    match main_inner() {
        Ok(code) => code,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}

fn main_inner() -> Result<ExitCode> {
    let mut papers = Vec::new();
    let mut effort = Effort::Full;
    let mut out = None;
    let mut gpu = true;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--quick" => effort = Effort::Quick,
            "--tiny" => effort = Effort::Tiny,
            "--no-gpu" => gpu = false,
            "--out" => {
                out = Some(PathBuf::from(
                    args.next().context("--out needs a directory")?,
                ));
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                return Ok(ExitCode::SUCCESS);
            }
            flag if flag.starts_with('-') => bail!("unknown option `{flag}`\n{USAGE}"),
            name => {
                let paper = Paper::from_name(name)?;
                if !papers.contains(&paper) {
                    papers.push(paper);
                }
            }
        }
    }
    if papers.is_empty() {
        papers = Paper::ALL.to_vec();
    }
    let out = out.unwrap_or_else(|| PathBuf::from("target/reproduce"));
    let mut config = Config::new(papers, effort, out);
    config.gpu = gpu;
    if config.shared_textures.is_none() {
        eprintln!(
            "reproduce: ../shared/testdata/textures is absent: exemplar figures use the built-in \
             exemplar only"
        );
    }
    let bar = if std::io::stderr().is_terminal() {
        let bar = ProgressBar::new_spinner();
        bar.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.enable_steady_tick(Duration::from_millis(120));
        bar
    } else {
        ProgressBar::hidden()
    };
    let start = Instant::now();
    let report = run(&config, &mut |step| bar.set_message(step.to_owned()))?;
    bar.finish_and_clear();
    write_report(&report, &config.out_dir)?;
    let (reproduced, differ, regressions) = report.counts();
    eprintln!(
        "reproduce: {} claims: {reproduced} reproduced, {differ} differ (documented), \
         {regressions} regressions; {:.1} s; report in {}",
        report.claims.len(),
        start.elapsed().as_secs_f64(),
        config.out_dir.join("index.html").display()
    );
    let regressions = report.regressions();
    if regressions.is_empty() {
        return Ok(ExitCode::SUCCESS);
    }
    for c in regressions {
        eprintln!(
            "error: claim {} ({}, {}) no longer holds: paper {}, ours {}",
            c.id,
            c.paper.name(),
            c.section,
            c.paper_value,
            c.ours
        );
    }
    Ok(ExitCode::FAILURE)
}
