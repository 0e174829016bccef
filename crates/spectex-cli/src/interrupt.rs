//! SIGINT and SIGTERM (Ctrl-C, a batch scheduler's time limit) as a request to stop: long
//! renders look at it between bands and return [`Interrupted`], so that their temporary output
//! file is removed as the error unwinds, and the command exits with 128 + the signal's number.

use std::fmt;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

/// The signal that asked the command to stop (0: none yet), once [`watch`] has run.
static REQUESTED: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

/// From now on, SIGINT and SIGTERM ask the command to stop instead of ending the process at
/// once; a second one still ends it at once (exit status 128 + its number), as the default
/// action would. Called by the commands that [`check`] often (renders, band by band); until
/// then the default action stands, so a command that never looks is not left deaf to Ctrl-C.
/// Idempotent.
pub(crate) fn watch() {
    REQUESTED.get_or_init(|| {
        let requested = Arc::new(AtomicUsize::new(0));
        #[cfg(unix)]
        {
            use std::sync::atomic::AtomicBool;

            use signal_hook::consts::{SIGINT, SIGTERM};
            use signal_hook::flag;

            let seen = Arc::new(AtomicBool::new(false));
            for signal in [SIGINT, SIGTERM] {
                // The actions run in the order they were registered: a second signal finds
                // `seen` set and exits; the first sets it and records which signal it was.
                let registered =
                    flag::register_conditional_shutdown(signal, 128 + signal, Arc::clone(&seen))
                        .and_then(|_| flag::register(signal, Arc::clone(&seen)))
                        .and_then(|_| {
                            flag::register_usize(signal, Arc::clone(&requested), signal as usize)
                        });
                if let Err(e) = registered {
                    eprintln!("note: cannot watch for signal {signal} ({e}); it will stop the command at once");
                }
            }
        }
        requested
    });
}

/// The signal that asked the command to stop, if one did since [`watch`].
pub(crate) fn requested() -> Option<Interrupted> {
    let signal = REQUESTED.get()?.load(Ordering::SeqCst);
    (signal != 0).then_some(Interrupted {
        signal: signal as i32,
    })
}

/// `Err(Interrupted)` once a signal asked the command to stop.
///
/// # Errors
/// [`Interrupted`], naming the signal.
pub(crate) fn check() -> Result<(), Interrupted> {
    requested().map_or(Ok(()), Err)
}

/// A command stopped by a signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Interrupted {
    /// The signal's number (2: SIGINT, 15: SIGTERM).
    pub signal: i32,
}

impl Interrupted {
    /// The exit status of a command stopped by this signal, as a shell reports one killed by
    /// it: 128 + the signal's number (130 for SIGINT, 143 for SIGTERM).
    #[must_use]
    pub fn exit_status(self) -> u8 {
        (128 + self.signal).clamp(0, 255) as u8
    }
}

impl fmt::Display for Interrupted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = match self.signal {
            2 => "SIGINT",
            15 => "SIGTERM",
            _ => "a signal",
        };
        write!(
            f,
            "stopped by {name} ({}); the unfinished output was removed, run the command again to \
             write it",
            self.signal
        )
    }
}

impl std::error::Error for Interrupted {}
