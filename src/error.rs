//! The engine's error type; the lab's error wraps it with its own (reference, metrics, report, assets).

use std::path::Path;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A scene file (or built-in scene) is malformed; `origin` names the file.
    #[error("{origin}: {message}")]
    Scene { origin: String, message: String },
    /// A mesh file is missing, unreadable or malformed.
    #[error("{origin}: {message}")]
    Mesh { origin: String, message: String },
    /// No usable GPU adapter.
    #[error("{0}")]
    NoAdapter(String),
    /// A requested size exceeds what the device or the budget allows and cannot be split.
    #[error("{0}")]
    Limit(String),
    /// A kernel failed to compile or validate.
    #[error("kernel `{name}`: {message}")]
    Kernel { name: String, message: String },
    /// A GPU operation failed (device lost, validation, mapping).
    #[error("gpu: {0}")]
    Gpu(String),
    /// A method name or parameter is wrong.
    #[error("{0}")]
    Param(String),
    /// A render setting given by key (`key=value` over a scene's `[render]` table) is unknown or
    /// refuses its value. Its text names the key as the setting is spelled; each front end words
    /// it as its user writes it (the command line `--set key=value`, Python `key=value`).
    #[error("{}{key}{}: {why}", origin.as_ref().map(|o| format!("{o}: ")).unwrap_or_default(), value.as_ref().map(|v| format!("={v}")).unwrap_or_default())]
    Setting {
        /// The scene the setting was given for, where the message names it.
        origin: Option<String>,
        key: String,
        /// The value as given; `None` when the key alone is at fault (an unknown setting).
        value: Option<String>,
        why: String,
    },
    /// A run input named by what it is (the scene, the backend) is refused. Each front end words
    /// the input as its user gives it: the command line `--scene`, Python `scene=`.
    #[error("{input} {}: {why}", show_value(.value))]
    Input {
        input: Input,
        value: String,
        why: String,
    },
    /// A method is given the same parameter twice: in its spec and again apart from it (the
    /// command line's `--param`, Python's `params=`).
    #[error(
        "method `{spec}`: `{key}` is given twice ({first} in the spec, and {again} apart from it)"
    )]
    ParamTwice {
        spec: String,
        key: String,
        first: String,
        again: String,
    },
    /// A `cache:` mesh whose file is not in the asset cache; the front ends say how to fetch
    /// its group (the command line `penumbra assets fetch --group G`).
    #[error("{file}: not in the asset cache ({missing} is missing; asset group `{group}`)")]
    MissingAsset {
        /// The mesh as the scene names it, with where (`s.toml: mesh 2: file = "cache:…"`).
        file: String,
        missing: String,
        group: String,
    },
    /// A mesh file over the cap on mesh files (`scene::mesh_input::set_max_mesh_mib`); the front
    /// ends say how to raise it (the command line's `--max-mesh-mib`).
    #[error("{message}")]
    MeshCap { message: String, cap_mib: u64 },
    /// A counter overflowed its buffer on the GPU.
    #[error("overflow: {0}")]
    Overflow(String),
    /// Reading or writing a file failed.
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    /// A registry asset could not be found or loaded (the message names the file and the line
    /// or element); the asset layer the program registers says why.
    #[error("{0}")]
    Asset(String),
}

/// The run inputs an [`Error::Input`] can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Input {
    /// The scene: a built-in name or a scene file's path.
    Scene,
    /// The graphics backend asked for.
    Backend,
}

impl Input {
    /// The input's own name, as the engine says it and Python's keyword argument spells it.
    pub fn name(self) -> &'static str {
        match self {
            Input::Scene => "scene",
            Input::Backend => "backend",
        }
    }
}

impl std::fmt::Display for Input {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A value as an error line shows it: quoted where bare text would hide it (empty, or with
/// spaces), else as given.
pub fn show_value(value: &str) -> String {
    if value.is_empty() || value.chars().any(char::is_whitespace) {
        format!("{value:?}")
    } else {
        value.to_string()
    }
}

impl Error {
    pub fn scene(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Scene {
            origin: origin.into(),
            message: message.into(),
        }
    }
    pub fn mesh(origin: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Mesh {
            origin: origin.into(),
            message: message.into(),
        }
    }
    pub fn io(path: &Path, err: impl std::fmt::Display) -> Self {
        Error::Io {
            path: path.display().to_string(),
            message: err.to_string(),
        }
    }
}

/// `line L, column C` of a TOML error in `text` (1-based), when the error has a position.
pub fn toml_position(text: &str, e: &toml::de::Error) -> Option<(usize, usize)> {
    let start = e.span()?.start.min(text.len());
    let before = &text[..start];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Some((
        before.matches('\n').count() + 1,
        before[line_start..].chars().count() + 1,
    ))
}
