//! PLY meshes (ASCII and binary, optionally gzip) through ply-rs-bw.
//!
//! Elements are read one at a time rather than with `read_payload`, so that every error can
//! name the element (`face 1032`) and, in ASCII files, its line.

use std::io::BufRead;
use std::path::Path;

use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyAccess, PropertyAccessResult};
use ply_rs_bw::ply::{PropertyType, ScalarType};

use super::error::{Failure, Location, Result};
use super::input;
use super::mesh::{LoadedMesh, MeshBuilder};

pub fn load_ply(path: &Path) -> Result<LoadedMesh> {
    load_ply_capped(path, input::max_mesh_bytes())
}

pub(crate) fn load_ply_capped(path: &Path, max: u64) -> Result<LoadedMesh> {
    parse_ply(input::open_capped(path, max)?).map_err(|failure| failure.in_file(path))
}

const FACE_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

pub(crate) fn parse_ply(input: impl BufRead) -> Result<LoadedMesh, Failure> {
    let mut reader = Reader::new(input);
    let parser = Parser::<Item>::new();
    let header = parser
        .read_header(&mut reader)
        .map_err(|e| header_failure(&e))?;
    let (vertex_count, face_count) = check_header(&header)?;
    // After the header, the reader's line counter points at the first payload line.
    let mut line = reader.line();

    let mut builder = MeshBuilder::new(vertex_count, face_count);
    let mut text = String::new();
    for def in header.elements.values() {
        for index in 0..def.count {
            let at = Location::Element {
                kind: def.name.clone(),
                index,
                line: (header.encoding == Encoding::Ascii).then_some(line),
            };
            let early_end = || {
                let found = format!("found {index} of {} `{}` elements", def.count, def.name);
                Failure::at(at.clone(), format!("file ends early: {found}"))
            };
            let item = match header.encoding {
                Encoding::Ascii => {
                    text.clear();
                    let read = reader.get_mut().read_line(&mut text);
                    if read.map_err(|e| Failure::at(at.clone(), e.to_string()))? == 0 {
                        return Err(early_end());
                    }
                    line += 1;
                    parser.read_ascii_element(&text, def).map_err(|e| {
                        Failure::at(
                            at.clone(),
                            ascii_message(&text, def).unwrap_or_else(|| flat(&e)),
                        )
                    })?
                }
                Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
                    let read = if header.encoding == Encoding::BinaryLittleEndian {
                        parser.read_little_endian_element(reader.get_mut(), def)
                    } else {
                        parser.read_big_endian_element(reader.get_mut(), def)
                    };
                    read.map_err(|e| match e.kind() {
                        std::io::ErrorKind::UnexpectedEof => early_end(),
                        _ => Failure::at(at.clone(), flat(&e)),
                    })?
                }
            };
            let added = match def.name.as_str() {
                "vertex" => builder.vertex(item.xyz),
                "face" => builder.face(&item.indices),
                _ => Ok(()), // normals, edges, materials: not needed for shadows
            };
            added.map_err(|m| Failure::at(at, m))?;
        }
    }
    builder.finish().map_err(Failure::whole)
}

/// Checks what the loader needs before reading any payload; returns the element counts.
fn check_header(header: &Header) -> Result<(usize, usize), Failure> {
    let vertex = header
        .elements
        .get("vertex")
        .ok_or_else(|| Failure::whole("no `vertex` element in the header"))?;
    for axis in ["x", "y", "z"] {
        match vertex.properties.get(axis).map(|p| &p.data_type) {
            Some(PropertyType::Scalar(_)) => {}
            Some(PropertyType::List(..)) => {
                return Err(Failure::whole(format!(
                    "vertex property `{axis}` is a list"
                )));
            }
            None => return Err(Failure::whole(format!("vertex has no property `{axis}`"))),
        }
    }
    let face = header
        .elements
        .get("face")
        .ok_or_else(|| Failure::whole("no `face` element in the header (a point cloud?)"))?;
    let list = face_list(face).ok_or_else(|| {
        Failure::whole("face has no integer list property `vertex_indices` or `vertex_index`")
    })?;
    if matches!(list, ScalarType::Float | ScalarType::Double) {
        return Err(Failure::whole(
            "face vertex indices are floats, not integers",
        ));
    }
    Ok((vertex.count, face.count))
}

fn face_list(face: &ElementDef) -> Option<&ScalarType> {
    FACE_LISTS
        .iter()
        .find_map(|name| match &face.properties.get(*name)?.data_type {
            PropertyType::List(_, item) => Some(item),
            PropertyType::Scalar(_) => None,
        })
}

