//! The engine's layers, lowest first, and the imports that run back up them. Data flows one way
//! (docs/architecture.md): a module may use the layers below it; an import of a higher layer is
//! listed here by file and counted, and the count may only fall. The engine cannot name the lab
//! (lab/): the compiler keeps that boundary. Needs no GPU.

mod common;

use std::path::Path;

/// Top-level modules of src/, lowest layer first.
const LAYERS: &[&str] = &[
    "error", "progress", "gpu", "scene", "render", "stages", "certify", "methods", "frame", "api",
];

#[test]
fn imports_run_down_the_layers_but_for_a_known_few() {
    let up = common::layers::upward_imports(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        LAYERS,
        // The crate root and the research façade sit above every layer: they re-export them.
        &["lib", "research"],
    );
    for (file, target) in &up {
        println!("src/{file} uses {target}");
    }
    println!("{} imports run back up the layers", up.len());
    // The engine has none left: every import runs down the layers.
    assert!(
        up.is_empty(),
        "{} imports run back up (none may): {up:#?}",
        up.len()
    );
}

/// The command line's words in one line of product code: a flag (`--scene`) or a `penumbra …`
/// command inside a string literal. Comments are not messages and are passed over.
fn cli_words_in(line: &str) -> Vec<String> {
    let code = line.trim_start();
    if code.starts_with("//") {
        return Vec::new();
    }
    // The odd pieces between quotes are the literals (an escaped quote only splits one early).
    code.split('"')
        .skip(1)
        .step_by(2)
        .filter(|lit| {
            let flag = lit.match_indices("--").any(|(i, _)| {
                lit[i + 2..]
                    .chars()
                    .next()
                    .is_some_and(|c| c.is_ascii_lowercase())
            });
            flag || lit.contains("`penumbra ") || lit.contains("penumbra assets")
        })
        .map(str::to_string)
        .collect()
}

/// Every product line of src/ (a file's lines outside its `#[cfg(test)]` items), as `file:line`.
fn product_lines(dir: &Path, out: &mut Vec<(String, String)>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().collect();
    entries.sort_by_key(|e| e.path());
    for e in entries {
        let path = e.path();
        if path.is_dir() {
            product_lines(&path, out);
        } else if path.extension().is_some_and(|x| x == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            for (n, line) in common::layers::product_lines(&text) {
                out.push((format!("{}:{n}", path.display()), line.to_string()));
            }
        }
    }
}

#[test]
fn only_the_test_items_are_left_out_of_the_product_lines() {
    let src = "fn a() {}\n#[cfg(test)]\npub(crate) fn helper() -> &'static str {\n    let c = '}';\n    let q = '\\'';\n    \"}\" // }\n}\n#[cfg(test)]\nuse std::fmt;\npub fn b() {}\n#[cfg(test)]\nmod tests {\n    /* } */\n    fn t() { let _ = r#\"}\"#; }\n}\npub fn c<'a>(x: &'a str) -> &'a str { x }\n";
    let kept: Vec<(usize, &str)> = common::layers::product_lines(src);
    assert_eq!(
        kept,
        [
            (1, "fn a() {}"),
            (10, "pub fn b() {}"),
            (16, "pub fn c<'a>(x: &'a str) -> &'a str { x }")
        ]
    );
}

