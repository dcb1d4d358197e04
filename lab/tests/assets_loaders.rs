//! Mesh loaders on tiny files written here: each valid form, and each malformed case with
//! the exact message a user sees.

use std::io::Write;
use std::path::{Path, PathBuf};

use penumbra_lab::assets::{load_mesh, LoadedMesh};

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("assets_loaders");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    encoder.write_all(bytes).unwrap();
    encoder.finish().unwrap()
}

fn load(name: &str, bytes: &[u8]) -> LoadedMesh {
    let path = write(name, bytes);
    load_mesh(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Asserts the whole message: the file's path, then `expected`.
fn fails(name: &str, bytes: &[u8], expected: &str) {
    let path = write(name, bytes);
    let message = load_mesh(&path).expect_err("should fail").to_string();
    assert_eq!(message, format!("{}: {expected}", path.display()));
}

const TRIANGLE_AND_QUAD: [[f32; 3]; 5] = [
    [0., 0., 0.],
    [1., 0., 0.],
    [1., 1., 0.],
    [0., 1., 0.],
    [0.5, 0.5, 1.],
];

// ---------------------------------------------------------------- OFF

#[test]
fn off_valid_with_comments_and_a_quad() {
    let mesh = load(
        "ok.off",
        b"OFF\n# a comment\n5 2 0\n\n0 0 0\n1 0 0\n1 1 0  # trailing\n0 1 0\n0.5 0.5 1\n4 0 1 2 3\n3 0 1 4\n",
    );
    assert_eq!(mesh.positions, TRIANGLE_AND_QUAD);
    assert_eq!(mesh.indices, [0, 1, 2, 0, 2, 3, 0, 1, 4]);
}

#[test]
fn off_beyond_off_rs_default_limits() {
    let mut text = String::from("OFF\n10001 1 0\n");
    for i in 0..10_001 {
        text += &format!("{i} 0 0\n");
    }
    text += "3 0 1 10000\n";
    let mesh = load("big.off", text.as_bytes());
    assert_eq!((mesh.vertex_count(), mesh.triangle_count()), (10_001, 1));
}

const OFF_HEAD: &str = "OFF\n3 1 0\n0 0 0\n";

#[test]
fn off_vertex_errors() {
    let case = |name, vertex_lines: &str, expected| {
        fails(
            name,
            format!("{OFF_HEAD}{vertex_lines}\n3 0 1 2\n").as_bytes(),
            expected,
        )
    };
    case(
        "v2.off",
        "1 0\n0 1 0",
        "line 4: expected 3 coordinates, found 2",
    );
    case(
        "vx.off",
        "1 x 0\n0 1 0",
        "line 4: coordinate `x` is not a number",
    );
    case(
        "vnan.off",
        "1 0 0\n0 nan 0",
        "line 5, vertex 2: coordinate y is NaN",
    );
    case(
        "vinf.off",
        "1 0 0\n0 0 -inf",
        "line 5, vertex 2: coordinate z is -inf",
    );
}

#[test]
fn off_face_errors() {
    let case = |name, face: &str, expected| {
        fails(
            name,
            format!("{OFF_HEAD}1 0 0\n0 1 0\n{face}\n").as_bytes(),
            expected,
        )
    };
    case(
        "fout.off",
        "3 0 1 7",
        "line 6, face 0: references vertex 7 of 3",
    );
    case(
        "fidx.off",
        "3 0 a 2",
        "line 6: vertex index `a` is not a non-negative integer",
    );
    case(
        "fshort.off",
        "3 0 1",
        "line 6: expected 3 vertex indices, found 2",
    );
    case(
        "fdeg.off",
        "2 0 1",
        "line 6: a face needs at least 3 vertices, this one declares 2",
    );
    case(
        "fnone.off",
        "",
        "line 2: file ends early: the counts say 3 vertices and 1 faces, but only 3 lines follow",
    );
}

#[test]
fn off_file_errors() {
    fails(
        "head.off",
        b"OF\n3 1\n",
        "line 1: expected the header `OFF`, found `OF`",
    );
    fails(
        "counts.off",
        b"OFF\n3 one\n",
        "line 2: expected the counts `vertices faces [edges]`, found `3 one`",
    );
    fails("empty.off", b"", "empty file: no `OFF` header");
    fails("novert.off", b"OFF\n0 0 0\n", "empty mesh: no vertices");
    fails(
        "noface.off",
        b"OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n",
        "empty mesh: no faces",
    );
}

// ---------------------------------------------------------------- PLY

fn ply_header(format: &str, coord: &str, index: &str, vertices: usize, faces: usize) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment tiny\nelement vertex {vertices}\nproperty {coord} x\n\
         property {coord} y\nproperty {coord} z\nelement face {faces}\n\
         property list uchar {index} vertex_indices\nend_header\n"
    )
}

