//! `penumbra merge DIR… --out DIR`: the shards of one sweep joined into one output, rows in the
//! spec's order, as if one process had run the whole grid. Shards of different specs, crate
//! versions, adapters or scenes are refused unless `--allow` names the difference.

use crate::record::{self, Provenance, SpecRef};
use crate::report::charts::ResultRow;
use crate::report::results::{read_results, LoadedRow};
use crate::studies::compare::REFERENCE_FILES;
use crate::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Differences `--allow` can accept.
pub const ALLOWABLE: &[&str] = &["spec", "version", "adapter", "scene", "partial"];

/// Parses `--allow spec,version`.
pub fn parse_allow(values: &[String]) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for v in values
        .iter()
        .flat_map(|v| v.split(','))
        .map(str::trim)
        .filter(|v| !v.is_empty())
    {
        if !ALLOWABLE.contains(&v) {
            return Err(Error::param(format!(
                "--allow `{v}`: not one of {}",
                ALLOWABLE.join(", ")
            )));
        }
        out.push(v.to_string());
    }
    Ok(out)
}

/// One input folder and what it holds.
struct Input {
    dir: PathBuf,
    rows: Vec<LoadedRow>,
    spec: SpecRef,
}

pub struct MergeOutcome {
    pub rows: Vec<ResultRow>,
    /// Every output file but the report.
    pub files: Vec<(String, Vec<u8>)>,
    /// One line per input: folder, shard, rows.
    pub inputs: Vec<String>,
}

fn spec_of<'a>(path: &Path, r: &'a ResultRow) -> Result<(&'a Provenance, &'a SpecRef)> {
    let p = r.provenance.as_ref();
    p.and_then(|p| Some((p, p.spec.as_ref()?))).ok_or_else(|| {
        Error::param(format!(
            "merge: {}: row `{}` records no sweep spec (merge joins `penumbra sweep` shards)",
            path.display(),
            r.label()
        ))
    })
}

fn text(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Object(m) => m
            .values()
            .map(|x| {
                x.as_str()
                    .map(String::from)
                    .unwrap_or_else(|| x.to_string())
            })
            .collect::<Vec<_>>()
            .join(" "),
        other => other.to_string(),
    }
}

fn read(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|e| Error::io(path, format!("cannot read: {e}")))
}

