//! One archive from its registry: the client runs under a time limit and is retried, each retry
//! said as it happens, and where the archive came from (the network, or npm's own cache) is said
//! as it is. Without a network, npm alone would retry for minutes per package and then hand over
//! a stale copy from its cache, and the run would call that a download.

use std::io::Read;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use super::error::{AssetError, Result};
use super::manifest::{Package, Registry};
use super::tools::{self, Tool, APT_GET, NPM};

/// The time limit on each attempt, in seconds (docs/assets.md).
pub const TIMEOUT_VAR: &str = "PENUMBRA_FETCH_TIMEOUT";
const DEFAULT_TIMEOUT: Duration = Duration::from_secs(120);
/// Attempts per archive, and the pause before each retry.
pub const ATTEMPTS: u32 = 3;
const PAUSE: Duration = Duration::from_secs(1);

/// Where an archive came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    Network,
    /// npm's own cache (`npm pack --offline`): nothing was downloaded.
    NpmCache,
}

/// `$PENUMBRA_FETCH_TIMEOUT` seconds, else 120 s.
pub fn time_limit() -> Result<Duration> {
    match std::env::var(TIMEOUT_VAR) {
        Err(_) => Ok(DEFAULT_TIMEOUT),
        Ok(v) => match v.trim().parse::<f64>() {
            Ok(s) if s > 0.0 && s.is_finite() => Ok(Duration::from_secs_f64(s)),
            _ => Err(AssetError::Setting(format!(
                "{TIMEOUT_VAR}={v}: expected a number of seconds above 0"
            ))),
        },
    }
}

/// Downloads `package` into the empty folder `dir`: its path and origin. Each failed attempt but
/// the last calls `retrying(next attempt, why)` before the pause.
pub(crate) fn download(
    package: &Package,
    dir: &Path,
    limit: Duration,
    retrying: &mut dyn FnMut(u32, &str),
) -> Result<(PathBuf, Origin)> {
    let spec = match package.registry {
        Registry::Debian => format!("{}={}", package.name, package.version),
        Registry::Npm => format!("{}@{}", package.name, package.version),
    };
    if package.registry == Registry::Npm {
        // npm's cache first, with no network at all: a hit is no download, and says so.
        let mut offline = Command::new(NPM.name);
        offline
            .args(["pack", "--offline", "--ignore-scripts", "--loglevel=error"])
            .arg(&spec)
            .current_dir(dir);
        if run_limited(&mut offline, &NPM, limit).is_ok() {
            if let Ok(path) = the_archive(dir, &offline) {
                return Ok((path, Origin::NpmCache));
            }
        }
    }
    let (mut command, tool) = match package.registry {
        Registry::Debian => {
            let mut c = Command::new(APT_GET.name);
            c.arg("download").arg(&spec);
            (c, &APT_GET)
        }
        Registry::Npm => {
            let mut c = Command::new(NPM.name);
            // --ignore-scripts: `npm pack` of a registry spec runs none, but say so anyway.
            // --fetch-retries=0: the retries are these attempts, each said on stderr.
            let ms = limit.as_millis().to_string();
            c.args([
                "pack",
                "--ignore-scripts",
                "--loglevel=error",
                "--prefer-online",
                "--fetch-retries=0",
                &format!("--fetch-timeout={ms}"),
            ])
            .arg(&spec);
            (c, &NPM)
        }
    };
    command.current_dir(dir);
    for attempt in 1..=ATTEMPTS {
        empty(dir)?;
        let e =
            match run_limited(&mut command, tool, limit).and_then(|_| the_archive(dir, &command)) {
                Ok(path) => return Ok((path, Origin::Network)),
                Err(e) => e,
            };
        if attempt == ATTEMPTS {
            return Err(e);
        }
        retrying(attempt + 1, &why(&e));
        std::thread::sleep(PAUSE);
    }
    unreachable!("the last attempt returns")
}

/// The one file the client left in `dir`.
fn the_archive(dir: &Path, command: &Command) -> Result<PathBuf> {
    let files = names(dir)?;
    match files.as_slice() {
        [one] => Ok(one.clone()),
        _ => Err(AssetError::ToolFailed {
            command: tools::shown(command),
            status: format!("left {} files instead of one archive", files.len()),
            stderr: String::new(),
        }),
    }
}

