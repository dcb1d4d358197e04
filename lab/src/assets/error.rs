//! The one error type of the asset layer: loading and fetching.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

/// Where in a file a problem is. Numbers are 1-based for lines and columns, 0-based for
/// element indices (as the file format counts them).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Location {
    Line(usize),
    LineColumn {
        line: usize,
        column: usize,
    },
    /// An element of a PLY/OFF file, e.g. `face 1032`, with its text line when the file is text.
    Element {
        kind: String,
        index: usize,
        line: Option<usize>,
    },
    /// An entry of a JS array, e.g. `cells[5]`.
    Item {
        array: &'static str,
        index: usize,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::LineColumn { line, column } => write!(f, "line {line}, column {column}"),
            Location::Element {
                kind,
                index,
                line: Some(line),
            } => {
                write!(f, "line {line}, {kind} {index}")
            }
            Location::Element {
                kind,
                index,
                line: None,
            } => write!(f, "{kind} {index}"),
            Location::Item { array, index } => write!(f, "{array}[{index}]"),
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum AssetError {
    #[error("{}: cannot read: {source}", file.display())]
    Read { file: PathBuf, source: io::Error },

    #[error("{}: {at}: {message}", file.display())]
    Malformed {
        file: PathBuf,
        at: Location,
        message: String,
    },

    /// A problem with the file as a whole (empty mesh, unknown format, missing array).
    #[error("{}: {message}", file.display())]
    Invalid { file: PathBuf, message: String },

    #[error("`{tool}` not found on PATH: {hint}")]
    ToolMissing {
        tool: &'static str,
        hint: &'static str,
    },

    #[error("`{command}` failed ({status}){}{stderr}", if stderr.is_empty() { "" } else { ":\n" })]
    ToolFailed {
        command: String,
        status: String,
        stderr: String,
    },

    #[error("{}: sha256 mismatch: expected {expected}, got {got}{hint}", file.display())]
    DigestMismatch {
        file: PathBuf,
        expected: String,
        got: String,
        hint: String,
    },

    #[error("{archive}: `{member}` not found in the package")]
    MissingMember { archive: String, member: String },

    /// Writing into the cache failed (disk full, permissions).
    #[error("{}: {source}", path.display())]
    Io { path: PathBuf, source: io::Error },

    /// An environment setting of the fetch with a value it cannot use.
    #[error("{0}")]
    Setting(String),

    /// Archives that could not be fetched, each with its one-line reason; the others were.
    #[error("{} of {total} archives not fetched: {}", failed.len(), failed.join("; "))]
    NotFetched { failed: Vec<String>, total: usize },

    #[error("no cache directory: set PENUMBRA_CACHE, XDG_CACHE_HOME or HOME")]
    NoCacheDir,

    #[error("unknown asset group `{0}` (known: meshes, panoramas, trees)")]
    UnknownGroup(String),

    /// A fetched mesh loads, but not with the vertex/triangle counts the manifest records.
    #[error("{}: expected {expected}, loaded {found}", file.display())]
    CountMismatch {
        file: PathBuf,
        expected: String,
        found: String,
    },
}

pub type Result<T, E = AssetError> = std::result::Result<T, E>;

/// A parse problem before the file name is attached: parsers work on text or readers and
/// stay testable without files.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Failure {
    pub at: Option<Location>,
    pub message: String,
}

impl Failure {
    pub fn at(at: Location, message: impl Into<String>) -> Self {
        Failure {
            at: Some(at),
            message: message.into(),
        }
    }

    pub fn whole(message: impl Into<String>) -> Self {
        Failure {
            at: None,
            message: message.into(),
        }
    }

    pub fn in_file(self, file: &Path) -> AssetError {
        let file = file.to_path_buf();
        match self.at {
            Some(at) => AssetError::Malformed {
                file,
                at,
                message: self.message,
            },
            None => AssetError::Invalid {
                file,
                message: self.message,
            },
        }
    }
}

pub(crate) fn io_at(path: &Path) -> impl FnOnce(io::Error) -> AssetError + '_ {
    move |source| AssetError::Io {
        path: path.to_path_buf(),
        source,
    }
}
