//! The facts every study's row carries, named once: [`RowCore`], flattened into each study's row
//! type so that every rows file the binary writes (`results.jsonl`, `frontier.jsonl`,
//! `estimate.jsonl`, …) holds them under the same keys. A study's own figures sit beside it in its
//! own struct. docs/formats.md lists the keys.

use serde::{Deserialize, Serialize};

use crate::methods::Method;

/// Scene, method, maps, error, time, adapter and build of one measured row.
///
/// Keys renamed when the schema became one are read under their old names too (`shadow_maps`,
/// `shadow_map_size`, `total_ms`, `measured_rmse`), so rows files written before still read; the new name is the
/// one written.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RowCore {
    pub scene: String,
    /// The method as a spec (`regular:n=5,layout=centred`): as the study was given it, or the
    /// method's label (a spec with its defaults left out). Empty in rows written before the key.
    #[serde(default)]
    pub spec: String,
    /// The method's name (`adaptive`); empty in rows written before the key.
    #[serde(default)]
    pub method: String,
    /// Method parameters, e.g. `{"p_m": 0, "scope": "local"}`.
    #[serde(default)]
    pub params: serde_json::Value,
    /// Shadow maps of the judged frame.
    #[serde(alias = "shadow_maps")]
    pub maps: u32,
    /// Raster size of a map per side (the base of hybrid maps; for `auto`, the size it chose);
    /// 0 where the row does not say.
    #[serde(default, alias = "shadow_map_size")]
    pub map_size: u32,
    /// RMSE of V against the row's reference, over geometry pixels.
    #[serde(default, alias = "measured_rmse")]
    pub rmse: f64,
    /// Wall clock of a frame in ms: the median over the timed frames where there are several.
    #[serde(default, alias = "total_ms")]
    pub frame_ms: f64,
    /// The adapter the row was measured on: its summary object, or its name as a study writes it.
    #[serde(default)]
    pub adapter: serde_json::Value,
    /// The build that measured the row (crate version and git hash).
    #[serde(default)]
    pub version: serde_json::Value,
    /// The target T the method was asked for (`auto:target=T`, `regions:target=T`), so that
    /// nothing reading the rows parses it out of `spec`; absent for a method without one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<f64>,
}

impl RowCore {
    /// The core of a row of `method` on `scene` as given by `spec`: its name, parameters, target
    /// and this build filled in; the measured figures (maps, map size, RMSE, time, adapter) are
    /// the caller's.
    pub fn of(scene: &str, spec: &str, method: &Method) -> RowCore {
        RowCore {
            scene: scene.to_string(),
            spec: spec.to_string(),
            method: method.name().to_string(),
            params: method.params_json(),
            target: target(method),
            version: crate::version(),
            ..RowCore::default()
        }
    }
}

/// The core's columns where a study writes its rows as CSV, in the order of [`RowCore::cells`].
pub const CSV_HEADER: [&str; 11] = [
    "scene", "spec", "method", "params", "maps", "map_size", "rmse", "frame_ms", "adapter",
    "version", "target",
];

/// The core's columns renamed when the schema became one, as (column, its old name): a CSV
/// written before reads under the old name as JSON rows do (the serde aliases above).
pub const CSV_ALIASES: [(&str, &str); 4] = [
    ("maps", "shadow_maps"),
    ("map_size", "shadow_map_size"),
    ("rmse", "measured_rmse"),
    ("frame_ms", "total_ms"),
];

impl RowCore {
    /// A study's CSV header: the core's columns, then the study's own (`own`), in the order its
    /// cells are written (`cells()` then its own).
    pub fn csv_header(own: &[&str]) -> Vec<String> {
        CSV_HEADER
            .iter()
            .chain(own)
            .map(|s| s.to_string())
            .collect()
    }

