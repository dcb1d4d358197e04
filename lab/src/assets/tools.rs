//! The registry clients, run as subprocesses: `apt-get`, `dpkg-deb`, `npm`, `node`.

use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::{Command, Output};

use super::error::{AssetError, Result};
use super::manifest::Registry;

pub(crate) struct Tool {
    pub name: &'static str,
    pub hint: &'static str,
}

pub(crate) const APT_GET: Tool = Tool {
    name: "apt-get",
    hint: "Debian packages are fetched with `apt-get download`: run on Debian or Ubuntu (package `apt`)",
};
pub(crate) const DPKG_DEB: Tool = Tool {
    name: "dpkg-deb",
    hint: "Debian packages are unpacked with `dpkg-deb`: install the `dpkg` package",
};
pub(crate) const NPM: Tool = Tool {
    name: "npm",
    hint: "npm packages are fetched with `npm pack`: install Node.js 20 and npm (Debian: `apt-get install nodejs npm`)",
};
pub(crate) const NODE: Tool = Tool {
    name: "node",
    hint: "the tree is generated with Node.js 20: install it (Debian: `apt-get install nodejs`)",
};

/// The tools a registry needs; the first one downloads.
pub(crate) fn tools_for(registry: Registry) -> &'static [&'static Tool] {
    match registry {
        Registry::Debian => &[&APT_GET, &DPKG_DEB],
        Registry::Npm => &[&NPM],
    }
}

/// Fails early, before any download, when a tool is not on PATH.
pub(crate) fn require(tool: &Tool) -> Result<()> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    match find_in(&path, tool.name) {
        Some(_) => Ok(()),
        None => Err(missing(tool)),
    }
}

pub(crate) fn missing(tool: &Tool) -> AssetError {
    AssetError::ToolMissing {
        tool: tool.name,
        hint: tool.hint,
    }
}

fn find_in(path_var: &OsStr, name: &str) -> Option<PathBuf> {
    std::env::split_paths(path_var)
        .map(|dir| dir.join(name))
        .find(|candidate| candidate.is_file())
}

/// Runs a command to completion; a non-zero exit becomes an error with its stderr.
pub(crate) fn run(command: &mut Command, tool: &Tool) -> Result<Output> {
    let shown = shown(command);
    let output = command.output().map_err(|e| match e.kind() {
        std::io::ErrorKind::NotFound => missing(tool),
        _ => AssetError::ToolFailed {
            command: shown.clone(),
            status: e.to_string(),
            stderr: String::new(),
        },
    })?;
    if !output.status.success() {
        return Err(failed(shown, &output.status, &output.stderr));
    }
    Ok(output)
}

pub(crate) fn shown(command: &Command) -> String {
    let mut parts = vec![command.get_program().to_string_lossy().into_owned()];
    parts.extend(command.get_args().map(|a| a.to_string_lossy().into_owned()));
    parts.join(" ")
}

pub(crate) fn failed(
    command: String,
    status: &std::process::ExitStatus,
    stderr: &[u8],
) -> AssetError {
    let stderr = String::from_utf8_lossy(stderr);
    let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
    let mut stderr = lines[lines.len().saturating_sub(20)..].join("\n");
    if stderr.contains("Unable to locate package")
        || stderr.contains("no installation candidate")
        || stderr.contains("Can't select")
        || stderr.contains("was not found")
    {
        stderr.push_str(
            "\n(run `apt-get update` first; if it persists, the pinned version left the archive)",
        );
    }
    AssetError::ToolFailed {
        command,
        status: status.to_string(),
        stderr,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_tool_is_named_with_a_hint() {
        assert_eq!(find_in(OsStr::new("/nonexistent-dir"), "npm"), None);
        let message = missing(&NPM).to_string();
        assert!(
            message.starts_with("`npm` not found on PATH: "),
            "{message}"
        );
        assert!(message.contains("apt-get install nodejs npm"), "{message}");
    }

    #[test]
    fn finds_a_tool_on_a_given_path() {
        assert!(find_in(OsStr::new("/nonexistent-dir:/bin:/usr/bin"), "sh").is_some());
    }
}