#[test]
fn the_engine_names_no_command_line_flag() {
    // The scanner finds what it is for (so the zero below can fail).
    assert_eq!(
        cli_words_in(r#"    format!("--scene {x}: empty", x)"#),
        ["--scene {x}: empty"]
    );
    assert_eq!(cli_words_in(r#"  "run `penumbra assets fetch`""#).len(), 1);
    assert!(cli_words_in(r#"  // `--set` in a comment"#).is_empty());
    assert!(cli_words_in(r#"  "a - b -- 3""#).is_empty());
    let mut lines = Vec::new();
    product_lines(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut lines,
    );
    assert!(lines.len() > 10_000, "{} lines read", lines.len());
    let named: Vec<String> = lines
        .iter()
        .flat_map(|(at, line)| {
            cli_words_in(line)
                .into_iter()
                .map(move |w| format!("{at}: {w}"))
        })
        .collect();
    println!(
        "{} engine strings name a command-line flag or command",
        named.len()
    );
    // The engine speaks its own words (`backend`, `scene`, a setting's key); each front end
    // words them as its user writes them (lab/src/error.rs, python/src/lib.rs).
    assert!(named.is_empty(), "{named:#?}");
}

#[test]
fn product_code_reads_no_twin() {
    // The CPU twins are the kernels' test oracles; what the product needs on the CPU (a pool's
    // reader, the regions rules, the frame's flag bits) lives beside its stage, and the twin
    // re-exports it.
    let mut lines = Vec::new();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    product_lines(&src, &mut lines);
    let twin_dir = src.join("stages").join("twin").display().to_string();
    let reads: Vec<&String> = lines
        .iter()
        .filter(|(at, line)| {
            !at.starts_with(&twin_dir)
                && !line.trim_start().starts_with("//")
                && line.contains("twin::")
        })
        .map(|(at, _)| at)
        .collect();
    assert!(reads.is_empty(), "product code names a twin: {reads:#?}");
}

/// Whether a line of source declares something unrestricted `pub`: an item, a method, a field or
/// a re-export (`pub(crate)` and comments are not).
fn declares_pub(line: &str) -> bool {
    line.trim_start().starts_with("pub ")
}

/// The engine's public surface, counted: the product lines of src/ that declare something `pub`,
/// the twins (`stages/twin/`, built only with the tests' `twins` feature) apart. src/lib.rs warns
/// on `unreachable_pub` (CI denies warnings), so each of these is reachable from outside: the API,
/// or the research façade (src/research.rs) and what its items carry. (1222 before auto's record
/// was read typed outside the engine: its tries, checks and filter check joined the façade; 1243
/// before `Footprint::record_listed` and `GeometryTiles::section` joined it, for the listed
/// footprint's test against its twin in lab/tests/culled_maps.rs.)
const PUBLIC_SURFACE: usize = 1245;

#[test]
fn the_public_surface_is_the_api_and_the_research_facade() {
    // The scanner finds what it is for (so the bound below can fail).
    assert!(declares_pub(
        "    pub fn new(ctx: &GpuContext) -> Result<Self> {"
    ));
    assert!(declares_pub("pub struct Shadows {"));
    assert!(!declares_pub(
        "    pub(crate) fn frame_size(&self) -> u32 {"
    ));
    assert!(!declares_pub("/// pub fn in a comment"));
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    // Only the API and the façade are public modules; the pipeline's modules are the crate's.
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let public_mods: Vec<&str> = lib
        .lines()
        .filter_map(|l| l.strip_prefix("pub mod "))
        .collect();
    assert_eq!(public_mods, ["api;", "research;"]);
    assert!(lib.contains("#![warn(unreachable_pub)]"));
    let mut lines = Vec::new();
    product_lines(&src, &mut lines);
    let twin_dir = src.join("stages").join("twin").display().to_string();
    let surface = lines
        .iter()
        .filter(|(at, line)| !at.starts_with(&twin_dir) && declares_pub(line))
        .count();
    let twins = lines
        .iter()
        .filter(|(at, line)| at.starts_with(&twin_dir) && declares_pub(line))
        .count();
    println!("the engine's public surface: {surface} `pub` lines (and {twins} in the twins)");
    assert!(surface > 500, "{surface} `pub` lines read");
    // What outside code needs joins the façade; anything else is `pub(crate)`. Lower the figure
    // when the surface shrinks.
    assert!(
        surface <= PUBLIC_SURFACE,
        "the engine's public surface grew to {surface} `pub` lines (at most {PUBLIC_SURFACE}): \
         make what outside code does not use `pub(crate)`"
    );
}