    /// The core's cells of a CSV row under [`CSV_HEADER`]: `params` as compact JSON, the adapter
    /// by name, the version by git hash, an absent target empty.
    pub fn cells(&self) -> Vec<String> {
        let text = |v: &serde_json::Value, key: &str| match v {
            serde_json::Value::String(s) => s.clone(),
            serde_json::Value::Null => String::new(),
            other => other
                .get(key)
                .and_then(|x| x.as_str())
                .map_or_else(|| other.to_string(), String::from),
        };
        vec![
            self.scene.clone(),
            self.spec.clone(),
            self.method.clone(),
            self.params.to_string(),
            self.maps.to_string(),
            self.map_size.to_string(),
            self.rmse.to_string(),
            self.frame_ms.to_string(),
            text(&self.adapter, "name"),
            text(&self.version, "git"),
            self.target.map_or(String::new(), |t| t.to_string()),
        ]
    }

    /// As [`RowCore::of`] from the spec's text; where it does not parse (a setting that failed
    /// before it ran), the scene, spec and build alone.
    pub fn of_spec(scene: &str, spec: &str) -> RowCore {
        match Method::parse(spec, &[]) {
            Ok(m) => RowCore::of(scene, spec, &m),
            Err(_) => RowCore {
                scene: scene.to_string(),
                spec: spec.to_string(),
                version: crate::version(),
                ..RowCore::default()
            },
        }
    }
}

/// A study's CSV rows read back by header: each row's core from the core's columns (typed, each
/// under its name, an old name of [`CSV_ALIASES`] or of `aliases`, a study's own renames), and
/// the study's own columns into `T` by csv's serde (which ignores the core's columns). The
/// csv crate's serde cannot read the core into a `#[serde(flatten)]` field: flattening buffers
/// each cell by its look, so a digit-only string (a git hash, a scene) reads as a number and an
/// empty target as text. A column the file lacks leaves its field empty (0, none), as JSON rows
/// written before a key read. Errors name the line, the column and the cell.
pub fn read_csv<T: serde::de::DeserializeOwned>(
    text: &str,
    aliases: &[(&str, &str)],
) -> std::result::Result<Vec<(RowCore, T)>, String> {
    let mut reader = ::csv::Reader::from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| e.to_string())?.clone();
    let column = |name: &str| {
        let old = CSV_ALIASES
            .iter()
            .chain(aliases)
            .filter(|(new, _)| *new == name)
            .map(|(_, old)| *old);
        std::iter::once(name)
            .chain(old)
            .find_map(|n| header.iter().position(|h| h == n))
    };
    let at: Vec<Option<usize>> = CSV_HEADER.iter().map(|c| column(c)).collect();
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| e.to_string())?;
        let line = record.position().map_or(0, |p| p.line());
        let cell = |k: usize| at[k].and_then(|i| record.get(i)).unwrap_or("");
        let core = RowCore::from_cells(cell).map_err(|e| format!("line {line}: {e}"))?;
        let own: T = record
            .deserialize(Some(&header))
            .map_err(|e| format!("line {line}: {e}"))?;
        rows.push((core, own));
    }
    Ok(rows)
}

impl RowCore {
    /// The inverse of [`RowCore::cells`]: cell `k` under `CSV_HEADER[k]`. Empty cells read as
    /// empty fields; `params` as JSON; the adapter and the build as the text written (their
    /// name and git hash).
    fn from_cells<'a>(cell: impl Fn(usize) -> &'a str) -> std::result::Result<RowCore, String> {
        fn number<N: std::str::FromStr + Default>(
            k: usize,
            text: &str,
        ) -> std::result::Result<N, String> {
            if text.is_empty() {
                return Ok(N::default());
            }
            text.parse()
                .map_err(|_| format!("{} = `{text}`: not a number", CSV_HEADER[k]))
        }
        let text = |k: usize| match cell(k) {
            "" => serde_json::Value::Null,
            s => serde_json::Value::String(s.to_string()),
        };
        let params = match cell(3) {
            "" => serde_json::Value::Null,
            s => serde_json::from_str(s).map_err(|e| format!("params = `{s}`: {e}"))?,
        };
        Ok(RowCore {
            scene: cell(0).to_string(),
            spec: cell(1).to_string(),
            method: cell(2).to_string(),
            params,
            maps: number(4, cell(4))?,
            map_size: number(5, cell(5))?,
            rmse: number(6, cell(6))?,
            frame_ms: number(7, cell(7))?,
            adapter: text(8),
            version: text(9),
            target: match cell(10) {
                "" => None,
                t => Some(number(10, t)?),
            },
        })
    }
}

