//! OBJ meshes through tobj, after a line-by-line check so errors name the file and line.

use super::mesh_input;
use super::raw_mesh::RawMesh;
use crate::{Error, Result};
use glam::Vec3;
use std::path::Path;

/// The text of a mesh embedded in the binary (provenance digests it).
pub fn embedded_source(file: &str) -> Option<&'static str> {
    super::builtin::embedded_mesh(file)
}

/// An OBJ embedded in the binary (built-in scenes: every scenes/*.obj).
pub(crate) fn load_embedded(file: &str) -> Result<RawMesh> {
    let text = super::builtin::embedded_mesh(file).ok_or_else(|| Error::mesh(file, "not a mesh file shipped in scenes/ (built-in scenes can only name those, or `cache:` paths)"))?;
    parse(text, file)
}

/// Reads at most `max` bytes; the caller has checked it is a regular file within the cap, and
/// the read stays bounded should it grow meanwhile.
pub(crate) fn load_file(path: &Path, max: u64) -> Result<RawMesh> {
    use std::io::Read;
    let label = path.display().to_string();
    let cannot = |e: std::io::Error| Error::mesh(&label, format!("cannot read: {e}"));
    let mut bytes = Vec::new();
    mesh_input::open_regular(path, max)
        .map_err(cannot)?
        .take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(cannot)?;
    if bytes.len() as u64 > max {
        return Err(Error::MeshCap {
            message: format!(
                "{label}: grew past the {} MiB cap on mesh files while being read",
                max >> 20
            ),
            cap_mib: max >> 20,
        });
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| Error::mesh(&label, "not a text OBJ file (invalid UTF-8)"))?;
    parse(&text, &label)
}

/// Checks every `v` and `f` line, then lets tobj triangulate.
pub(crate) fn parse(text: &str, label: &str) -> Result<RawMesh> {
    check_lines(text, label)?;
    let mut reader = std::io::BufReader::new(text.as_bytes());
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| Error::mesh(label, format!("malformed OBJ: {e}")))?;
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for m in models {
        let base = positions.len() as u32;
        positions.extend(
            m.mesh
                .positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        indices.extend(m.mesh.indices.iter().map(|i| i + base));
    }
    if indices.is_empty() {
        return Err(Error::mesh(label, "the mesh is empty (no faces)"));
    }
    // Normals are recomputed after the transform: files disagree on whether theirs are smooth.
    Ok(RawMesh {
        positions,
        normals: None,
        indices,
    })
}

fn check_lines(text: &str, label: &str) -> Result<()> {
    // Vertices, texture coordinates and normals defined so far: indices (also negative, relative
    // ones) must fall inside them. tobj's own arithmetic overflows on some that do not.
    let (mut vertices, mut texcoords, mut normals) = (0i64, 0i64, 0i64);
    for (n, line) in text.lines().enumerate() {
        let at = |msg: String| Error::mesh(label, format!("line {}: {msg}", n + 1));
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<&str> = words.collect();
                if coords.len() < 3 {
                    return Err(at(format!(
                        "vertex needs 3 coordinates, found {}",
                        coords.len()
                    )));
                }
                for c in &coords[..3] {
                    let x: f32 = c
                        .parse()
                        .map_err(|_| at(format!("vertex coordinate `{c}` is not a number")))?;
                    if !x.is_finite() {
                        return Err(at(format!("vertex coordinate `{c}` is NaN or infinite")));
                    }
                }
                vertices += 1;
            }
            Some("vt") => texcoords += 1,
            Some("vn") => normals += 1,
            // tobj reads line elements (`l`) as faces, with the same index arithmetic.
            Some(kind @ ("f" | "l")) => {
                let corners: Vec<&str> = words.collect();
                let (least, element) = if kind == "f" {
                    (3, "face")
                } else {
                    (2, "line element")
                };
                if corners.len() < least {
                    return Err(at(format!(
                        "{element} needs at least {least} corners, found {}",
                        corners.len()
                    )));
                }
                let form = |c: &str| c.split('/').map(|p| p.is_empty()).collect::<Vec<bool>>();
                for c in &corners {
                    if form(c) != form(corners[0]) {
                        return Err(at(format!(
                            "{element} mixes corner forms `{}` and `{c}`",
                            corners[0]
                        )));
                    }
                    let parts: Vec<&str> = c.split('/').collect();
                    if parts.len() > 3 {
                        return Err(at(format!("{element} corner `{c}` has more than v/vt/vn")));
                    }
                    for (k, (part, count, what)) in [(parts[0], vertices, "vertex")]
                        .into_iter()
                        .chain(parts.get(1).map(|p| (*p, texcoords, "texture coordinate")))
                        .chain(parts.get(2).map(|p| (*p, normals, "normal")))
                        .enumerate()
                    {
                        if part.is_empty() && k > 0 {
                            continue;
                        }
                        let i: i64 = part
                            .parse()
                            .map_err(|_| at(format!("{element} index `{c}` is not an integer")))?;
                        let resolved = if i < 0 {
                            count.saturating_add(i).saturating_add(1)
                        } else {
                            i
                        };
                        if i == 0 || resolved < 1 || resolved > count {
                            return Err(at(format!(
                                "{element} references {what} {i}, but {count} are defined so far"
                            )));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_the_line_of_a_bad_vertex_or_face() {
        let e = parse("v 0 0 0\nv 1 0 nan\n", "x.obj")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "x.obj: line 2: vertex coordinate `nan` is NaN or infinite"
        );
        let e = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "x.obj")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("vertex 4"), "{e}");
        let e = parse("v 0 0\n", "x.obj").unwrap_err().to_string();
        assert!(e.contains("line 1: vertex needs 3 coordinates"), "{e}");
        let e = parse("# nothing\n", "x.obj").unwrap_err().to_string();
        assert!(e.contains("empty"), "{e}");
        // Found by the OBJ fuzz target: a line element's relative normal index before any normal
        // overflowed tobj's index arithmetic.
        let e = parse(
            "v 0 0 1\nv 0 0 0\nv 0 2 0\nvt 0 0\nvn 0 0 1\nl 3/1/-3 1/1/1\n",
            "x.obj",
        )
        .unwrap_err()
        .to_string();
        assert_eq!(
            e,
            "x.obj: line 6: line element references normal -3, but 1 are defined so far"
        );
        let e = parse("v 0 0 0\nl 1\n", "x.obj").unwrap_err().to_string();
        assert_eq!(
            e,
            "x.obj: line 2: line element needs at least 2 corners, found 1"
        );
        let ok = parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "x.obj").unwrap();
        assert_eq!(ok.indices.len(), 6);
    }
}
