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

impl RowCore {
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