/// Reads, checks and joins the shards; nothing is written.
pub fn merge(dirs: &[PathBuf], allow: &[String]) -> Result<MergeOutcome> {
    if dirs.is_empty() {
        return Err(Error::param("merge: give at least one shard folder".into()));
    }
    let allowed = |what: &str| allow.iter().any(|a| a == what);
    let mut inputs: Vec<Input> = Vec::new();
    for dir in dirs {
        let path = dir.join("results.jsonl");
        if !path.is_file() {
            return Err(Error::io(
                &path,
                "no results.jsonl in this folder (is it a sweep's --out?)",
            ));
        }
        // A shard's unreadable rows are merge's error, not the report's.
        let rows = read_results(&path).map_err(|e| match e {
            Error::Report(crate::report::ReportError::Results { path, message }) => {
                Error::param(format!("merge: {}: {message}", path.display()))
            }
            e => e,
        })?;
        let (_, spec) = spec_of(&path, &rows[0].row)?;
        let spec = spec.clone();
        for r in &rows {
            let (_, s) = spec_of(&path, &r.row)?;
            if s.shard != spec.shard || s.sha256 != spec.sha256 {
                return Err(Error::param(format!(
                    "merge: {}: rows of more than one shard or spec in one file",
                    path.display()
                )));
            }
        }
        inputs.push(Input {
            dir: dir.clone(),
            rows,
            spec,
        });
    }

    // Everything must match the first input, unless allowed.
    let first = &inputs[0];
    let (p0, r0) = (
        first.rows[0].row.provenance.clone().unwrap_or_default(),
        first.rows[0].row.clone(),
    );
    for input in &inputs {
        for l in &input.rows {
            let r = &l.row;
            let p = r.provenance.as_ref().expect("checked above");
            let at = |what: &str, a: String, b: String, flag: &str| {
                Error::param(format!(
                    "merge: {} has {what} {a}, {} has {b} (pass --allow {flag} to merge anyway)",
                    input.dir.display(),
                    first.dir.display()
                ))
            };
            if input.spec.sha256 != first.spec.sha256 && !allowed("spec") {
                return Err(at(
                    "sweep spec",
                    format!("{} (sha256 {:.12})", input.spec.file, input.spec.sha256),
                    format!("{} (sha256 {:.12})", first.spec.file, first.spec.sha256),
                    "spec",
                ));
            }
            if r.core.version != r0.core.version && !allowed("version") {
                return Err(at(
                    "version",
                    text(&r.core.version),
                    text(&r0.core.version),
                    "version",
                ));
            }
            if r.core.adapter != r0.core.adapter && !allowed("adapter") {
                return Err(at(
                    "adapter",
                    text(&r.core.adapter),
                    text(&r0.core.adapter),
                    "adapter",
                ));
            }
            let scene = |p: &Provenance, r: &ResultRow| {
                format!(
                    "{} {} (sha256 {:.12}, {:?})",
                    r.core.scene, p.scene_file, p.geometry_sha256, p.overrides
                )
            };
            if (p.scene_sha256 != p0.scene_sha256
                || p.geometry_sha256 != p0.geometry_sha256
                || p.overrides != p0.overrides
                || r.resolution != r0.resolution)
                && !allowed("scene")
            {
                return Err(at("scene", scene(p, r), scene(&p0, &r0), "scene"));
            }
        }
    }

    // Shards: one count, each index at most once, all present unless `partial`.
    let count = first.spec.shard[1];
    let mut seen: BTreeMap<u32, &Path> = BTreeMap::new();
    for input in &inputs {
        let [i, n] = input.spec.shard;
        if n != count && !allowed("spec") {
            return Err(Error::param(format!(
                "merge: {} is shard {i}/{n}, {} is of {count} shards",
                input.dir.display(),
                first.dir.display()
            )));
        }
        if let Some(prev) = seen.insert(i, &input.dir) {
            if input.spec.sha256 == first.spec.sha256 {
                return Err(Error::param(format!(
                    "merge: shard {i}/{n} given twice ({} and {})",
                    prev.display(),
                    input.dir.display()
                )));
            }
        }
    }
    let missing: Vec<String> = (0..count)
        .filter(|i| !seen.contains_key(i))
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() && !allowed("partial") {
        return Err(Error::param(format!(
            "merge: shards {} are missing (pass --allow partial to merge what is here)",
            missing.join(", ")
        )));
    }

    // Rows in the spec's order (inputs in the order given when specs differ).
    let mut rows: Vec<(usize, usize, &LoadedRow)> = Vec::new();
    for (k, input) in inputs.iter().enumerate() {
        let key = if input.spec.sha256 == first.spec.sha256 {
            0
        } else {
            k
        };
        rows.extend(input.rows.iter().map(|l| {
            (
                key,
                l.row
                    .provenance
                    .as_ref()
                    .and_then(|p| p.spec.as_ref())
                    .map_or(0, |s| s.config),
                l,
            )
        }));
    }
    rows.sort_by_key(|(k, c, _)| (*k, *c));
    if let Some(w) = rows
        .windows(2)
        .find(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
    {
        return Err(Error::param(format!(
            "merge: configuration {} (`{}`) appears in two shards",
            w[1].1,
            w[1].2.row.label()
        )));
    }

    // Pictures: each row's folder copied under its slug in the merged list; the reference once
    // (per differing reference, when scenes differ and that was allowed).
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let mut references: Vec<(PathBuf, Vec<u8>, String)> = Vec::new(); // (input dir, reference.exr bytes, folder in the output)
    let labels: Vec<String> = rows.iter().map(|(_, _, l)| l.row.label()).collect();
    let slugs = crate::report::unique_slugs(labels.iter().map(String::as_str));
    let mut out_rows = Vec::new();
    for ((_, _, l), slug) in rows.iter().zip(&slugs) {
        let mut row = l.row.clone();
        let mut images = BTreeMap::new();
        if let Some(shaded) = row.images.get("shaded") {
            let old_dir = l
                .base
                .join(shaded)
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default();
            let entries = std::fs::read_dir(&old_dir)
                .map_err(|e| Error::io(&old_dir, format!("cannot list: {e}")))?;
            let mut names: Vec<String> = entries
                .filter_map(|e| e.ok())
                .filter(|e| e.path().is_file())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect();
            names.sort();
            for name in names.iter().filter(|n| !n.starts_with('.')) {
                files.push((format!("images/{slug}/{name}"), read(&old_dir.join(name))?));
            }
            for (key, rel) in &row.images {
                let name = Path::new(rel)
                    .file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default();
                if key != "reference" {
                    images.insert(key.clone(), format!("images/{slug}/{name}"));
                }
            }
        }
        if row.images.contains_key("reference") {
            let base = l.base.clone();
            let exr = read(&base.join("reference.exr"))?;
            let folder = match references.iter().find(|(d, b, _)| *d == base || *b == exr) {
                Some((_, _, f)) => f.clone(),
                None => {
                    let f = if references.is_empty() {
                        String::new()
                    } else {
                        format!("references/{}/", references.len())
                    };
                    for name in REFERENCE_FILES {
                        files.push((format!("{f}{name}"), read(&base.join(name))?));
                    }
                    references.push((base, exr, f.clone()));
                    f
                }
            };
            images.insert("reference".into(), format!("{folder}reference_shaded.png"));
        }
        row.images = images;
        out_rows.push(row);
    }
    let inputs_text: Vec<String> = inputs
        .iter()
        .map(|i| {
            format!(
                "{}: shard {}/{} of {} (sha256 {:.12}), {} rows",
                i.dir.display(),
                i.spec.shard[0],
                i.spec.shard[1],
                i.spec.file,
                i.spec.sha256,
                i.rows.len()
            )
        })
        .collect();
    let record = serde_json::json!({ "inputs": inputs_text, "allowed": allow, "missing_shards": missing, "rows": out_rows.len() });
    files.push((
        "merge.json".into(),
        serde_json::to_vec_pretty(&record).unwrap_or_default(),
    ));
    files.extend(record::result_files(&out_rows)?);
    Ok(MergeOutcome {
        rows: out_rows,
        files,
        inputs: inputs_text,
    })
}
