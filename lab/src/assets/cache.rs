//! Where fetched assets live: outside git, shared by every checkout of the project.

use std::ffi::OsString;
use std::path::PathBuf;

use super::error::{AssetError, Result};

/// `$PENUMBRA_CACHE`, else `$XDG_CACHE_HOME/penumbra`, else `~/.cache/penumbra`.
pub fn default_cache_dir() -> Result<PathBuf> {
    let var = |name| std::env::var_os(name).filter(|v| !v.is_empty());
    cache_dir_from(var("PENUMBRA_CACHE"), var("XDG_CACHE_HOME"), var("HOME"))
}

fn cache_dir_from(
    penumbra: Option<OsString>,
    xdg: Option<OsString>,
    home: Option<OsString>,
) -> Result<PathBuf> {
    if let Some(dir) = penumbra {
        return Ok(dir.into());
    }
    // The XDG spec says to ignore a relative XDG_CACHE_HOME.
    if let Some(xdg) = xdg.map(PathBuf::from).filter(|p| p.is_absolute()) {
        return Ok(xdg.join("penumbra"));
    }
    home.map(|h| PathBuf::from(h).join(".cache/penumbra"))
        .ok_or(AssetError::NoCacheDir)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(p: Option<&str>, x: Option<&str>, h: Option<&str>) -> Option<PathBuf> {
        cache_dir_from(p.map(Into::into), x.map(Into::into), h.map(Into::into)).ok()
    }

    #[test]
    fn precedence() {
        assert_eq!(dir(Some("/c"), Some("/x"), Some("/h")), Some("/c".into()));
        assert_eq!(
            dir(None, Some("/x"), Some("/h")),
            Some("/x/penumbra".into())
        );
        assert_eq!(
            dir(None, Some("rel"), Some("/h")),
            Some("/h/.cache/penumbra".into())
        );
        assert_eq!(dir(None, None, None), None);
    }
}
