//! Meshes shipped as JavaScript modules (npm `bunny`, `teapot`): `positions = [[x,y,z],…]`
//! and `cells = [[i,j,k],…]` array literals, read from the text so no JS runtime is needed.

use std::path::Path;

use super::error::{Failure, Location, Result};
use super::input::{max_mesh_bytes, read_text_capped};
use super::mesh::{LoadedMesh, MeshBuilder};

pub fn load_js_arrays(path: &Path) -> Result<LoadedMesh> {
    load_js_arrays_capped(path, max_mesh_bytes())
}

pub(crate) fn load_js_arrays_capped(path: &Path, max: u64) -> Result<LoadedMesh> {
    let text = read_text_capped(path, max)?;
    parse_js_arrays(&text).map_err(|failure| failure.in_file(path))
}

pub(crate) fn parse_js_arrays(text: &str) -> Result<LoadedMesh, Failure> {
    let positions = named_array(text, "positions")?;
    let cells = named_array(text, "cells")?;

    let mut builder = MeshBuilder::new(positions.len(), cells.len());
    for (index, p) in positions.iter().enumerate() {
        let at = || Location::Item {
            array: "positions",
            index,
        };
        let xyz: [f64; 3] = p
            .as_slice()
            .try_into()
            .map_err(|_| Failure::at(at(), format!("expected 3 coordinates, found {}", p.len())))?;
        builder.vertex(xyz).map_err(|m| Failure::at(at(), m))?;
    }
    let mut face = Vec::new();
    for (index, cell) in cells.iter().enumerate() {
        let at = || Location::Item {
            array: "cells",
            index,
        };
        face.clear();
        for &v in cell {
            if v.fract() != 0.0 || !v.is_finite() || v.abs() > 1e15 {
                return Err(Failure::at(
                    at(),
                    format!("vertex index {v} is not an integer"),
                ));
            }
            face.push(v as i64);
        }
        builder.face(&face).map_err(|m| Failure::at(at(), m))?;
    }
    builder.finish().map_err(Failure::whole)
}

/// Finds `name = [` or `name: [` (as in `exports.name=[`) and parses the array of arrays.
fn named_array(text: &str, name: &str) -> Result<Vec<Vec<f64>>, Failure> {
    let bytes = text.as_bytes();
    let is_ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'$';
    for (start, _) in text.match_indices(name) {
        let end = start + name.len();
        if (start > 0 && is_ident(bytes[start - 1])) || bytes.get(end).is_some_and(|&b| is_ident(b))
        {
            continue;
        }
        let mut cursor = Cursor { text, pos: end };
        cursor.skip_space();
        if !(cursor.eat(b'=') || cursor.eat(b':')) {
            continue;
        }
        cursor.skip_space();
        return cursor.array_of_arrays();
    }
    Err(Failure::whole(format!("no `{name} = [...]` array found")))
}

struct Cursor<'a> {
    text: &'a str,
    pos: usize,
}

impl Cursor<'_> {
    fn peek(&self) -> Option<u8> {
        self.text.as_bytes().get(self.pos).copied()
    }

    fn eat(&mut self, byte: u8) -> bool {
        let hit = self.peek() == Some(byte);
        self.pos += usize::from(hit);
        hit
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.pos += 1;
        }
    }

    fn fail(&self, message: impl Into<String>) -> Failure {
        let before = &self.text[..self.pos];
        let line = before.matches('\n').count() + 1;
        let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
        Failure::at(Location::LineColumn { line, column }, message)
    }

    fn found(&self) -> String {
        match self.text[self.pos..].chars().next() {
            Some(c) => format!("`{c}`"),
            None => "end of file".into(),
        }
    }

    /// `[` item (`,` item)* `,`? `]` with whitespace anywhere between.
    fn list<T>(
        &mut self,
        mut item: impl FnMut(&mut Self) -> Result<T, Failure>,
    ) -> Result<Vec<T>, Failure> {
        if !self.eat(b'[') {
            return Err(self.fail(format!("expected `[`, found {}", self.found())));
        }
        let mut items = Vec::new();
        loop {
            self.skip_space();
            if self.eat(b']') {
                return Ok(items);
            }
            items.push(item(self)?);
            self.skip_space();
            if self.eat(b']') {
                return Ok(items);
            }
            if !self.eat(b',') {
                return Err(self.fail(format!("expected `,` or `]`, found {}", self.found())));
            }
        }
    }

    fn array_of_arrays(&mut self) -> Result<Vec<Vec<f64>>, Failure> {
        self.list(|c| c.list(Self::number))
    }

    /// A JS number literal in decimal, plus `NaN`/`Infinity` so they reach the NaN/inf checks.
    fn number(&mut self) -> Result<f64, Failure> {
        let start = self.pos;
        let rest = &self.text[start..];
        let unsigned = rest.strip_prefix(['-', '+']).unwrap_or(rest);
        let sign = rest.len() - unsigned.len();
        for (word, value) in [("Infinity", f64::INFINITY), ("NaN", f64::NAN)] {
            if unsigned.starts_with(word) {
                self.pos += sign + word.len();
                return Ok(if rest.starts_with('-') { -value } else { value });
            }
        }
        let len = rest
            .bytes()
            .enumerate()
            .take_while(|&(i, b)| {
                b.is_ascii_digit()
                    || b == b'.'
                    || b == b'e'
                    || b == b'E'
                    || ((b == b'-' || b == b'+')
                        && (i == 0 || matches!(rest.as_bytes()[i - 1], b'e' | b'E')))
            })
            .count();
        let token = &rest[..len];
        match token.parse::<f64>() {
            Ok(value) if len > 0 => {
                self.pos += len;
                Ok(value)
            }
            _ => Err(self.fail(format!(
                "expected a number, found {}",
                self.found_token(len)
            ))),
        }
    }

    fn found_token(&self, len: usize) -> String {
        let token: String = self.text[self.pos..]
            .chars()
            .enumerate()
            .take_while(|&(i, c)| i < len.max(1) || !(c.is_whitespace() || c == ',' || c == ']'))
            .map(|(_, c)| c)
            .take(40)
            .collect();
        if token.is_empty() {
            "end of file".into()
        } else {
            format!("`{token}`")
        }
    }
}
