//! OFF meshes through off-rs, with errors reworded to name the line and what was expected.

use std::path::Path;

use off_rs::parser::error::{Error as OffError, Kind};
use off_rs::parser::options::{Limits, Options};

use super::error::{Failure, Location, Result};
use super::input::{max_mesh_bytes, read_text_capped};
use super::mesh::{LoadedMesh, MeshBuilder};

pub fn load_off(path: &Path) -> Result<LoadedMesh> {
    load_off_capped(path, max_mesh_bytes())
}

pub(crate) fn load_off_capped(path: &Path, max: u64) -> Result<LoadedMesh> {
    let text = read_text_capped(path, max)?;
    parse_off(&text).map_err(|failure| failure.in_file(path))
}

pub(crate) fn parse_off(text: &str) -> Result<LoadedMesh, Failure> {
    // The default limits stop at 10k vertices / 1k faces: every real scan is larger.
    let options = Options {
        limits: Limits::MAX,
        ..Options::default()
    };
    check_counts(text)?;
    let off = match off_rs::parse(text, options) {
        Ok(mesh) => mesh,
        Err(off_rs::Error::ParserError(e)) => return Err(reword(text, &e)),
        Err(off_rs::Error::IOError(e)) => return Err(Failure::whole(e.to_string())),
    };

    // off-rs keeps no line numbers for elements; OFF puts the header and the counts on the
    // first two content lines, then one vertex or face per content line.
    let line_of = |content_index: usize| content_line(text, content_index);
    let vertex_count = off.vertices.len();
    let mut builder = MeshBuilder::new(vertex_count, off.faces.len());
    for (i, v) in off.vertices.iter().enumerate() {
        let p = v.position;
        builder
            .vertex([p.x.into(), p.y.into(), p.z.into()])
            .map_err(|m| Failure::at(element("vertex", i, line_of(2 + i)), m))?;
    }
    let mut face = Vec::new();
    for (j, f) in off.faces.iter().enumerate() {
        face.clear();
        // usize -> i64 saturates only beyond any real vertex count; the range check catches it.
        face.extend(
            f.vertices
                .iter()
                .map(|&v| i64::try_from(v).unwrap_or(i64::MAX)),
        );
        builder
            .face(&face)
            .map_err(|m| Failure::at(element("face", j, line_of(2 + vertex_count + j)), m))?;
    }
    builder.finish().map_err(Failure::whole)
}

/// A header that claims more vertices or faces than the file holds would make off-rs read faces as
/// vertices (and report an "invalid color"): compare the counts with the lines first.
fn check_counts(text: &str) -> Result<(), Failure> {
    let content: Vec<(usize, Vec<&str>)> = text
        .lines()
        .enumerate()
        .map(|(n, l)| (n + 1, tokens(l)))
        .filter(|(_, t)| !t.is_empty())
        .collect();
    let Some((_, header)) = content.first() else {
        return Ok(());
    };
    if !header[0].ends_with("OFF") {
        return Ok(()); // off-rs words the header error
    }
    let (line, counts, rest) = if header.len() > 1 {
        (content[0].0, header[1..].to_vec(), &content[1..])
    } else if let Some((line, counts)) = content.get(1) {
        (*line, counts.clone(), content.get(2..).unwrap_or(&[]))
    } else {
        return Ok(());
    };
    let (Some(Ok(vertices)), Some(Ok(faces))) = (
        counts.first().map(|v| v.parse::<usize>()),
        counts.get(1).map(|f| f.parse::<usize>()),
    ) else {
        return Ok(()); // off-rs words bad counts
    };
    if rest.len() < vertices.saturating_add(faces) {
        return Err(Failure::at(
            Location::Line(line),
            format!("file ends early: the counts say {vertices} vertices and {faces} faces, but only {} lines follow", rest.len()),
        ));
    }
    Ok(())
}

fn element(kind: &str, index: usize, line: Option<usize>) -> Location {
    Location::Element {
        kind: kind.to_string(),
        index,
        line,
    }
}

/// Tokens of a line as off-rs sees them: `#` starts a comment.
fn tokens(line: &str) -> Vec<&str> {
    line.split('#')
        .next()
        .unwrap_or("")
        .split_whitespace()
        .collect()
}

/// 1-based number of the `index`-th (0-based) line that holds something besides comments.
fn content_line(text: &str, index: usize) -> Option<usize> {
    text.lines()
        .enumerate()
        .filter(|(_, line)| !tokens(line).is_empty())
        .nth(index)
        .map(|(n, _)| n + 1)
}

fn first_unparsable<T: std::str::FromStr>(parts: &[&str]) -> Option<String> {
    parts
        .iter()
        .find(|t| t.parse::<T>().is_err())
        .map(|t| t.to_string())
}

/// off-rs reports a kind and a line; say in words what that line should have held.
fn reword(text: &str, e: &OffError) -> Failure {
    let line_number = e.line_index + 1;
    let line = text.lines().nth(e.line_index).unwrap_or("");
    let parts = tokens(line);
    let detail = std::error::Error::source(e)
        .map(|s| s.to_string())
        .unwrap_or_default();
    let message = match e.kind {
        Kind::Empty => return Failure::whole("empty file: no `OFF` header"),
        Kind::InvalidHeader => format!("expected the header `OFF`, found `{}`", line.trim()),
        Kind::Missing => format!("file ends early: {}", lowercase_first(&detail)),
        Kind::InvalidCounts => format!(
            "expected the counts `vertices faces [edges]`, found `{}`",
            parts.join(" ")
        ),
        Kind::InvalidVertexPosition if parts.len() < 3 => {
            format!("expected 3 coordinates, found {}", parts.len())
        }
        Kind::InvalidVertexPosition => match first_unparsable::<f32>(&parts[..3]) {
            Some(token) => format!("coordinate `{token}` is not a number"),
            None => format!("invalid vertex: {detail}"),
        },
        Kind::InvalidFaceIndex => match first_unparsable::<usize>(parts.get(1..).unwrap_or(&[])) {
            Some(token) => format!("vertex index `{token}` is not a non-negative integer"),
            None => format!("invalid face: {detail}"),
        },
        Kind::InvalidFace => reword_face(&parts, &detail),
        Kind::InvalidColor => format!("invalid color: {}", lowercase_first(&detail)),
        Kind::LimitExceeded => lowercase_first(&detail),
    };
    Failure::at(Location::Line(line_number), message)
}

fn reword_face(parts: &[&str], detail: &str) -> String {
    let Some((count, indices)) = parts.split_first() else {
        return format!("invalid face: {}", lowercase_first(detail));
    };
    match count.parse::<usize>() {
        Err(_) => format!("face vertex count `{count}` is not a non-negative integer"),
        Ok(n) if n < 3 => format!("a face needs at least 3 vertices, this one declares {n}"),
        Ok(n) if indices.len() < n => {
            format!("expected {n} vertex indices, found {}", indices.len())
        }
        Ok(_) => format!("invalid face: {}", lowercase_first(detail)),
    }
}

fn lowercase_first(s: &str) -> String {
    let mut chars = s.chars();
    match chars.next() {
        Some(c) => c.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}