/// A method's target as it was asked: the methods keep T as f32, whose shortest decimal is what
/// was written (0.03, not the 0.029999999329447746 its widening reads). None without a target.
pub fn target(m: &Method) -> Option<f64> {
    let t = m.params_json().get("target")?.as_f64()? as f32;
    t.to_string().parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn old_names_read_and_the_new_ones_are_written() {
        let old = json!({"scene": "s", "shadow_maps": 9, "shadow_map_size": 512, "total_ms": 4.5, "rmse": 0.01});
        let core: RowCore = serde_json::from_value(old).unwrap();
        assert_eq!((core.maps, core.map_size, core.frame_ms), (9, 512, 4.5));
        let written = serde_json::to_value(&core).unwrap();
        assert_eq!(written["maps"], 9);
        assert_eq!(written["map_size"], 512);
        assert_eq!(written["frame_ms"], 4.5);
        assert!(written.get("shadow_maps").is_none() && written.get("total_ms").is_none());
        assert!(written.get("target").is_none());
    }

    #[derive(Debug, PartialEq, serde::Deserialize)]
    struct Own {
        half: String,
        draws: u32,
        oracle: Option<f64>,
    }

    #[test]
    fn csv_rows_read_back_typed_under_new_and_old_names() {
        // Digit-only text (a scene, a git hash) stays text; an empty target is none; the study's
        // own columns come typed, an empty option none.
        let core = RowCore {
            scene: "1024".into(),
            spec: "auto:target=0.03".into(),
            method: "auto".into(),
            params: json!({"target": 0.03, "filters": "pcss"}),
            maps: 9,
            map_size: 512,
            rmse: 0.012345678901234567,
            frame_ms: 4.5,
            adapter: json!("llvmpipe (LLVM 15.0.6, 256 bits)"),
            version: json!("605512345678"),
            target: Some(0.03),
        };
        let mut text = crate::record::csv::lines(
            std::iter::once(RowCore::csv_header(&["half", "draws", "oracle"])).chain([
                [core.cells(), vec!["fitting".into(), "3".into(), "".into()]].concat(),
                [
                    RowCore::default().cells(),
                    vec!["held-out".into(), "0".into(), "0.5".into()],
                ]
                .concat(),
            ]),
        );
        let rows = read_csv::<Own>(&text, &[]).unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].0, core);
        assert_eq!(rows[1].0, RowCore::default());
        let own = |half: &str, draws, oracle| Own {
            half: half.into(),
            draws,
            oracle,
        };
        assert_eq!(rows[0].1, own("fitting", 3, None));
        assert_eq!(rows[1].1, own("held-out", 0, Some(0.5)));
        // A file written before: old names, a study's own rename, columns it never had.
        let old =
            "scene,measured_rmse,shadow_maps,ms,half,draws,oracle\n123,0.25,4,7.5,fitting,1,\n";
        let rows = read_csv::<Own>(old, &[("frame_ms", "ms")]).unwrap();
        assert_eq!(
            rows[0].0,
            RowCore {
                scene: "123".into(),
                rmse: 0.25,
                maps: 4,
                frame_ms: 7.5,
                ..RowCore::default()
            }
        );
        // A bad cell names its line, column and text.
        text = text.replace(",9,512,", ",nine,512,");
        assert_eq!(
            read_csv::<Own>(&text, &[]).unwrap_err(),
            "line 2: maps = `nine`: not a number"
        );
    }

    #[test]
    fn a_budget_method_carries_its_target_as_asked() {
        let m = Method::parse("auto:target=0.03", &[]).unwrap();
        let core = RowCore::of("default", "auto:target=0.03", &m);
        assert_eq!(core.target, Some(0.03));
        assert_eq!(core.method, "auto");
        let fixed = Method::parse("regular:n=3", &[]).unwrap();
        assert_eq!(RowCore::of("default", "regular:n=3", &fixed).target, None);
    }
}
