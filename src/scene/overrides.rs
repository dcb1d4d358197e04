//! `--set key=value` on the scene's `[render]` table. Short keys (`width`) and dotted keys
//! (`bias.constant`, `render.width`) both work; `resolution` sets width and height.

use crate::Error;

pub(crate) const RENDER_KEYS: &[&str] = &[
    "width",
    "height",
    "resolution",
    "shadow_map_size",
    "cull",
    "ambient",
    "shadow_map_budget_mib",
    "self_shadow",
    "bias.constant",
    "bias.slope",
    "bias.normal_offset",
    "bias.max_slope",
    "maps",
    "raster",
    "hybrid.base",
    "hybrid.levels",
    "hybrid.eps",
    "base",
    "levels",
    "eps",
];

/// Whether `key` (without its `render.` prefix) is a render setting `--set` may override.
pub fn is_render_key(key: &str) -> bool {
    RENDER_KEYS.contains(&key)
}

/// Value text as TOML (numbers, booleans), else as a string.
pub(crate) fn parse_value(text: &str) -> toml::Value {
    format!("v = {text}")
        .parse::<toml::Table>()
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_string()))
}

/// Sets each `key=value` pair in `table`'s `[render]`; an unknown key is a [`Error::Setting`]
/// naming `origin`, the scene it was given for.
pub(crate) fn apply_overrides(
    table: &mut toml::Table,
    overrides: &[(String, String)],
    origin: &str,
) -> crate::Result<()> {
    for (key, value) in overrides {
        let short = key.strip_prefix("render.").unwrap_or(key);
        if !RENDER_KEYS.contains(&short) {
            let why = format!("unknown render setting (known: {})", RENDER_KEYS.join(", "));
            return Err(Error::Setting {
                origin: Some(origin.to_string()),
                key: key.clone(),
                value: None,
                why,
            });
        }
        let v = parse_value(value);
        let render = table
            .entry("render")
            .or_insert_with(|| toml::Value::Table(Default::default()))
            .as_table_mut()
            .ok_or_else(|| Error::scene(origin, "`render` is not a table"))?;
        if short == "resolution" {
            render.insert("width".into(), v.clone());
            render.insert("height".into(), v);
        } else if let Some(h) = short
            .strip_prefix("hybrid.")
            .or(["base", "levels", "eps"].into_iter().find(|k| *k == short))
        {
            // `base`, `levels` and `eps` are the hybrid map's: `--set maps=hybrid --set base=2048`.
            let hybrid = render
                .entry("hybrid")
                .or_insert_with(|| toml::Value::Table(Default::default()))
                .as_table_mut()
                .ok_or_else(|| Error::scene(origin, "`render.hybrid` is not a table"))?;
            hybrid.insert(h.into(), v);
        } else if let Some(b) = short.strip_prefix("bias.") {
            let bias = render
                .entry("bias")
                .or_insert_with(|| toml::Value::Table(Default::default()))
                .as_table_mut()
                .ok_or_else(|| Error::scene(origin, "`render.bias` is not a table"))?;
            bias.insert(b.into(), v);
        } else {
            render.insert(short.into(), v);
        }
    }
    Ok(())
}
