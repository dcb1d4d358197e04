//! Progress bars for work longer than a second (the lab's, and the engine's through its callback); hidden when stderr is not a terminal or in tests.
//! All bars share one `MultiProgress`, so a suite's bar and a method's per-map bar stack instead of
//! overwriting each other.

use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use std::sync::OnceLock;

fn multi() -> &'static MultiProgress {
    static MULTI: OnceLock<MultiProgress> = OnceLock::new();
    MULTI.get_or_init(MultiProgress::new)
}

pub fn bar(len: u64, what: &str) -> ProgressBar {
    let bar = if std::env::var_os("PENUMBRA_NO_PROGRESS").is_some() {
        ProgressBar::hidden()
    } else {
        multi().add(ProgressBar::new(len))
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg:24} [{bar:32}] {pos}/{len} {elapsed_precise}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar
}

/// Runs `f` (which prints lines) with the bars lifted off the terminal, then redraws them.
pub fn suspend<T>(f: impl FnOnce() -> T) -> T {
    multi().suspend(f)
}

struct Bar(ProgressBar);

impl penumbra::research::progress::Bar for Bar {
    fn inc(&self, delta: u64) {
        self.0.inc(delta);
    }
    fn finish_and_clear(&self) {
        self.0.finish_and_clear();
    }
}

/// Draws the engine's progress with these bars.
pub fn install() {
    penumbra::research::progress::register(penumbra::research::progress::Progress {
        bar: |len, what| Box::new(Bar(bar(len, what))),
        notice: |line| suspend(|| eprintln!("{line}")),
    });
}