const PLY_ASCII_OK: &str = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n\
    property float y\nproperty float z\nproperty float nx\nelement face 2\n\
    property list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\n\
    property int vertex2\nend_header\n0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n0.5 0.5 1 1\n\
    4 0 1 2 3\n3 0 1 4\n0 1\n";

#[test]
fn ply_ascii_with_extra_property_and_element() {
    let mesh = load("ok.ply", PLY_ASCII_OK.as_bytes());
    assert_eq!(mesh.positions, TRIANGLE_AND_QUAD);
    assert_eq!(mesh.indices, [0, 1, 2, 0, 2, 3, 0, 1, 4]);
}

#[test]
fn ply_gzip() {
    let mesh = load("ok.ply.gz", &gzip(PLY_ASCII_OK.as_bytes()));
    assert_eq!(mesh.triangle_count(), 3);
}

fn binary_ply(little: bool, faces: &[&[u32]], z2: f32) -> Vec<u8> {
    let format = if little {
        "binary_little_endian"
    } else {
        "binary_big_endian"
    };
    let mut bytes = ply_header(format, "float", "uint", 3, faces.len()).into_bytes();
    let mut put = |b: [u8; 4]| bytes.extend(if little { b } else { [b[3], b[2], b[1], b[0]] });
    for v in [[0., 0., 0.], [1., 0., 0.], [0., 1., z2]] {
        v.iter().for_each(|c: &f32| put(c.to_le_bytes()));
    }
    for face in faces {
        bytes.push(face.len() as u8);
        for i in *face {
            let b = i.to_le_bytes();
            bytes.extend(if little { b } else { [b[3], b[2], b[1], b[0]] });
        }
    }
    bytes
}

#[test]
fn ply_binary_both_byte_orders() {
    for (name, little) in [("le.ply", true), ("be.ply", false)] {
        let mesh = load(name, &binary_ply(little, &[&[0, 1, 2]], 0.5));
        assert_eq!(
            mesh.positions,
            [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.5]],
            "{name}"
        );
        assert_eq!(mesh.indices, [0, 1, 2], "{name}");
    }
}

#[test]
fn ply_binary_errors() {
    fails(
        "bout.ply",
        &binary_ply(true, &[&[0, 1, 2], &[0, 999_999, 2]], 0.),
        "face 1: references vertex 999999 of 3",
    );
    fails(
        "bnan.ply",
        &binary_ply(true, &[&[0, 1, 2]], f32::NAN),
        "vertex 2: coordinate z is NaN",
    );
    let mut truncated = binary_ply(true, &[&[0, 1, 2], &[0, 1, 2]], 0.);
    truncated.truncate(truncated.len() - 6);
    fails(
        "btrunc.ply",
        &truncated,
        "face 1: file ends early: found 1 of 2 `face` elements",
    );
}

#[test]
fn ply_ascii_errors() {
    let ascii = |body: &str| ply_header("ascii", "float", "int", 3, 1) + body;
    // The header takes lines 1-10, so vertex 0 is on line 11.
    fails(
        "a2.ply",
        ascii("0 0 0\n1 0\n0 1 0\n3 0 1 2\n").as_bytes(),
        "line 12, vertex 1: expected 3 values (x y z), found 2",
    );
    fails(
        "anan.ply",
        ascii("nan 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").as_bytes(),
        "line 11, vertex 0: coordinate x is NaN",
    );
    fails(
        "ainf.ply",
        ascii("0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n").as_bytes(),
        "line 12, vertex 1: coordinate y is -inf",
    );
    fails(
        "ax.ply",
        ascii("0 0 0\n1 0 0\n0 1 0\n3 0 one 2\n").as_bytes(),
        "line 14, face 0: value `one` is not a number",
    );
    fails(
        "ay.ply",
        ascii("0 0 0\n1 0 0\n0 why 0\n3 0 1 2\n").as_bytes(),
        "line 13, vertex 2: coordinate y is `why`, not a number",
    );
    fails(
        "aout.ply",
        ascii("0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n").as_bytes(),
        "line 14, face 0: references vertex 3 of 3",
    );
    fails(
        "aeof.ply",
        ascii("0 0 0\n1 0 0\n").as_bytes(),
        "line 13, vertex 2: file ends early: found 2 of 3 `vertex` elements",
    );
    // The dragon's shape of message, through gzip.
    fails(
        "dragon.ply.gz",
        &gzip(ascii("0 0 0\n1 0 0\n0 1 0\n3 0 999999 2\n").as_bytes()),
        "line 14, face 0: references vertex 999999 of 3",
    );
}

