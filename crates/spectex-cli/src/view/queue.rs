//! The bounded work queue of the view's renders: coarse tiles first, then the rest in arrival
//! order; a full queue refuses new work at once (503) instead of growing.

use std::collections::VecDeque;
use std::sync::{Condvar, Mutex};

/// Jobs waiting at most (tiles and renders together): a burst past it is refused.
pub(crate) const MAX_QUEUED: usize = 512;

/// Two lanes of jobs: coarse tiles (served first) and the rest.
pub(crate) struct JobQueue<J> {
    /// `(coarse, fine)` lanes.
    lanes: Mutex<(VecDeque<J>, VecDeque<J>)>,
    /// Signals a job or the end.
    ready: Condvar,
}

impl<J> JobQueue<J> {
    /// An empty queue.
    pub(crate) fn new() -> Self {
        Self {
            lanes: Mutex::new((VecDeque::new(), VecDeque::new())),
            ready: Condvar::new(),
        }
    }

    /// Queues `job` (in the coarse lane when `coarse`), or gives it back when the queue is full.
    pub(crate) fn push(&self, job: J, coarse: bool) -> Result<(), J> {
        let Ok(mut lanes) = self.lanes.lock() else {
            return Err(job);
        };
        if lanes.0.len() + lanes.1.len() >= MAX_QUEUED {
            return Err(job);
        }
        if coarse {
            lanes.0.push_back(job);
        } else {
            lanes.1.push_back(job);
        }
        self.ready.notify_one();
        Ok(())
    }

    /// The next job, waiting for one.
    pub(crate) fn pop(&self) -> Option<J> {
        let mut lanes = self.lanes.lock().ok()?;
        loop {
            if let Some(job) = lanes.0.pop_front().or_else(|| lanes.1.pop_front()) {
                return Some(job);
            }
            lanes = self.ready.wait(lanes).ok()?;
        }
    }
}
