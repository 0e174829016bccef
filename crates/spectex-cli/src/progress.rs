//! What a long command shows and says on the way: a progress bar on a terminal (nothing when
//! piped) and the note on clamped values.

use std::io::IsTerminal;

use crate::io;

/// A progress bar on stderr when it is a terminal; hidden (and free) when piped.
pub(crate) fn progress_bar(len: u64, what: &'static str) -> indicatif::ProgressBar {
    if !std::io::stderr().is_terminal() || len < 256 {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} rows, {eta} left")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(what);
    bar
}

/// Says how many values a PNG output clamped, if any.
pub(crate) fn note_clipping(report: io::WriteReport) {
    if report.clipped > 0 {
        eprintln!(
            "note: {:.2}% of the values fell outside [0, 1] and were clamped in the PNG; write .exr to keep them",
            100.0 * report.clipped as f64 / report.total.max(1) as f64
        );
    }
}
