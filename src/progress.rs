//! Progress of work longer than a second, and lines for the user, as callbacks: the program that
//! embeds the engine registers how to show them (the `penumbra` binary draws bars and prints the
//! lines on stderr); without one nothing is shown. The engine itself prints nothing: a line it
//! hands to `notice` is also in a value its caller can read (a frame's record, a scene's
//! `warnings`), except what a read waits for, which is only news while it waits.

use std::sync::OnceLock;

/// One unit of work under way: `inc` as it advances, `finish_and_clear` when it ends.
pub trait Bar: Send + Sync {
    fn inc(&self, delta: u64);
    fn finish_and_clear(&self);
}

/// What a program registers: `bar(len, what)` starts a unit of `len` steps, and `notice` shows a
/// line the user should read now (a warning, what a read waits for).
pub struct Progress {
    pub bar: fn(u64, &str) -> Box<dyn Bar>,
    pub notice: fn(&str),
}

static PROGRESS: OnceLock<Progress> = OnceLock::new();

/// Registers the progress callback; only the first call counts.
pub fn register(progress: Progress) {
    let _ = PROGRESS.set(progress);
}

struct Hidden;

impl Bar for Hidden {
    fn inc(&self, _: u64) {}
    fn finish_and_clear(&self) {}
}

pub(crate) fn bar(len: u64, what: &str) -> Box<dyn Bar> {
    match PROGRESS.get() {
        Some(p) => (p.bar)(len, what),
        None => Box::new(Hidden),
    }
}

/// Hands `line` to the registered `notice`; without one it is not shown.
pub(crate) fn notice(line: &str) {
    if let Some(p) = PROGRESS.get() {
        (p.notice)(line);
    }
}
