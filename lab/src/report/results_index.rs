//! `penumbra report --index results`: the index of the results folders, written into
//! `results/README.md` between two marker lines, one row per folder with its README's title, so
//! the index cannot miss a folder (a lab test holds the committed README to it).

use std::path::{Path, PathBuf};

use super::ReportError;
use crate::Result;

/// The line above the index, naming the command that writes it.
pub const BEGIN: &str = "<!-- index: written by `penumbra report --index results` -->";
/// The line below it.
pub const END: &str = "<!-- end of index -->";

/// A folder's title: its README's first heading, less a leading `<folder>: ` the index's first
/// column already says.
fn title(dir: &Path, name: &str) -> Result<String> {
    let readme = dir.join("README.md");
    let text = std::fs::read_to_string(&readme).map_err(|e| ReportError::Results {
        path: readme.clone(),
        message: format!("a results folder needs its README.md: {e}"),
    })?;
    let heading = text
        .lines()
        .find_map(|l| l.strip_prefix("# "))
        .ok_or_else(|| ReportError::Results {
            path: readme.clone(),
            message: "no `# ` title line".into(),
        })?;
    let heading = heading.trim();
    Ok(heading
        .strip_prefix(&format!("{name}: "))
        .unwrap_or(heading)
        .replace('|', "\\|"))
}

/// The index table of every folder under `root`, by name.
pub fn table(root: &Path) -> Result<String> {
    let io = |source| ReportError::Io {
        path: root.to_path_buf(),
        source,
    };
    let mut names: Vec<String> = std::fs::read_dir(root)
        .map_err(io)?
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    names.sort();
    let mut s = String::from("| folder | what |\n|---|---|\n");
    for n in &names {
        s += &format!("| `{n}/` | {} |\n", title(&root.join(n), n)?);
    }
    Ok(s)
}

/// `readme` with the text between its marker lines replaced by `index`.
pub fn splice(readme: &str, index: &str, path: &Path) -> Result<String> {
    let missing = |what: &str| ReportError::Results {
        path: path.to_path_buf(),
        message: format!("no line {what}: the index goes between `{BEGIN}` and `{END}`"),
    };
    let start = readme.find(BEGIN).ok_or_else(|| missing(BEGIN))? + BEGIN.len();
    let end = readme[start..].find(END).ok_or_else(|| missing(END))? + start;
    Ok(format!("{}\n{index}{}", &readme[..start], &readme[end..]))
}

/// Rewrites the index in `root/README.md` (read and checked before anything is written; the file
/// replaced whole by a rename); returns its path.
pub fn write(root: &Path) -> Result<PathBuf> {
    let path = root.join("README.md");
    let readme = std::fs::read_to_string(&path).map_err(|source| ReportError::Io {
        path: path.clone(),
        source,
    })?;
    let text = splice(&readme, &table(root)?, &path)?;
    super::files::write_atomic(&path, text.as_bytes())?;
    Ok(path)
}