/// Says what is wrong with an ASCII line that ply-rs-bw rejected, in the common cases:
/// a value that is not a finite number (its grammar has no `nan`), or too few values.
fn ascii_message(text: &str, def: &ElementDef) -> Option<String> {
    let tokens: Vec<&str> = text.split_whitespace().collect();
    let names: Vec<&str> = def.properties.keys().map(String::as_str).collect();
    let all_scalar = def
        .properties
        .values()
        .all(|p| matches!(p.data_type, PropertyType::Scalar(_)));
    let bad = tokens
        .iter()
        .position(|t| !t.parse::<f64>().is_ok_and(f64::is_finite));
    if let Some(i) = bad {
        let token = tokens[i];
        let what = match names.get(i).filter(|_| all_scalar) {
            Some(name) if def.name == "vertex" && ["x", "y", "z"].contains(name) => {
                format!("coordinate {name}")
            }
            Some(name) => format!("property `{name}`"),
            None => format!("value `{token}`"),
        };
        return Some(match token.parse::<f64>() {
            Ok(v) if v.is_nan() => format!("{what} is NaN"),
            Ok(v) => format!("{what} is {v}"),
            Err(_) if what.ends_with('`') => format!("{what} is not a number"),
            Err(_) => format!("{what} is `{token}`, not a number"),
        });
    }
    (all_scalar && tokens.len() < names.len()).then(|| {
        format!(
            "expected {} values ({}), found {}",
            names.len(),
            names.join(" "),
            tokens.len()
        )
    })
}

/// ply-rs-bw messages span several tab-indented lines; keep them on one.
fn flat(e: &ParseError) -> String {
    let text = e.to_string();
    let text = match e.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .unwrap_or(&text)
            .to_string(),
        None => text,
    };
    text.split(['\n', '\t'])
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// The header parser's errors carry a debug dump of its grammar: say instead what the line was.
fn header_failure(e: &ParseError) -> Failure {
    let text = e.to_string();
    let message = match text.split("String: '").nth(1).and_then(|rest| rest.split('\'').next()) {
        Some(line) if e.line() == Some(1) => format!("not a PLY file: the first line must be `ply` (the magic number), found `{}`", line.trim()),
        Some(line) => format!(
            "header line `{}` is not a PLY header line (expected ply, format, comment, obj_info, element, property or end_header); is the header cut short?",
            line.trim()
        ),
        None if text.contains("Error:") || text.contains("{") => "the header is malformed or cut short before `end_header`".to_string(),
        None => flat(e),
    };
    Failure {
        at: e.line().map(Location::Line),
        message,
    }
}

/// One PLY element: only what a vertex or a face needs, whatever the declared number types.
#[derive(Default)]
struct Item {
    xyz: [f64; 3],
    indices: Vec<i64>,
}

impl Item {
    fn coordinate(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return PropertyAccessResult::Ignored,
        };
        self.xyz[axis] = value;
        PropertyAccessResult::Set
    }

    fn list<T: Into<i64>>(&mut self, name: &str, values: Vec<T>) -> PropertyAccessResult {
        if !FACE_LISTS.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        self.indices = values.into_iter().map(Into::into).collect();
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Item {
    fn new() -> Self {
        Item::default()
    }
    fn set_char(&mut self, name: &str, v: i8) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_uchar(&mut self, name: &str, v: u8) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_short(&mut self, name: &str, v: i16) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_ushort(&mut self, name: &str, v: u16) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_int(&mut self, name: &str, v: i32) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_uint(&mut self, name: &str, v: u32) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_float(&mut self, name: &str, v: f32) -> PropertyAccessResult {
        self.coordinate(name, v.into())
    }
    fn set_double(&mut self, name: &str, v: f64) -> PropertyAccessResult {
        self.coordinate(name, v)
    }
    fn set_list_char(&mut self, name: &str, v: Vec<i8>) -> PropertyAccessResult {
        self.list(name, v)
    }
    fn set_list_uchar(&mut self, name: &str, v: Vec<u8>) -> PropertyAccessResult {
        self.list(name, v)
    }
    fn set_list_short(&mut self, name: &str, v: Vec<i16>) -> PropertyAccessResult {
        self.list(name, v)
    }
    fn set_list_ushort(&mut self, name: &str, v: Vec<u16>) -> PropertyAccessResult {
        self.list(name, v)
    }
    fn set_list_int(&mut self, name: &str, v: Vec<i32>) -> PropertyAccessResult {
        self.list(name, v)
    }
    fn set_list_uint(&mut self, name: &str, v: Vec<u32>) -> PropertyAccessResult {
        self.list(name, v)
    }
}
