//! Panics appended to a file, one line each, for a census over many runs.
//!
//! A panic is a bug at any input (docs/robustness.md), but a run's stderr is read by whatever ran
//! it, and a test that captures it may not look. With `PENUMBRA_PANIC_LOG=FILE` every panic of the
//! binary is also appended to FILE, so a batch of runs — the whole test suite, a probe of hundreds
//! of inputs — is counted for panics in one place (scripts/panic-census.sh).

use std::io::Write;
use std::path::PathBuf;

/// Chains a hook that appends `panicked: MESSAGE (args: …)` to `path` before the default hook
/// prints as usual. Appends are single writes of one line, so concurrent runs do not interleave.
pub fn install(path: PathBuf) {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let args: Vec<String> = std::env::args().collect();
        let line = format!("panicked: {info} (args: {})", args.join(" ")).replace('\n', " ") + "\n";
        if let Ok(mut f) = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
        {
            let _ = f.write_all(line.as_bytes());
        }
        default(info);
    }));
}