#[test]
fn ply_header_errors() {
    fails("cloud.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n",
        "no `face` element in the header (a point cloud?)");
    fails("noz.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n",
        "vertex has no property `z`");
    fails(
        "empty.ply",
        ply_header("ascii", "float", "int", 0, 0).as_bytes(),
        "empty mesh: no vertices",
    );
    let path = write("notply.ply", b"OFF\n3 1 0\n");
    let message = load_mesh(&path).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("{}: line 1: ", path.display())),
        "{message}"
    );
    assert!(message.contains("magic number"), "{message}");
}

#[test]
fn corrupt_gzip_names_the_file() {
    let mut bytes = gzip(PLY_ASCII_OK.as_bytes());
    bytes.truncate(bytes.len() / 2);
    let path = write("cut.ply.gz", &bytes);
    let message = load_mesh(&path).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("{}: ", path.display())),
        "{message}"
    );
}

// ---------------------------------------------------------------- JS arrays

#[test]
fn js_arrays_in_both_styles() {
    // npm `bunny` style: one `exports.x=[...]` per line.
    let mesh = load(
        "ok.js",
        b"exports.positions=[[0,0,0],[1,0,0],[1,1,0],[0,1,0],[0.5,0.5,1e0]]\n\
          exports.cells=[[0,1,2,3],[0,1,4]]\n",
    );
    assert_eq!(mesh.positions, TRIANGLE_AND_QUAD);
    assert_eq!(mesh.indices, [0, 1, 2, 0, 2, 3, 0, 1, 4]);
    // An object literal, spread over lines, with trailing commas and a decoy name.
    let mesh = load(
        "obj.js",
        b"// positions of a triangle\nmodule.exports = {\n  positions: [\n    [0, 0, 0],\n    [1, 0, 0],\n    [0, 1, -.5],\n  ],\n  cells: [[0, 1, 2],],\n};\n",
    );
    assert_eq!(mesh.positions[2], [0., 1., -0.5]);
    assert_eq!(mesh.indices, [0, 1, 2]);
}

#[test]
fn js_array_errors() {
    let case = |name, positions: &str, cells: &str, expected| {
        fails(
            name,
            format!("exports.positions={positions}\nexports.cells={cells}\n").as_bytes(),
            expected,
        )
    };
    let tri = "[[0,0,0],[1,0,0],[0,1,0]]";
    case(
        "j2.js",
        "[[0,0,0],[1,0],[0,1,0]]",
        "[[0,1,2]]",
        "positions[1]: expected 3 coordinates, found 2",
    );
    case(
        "jnan.js",
        "[[NaN,0,0],[1,0,0],[0,1,0]]",
        "[[0,1,2]]",
        "positions[0]: coordinate x is NaN",
    );
    case(
        "jinf.js",
        "[[0,0,0],[1,-Infinity,0],[0,1,0]]",
        "[[0,1,2]]",
        "positions[1]: coordinate y is -inf",
    );
    case(
        "jout.js",
        tri,
        "[[0,1,2],[0,2,3]]",
        "cells[1]: references vertex 3 of 3",
    );
    case(
        "jfrac.js",
        tri,
        "[[0,1.5,2]]",
        "cells[0]: vertex index 1.5 is not an integer",
    );
    case(
        "jsyn.js",
        "[[0,0,0],[1,0 0]]",
        "[[0,1,2]]",
        "line 1, column 33: expected `,` or `]`, found `0`",
    );
    case(
        "jnum.js",
        "[[0,0,0],[1,0,x]]",
        "[[0,1,2]]",
        "line 1, column 33: expected a number, found `x`",
    );
    case("jempty.js", "[]", "[]", "empty mesh: no vertices");
    fails(
        "jnocells.js",
        format!("exports.positions={tri}\n").as_bytes(),
        "no `cells = [...]` array found",
    );
}

// ---------------------------------------------------------------- dispatch

#[test]
fn unknown_and_missing_files() {
    fails(
        "tree.obj",
        b"v 0 0 0\n",
        "unknown mesh format (expected .off, .ply, .ply.gz or .js)",
    );
    let missing = Path::new(env!("CARGO_TARGET_TMPDIR")).join("no-such-mesh.off");
    let message = load_mesh(&missing).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("{}: cannot read: ", missing.display())),
        "{message}"
    );
}