fn names(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|source| AssetError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    Ok(entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
}

/// What a failed attempt left, gone before the next.
fn empty(dir: &Path) -> Result<()> {
    for p in names(dir)? {
        let gone = if p.is_dir() {
            std::fs::remove_dir_all(&p)
        } else {
            std::fs::remove_file(&p)
        };
        gone.map_err(|source| AssetError::Io { path: p, source })?;
    }
    Ok(())
}

/// A failed attempt in one line: the status and the client's own reason. npm ends its error with
/// where its log is (`A complete log of this run …`) after a stack trace, so its reason is the
/// `code` line and the line that says why (`… failed, reason: …`); any other client's is its last
/// line. (npm ran with `--silent` before, which left no reason at all.)
pub(crate) fn why(e: &AssetError) -> String {
    match e {
        AssetError::ToolFailed { status, stderr, .. } => {
            let lines: Vec<&str> = stderr
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            fn npm(l: &str) -> Option<&str> {
                l.strip_prefix("npm error ")
                    .or_else(|| l.strip_prefix("npm ERR! "))
                    .map(str::trim)
            }
            let code = lines
                .iter()
                .find_map(|l| npm(l).and_then(|r| r.strip_prefix("code ")));
            // The line that says why, else npm's last line that is not the code, a stack frame,
            // punctuation or where its log is.
            let npm_lines: Vec<&str> = lines.iter().filter_map(|l| npm(l)).collect();
            let said = |r: &&&str| {
                !(r.starts_with("code ")
                    || r.starts_with("at ")
                    || r.starts_with("A complete log")
                    || r.len() < 3)
            };
            let reason = npm_lines
                .iter()
                .find(|r| r.contains("reason:") || r.contains(" failed"))
                .or_else(|| npm_lines.iter().rev().find(said));
            match (code, reason, lines.last()) {
                (Some(code), Some(reason), _) => format!("{status}: npm {code}: {reason}"),
                (Some(code), None, _) => format!("{status}: npm {code}"),
                (None, _, Some(last)) => format!("{status}: {last}"),
                (None, _, None) => status.clone(),
            }
        }
        other => other.to_string().replace('\n', "; "),
    }
}

/// Runs `command` to completion within `limit`; past it the client and everything it started
/// are killed. A signal that ends penumbra ends them too (`crate::interrupt`).
pub(crate) fn run_limited(command: &mut Command, tool: &Tool, limit: Duration) -> Result<Output> {
    let shown = tools::shown(command);
    // Its own process group, so the kill reaches the client's children (npm starts several).
    command
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .process_group(0);
    let mut child = command.spawn().map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => tools::missing(tool),
        _ => AssetError::ToolFailed {
            command: shown.clone(),
            status: e.to_string(),
            stderr: String::new(),
        },
    })?;
    let group = child.id() as libc::pid_t;
    // SAFETY: signalling the process group this run started.
    let kill = move || unsafe {
        libc::kill(-group, libc::SIGKILL);
    };
    let _on_signal = crate::interrupt::on_signal(kill);
    let (stdout, stderr) = (drain(child.stdout.take()), drain(child.stderr.take()));
    let deadline = Instant::now() + limit;
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| failed_to_wait(&shown, e))? {
            break Some(status);
        }
        if Instant::now() >= deadline {
            kill();
            reap(&mut child);
            break None;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = stderr.join().unwrap_or_default();
    let Some(status) = status else {
        return Err(AssetError::ToolFailed {
            command: shown,
            status: format!(
                "no answer within {} s ({TIMEOUT_VAR}), stopped",
                limit.as_secs_f64()
            ),
            stderr: String::from_utf8_lossy(&stderr).into_owned(),
        });
    };
    let output = Output {
        status,
        stdout: stdout.join().unwrap_or_default(),
        stderr,
    };
    if !output.status.success() {
        return Err(tools::failed(shown, &output.status, &output.stderr));
    }
    Ok(output)
}

fn drain(pipe: Option<impl Read + Send + 'static>) -> std::thread::JoinHandle<Vec<u8>> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut p) = pipe {
            let _ = p.read_to_end(&mut bytes);
        }
        bytes
    })
}

fn reap(child: &mut Child) {
    let _ = child.wait();
}

fn failed_to_wait(shown: &str, e: std::io::Error) -> AssetError {
    AssetError::ToolFailed {
        command: shown.to_string(),
        status: e.to_string(),
        stderr: String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_client_past_its_limit_is_stopped_and_named() {
        let start = Instant::now();
        let mut c = Command::new("sh");
        c.args(["-c", "echo starting >&2; sleep 30"]);
        let e = run_limited(&mut c, &NPM, Duration::from_millis(300))
            .unwrap_err()
            .to_string();
        assert!(
            start.elapsed() < Duration::from_secs(5),
            "{:?}",
            start.elapsed()
        );
        assert!(e.starts_with("`sh -c echo starting >&2; sleep 30` failed (no answer within 0.3 s (PENUMBRA_FETCH_TIMEOUT), stopped)"), "{e}");
        assert_eq!(
            why(&AssetError::ToolFailed {
                command: "x".into(),
                status: "exit status: 1".into(),
                stderr: "a\nnpm ERR! ENOTFOUND\n".into()
            }),
            "exit status: 1: npm ERR! ENOTFOUND"
        );
        // npm 10 offline (`--loglevel=error`): the code and the reason, not the log's path.
        let offline = "npm error code ECONNREFUSED\nnpm error syscall connect\nnpm error FetchError: request to http://127.0.0.1:9/left-pad failed, reason: connect ECONNREFUSED 127.0.0.1:9\nnpm error     at ClientRequest.<anonymous> (x.js:130:14)\nnpm error }\nnpm error\nnpm error A complete log of this run can be found in: /root/.npm/_logs/x.log\n";
        assert_eq!(
            why(&AssetError::ToolFailed { command: "x".into(), status: "exit status: 1".into(), stderr: offline.into() }),
            "exit status: 1: npm ECONNREFUSED: FetchError: request to http://127.0.0.1:9/left-pad failed, reason: connect ECONNREFUSED 127.0.0.1:9"
        );
    }
}
