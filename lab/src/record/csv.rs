//! `results.csv`: one line per row, the same figures as `results.jsonl` flattened, one
//! `stage_<name>_ms` column per stage seen in any row.

use crate::record::row::ResultRow;

/// Records as CSV text: a field is quoted only when it holds a comma, a quote or a line break
/// (RFC 4180, the `csv` crate's `Necessary` style), and each record ends in `\n`.
pub fn lines<I, R>(records: I) -> String
where
    I: IntoIterator<Item = R>,
    R: IntoIterator,
    R::Item: AsRef<[u8]>,
{
    let mut w = ::csv::WriterBuilder::new()
        .terminator(::csv::Terminator::Any(b'\n'))
        .flexible(true)
        .from_writer(Vec::new());
    for record in records {
        // Writing to memory cannot fail, and a CSV writer takes any bytes.
        w.write_record(record).expect("CSV into memory");
    }
    String::from_utf8(w.into_inner().expect("CSV into memory"))
        .expect("CSV of UTF-8 fields is UTF-8")
}

fn opt(v: Option<f64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_default()
}

pub fn render(rows: &[ResultRow]) -> String {
    let mut stages: Vec<&str> = Vec::new();
    for r in rows {
        for k in r.stages_ms.keys() {
            if !stages.contains(&k.as_str()) {
                stages.push(k);
            }
        }
    }
    let mut header: Vec<String> = [
        "scene",
        "label",
        "spec",
        "method",
        "params",
        "adapter",
        "map_size",
        "maps",
        "syncs",
        "frame_ms",
        "frame_ms_min",
        "frame_ms_max",
        "setup_ms",
        "rmse",
        "mae",
        "max_abs",
        "psnr",
        "ssim",
        "flip_mean",
        "flip_p95",
        "flip_p99",
        "penumbra_rmse",
        "bad_pixel_share",
        "nan_count",
        "pixels",
        "penumbra_pixels",
        "mismatch_share",
        "reference",
        "raster",
        "target",
        "version",
    ]
    .map(String::from)
    .to_vec();
    header.extend(stages.iter().map(|s| format!("stage_{s}_ms")));
    // A `failed` column only when some setting failed: its reason; that row's figures are empty.
    let any_failed = rows.iter().any(|r| r.failed.is_some());
    if any_failed {
        header.push("failed".into());
    }
    let mut records = vec![header];
    for r in rows {
        let m = &r.metrics;
        let adapter = r
            .core
            .adapter
            .get("name")
            .and_then(|v| v.as_str())
            .map(String::from)
            .unwrap_or_else(|| r.core.adapter.to_string());
        let mut cells = vec![
            r.core.scene.clone(),
            r.label(),
            r.core.spec.clone(),
            r.core.method.clone(),
            r.core.params.to_string(),
            adapter,
            r.core.map_size.to_string(),
            r.core.maps.to_string(),
            r.syncs.to_string(),
            r.core.frame_ms.to_string(),
            r.frame_ms_min.to_string(),
            r.frame_ms_max.to_string(),
            opt(r.setup_ms),
            m.rmse.to_string(),
            m.mae.to_string(),
            m.max_abs.to_string(),
            opt(m.psnr),
            m.ssim.to_string(),
            m.flip_mean.to_string(),
            m.flip_p95.to_string(),
            m.flip_p99.to_string(),
            opt(m.penumbra_rmse),
            m.bad_pixel_share.to_string(),
            m.nan_count.to_string(),
            m.pixels.to_string(),
            m.penumbra_pixels.to_string(),
            m.mismatch_share.to_string(),
            r.reference.clone(),
            r.raster.clone().unwrap_or_default(),
            opt(r.core.target),
            r.core
                .version
                .get("git")
                .and_then(|v| v.as_str())
                .unwrap_or_default()
                .to_string(),
        ];
        cells.extend(stages.iter().map(|s| opt(r.stages_ms.get(*s).copied())));
        if let Some(reason) = &r.failed {
            // Scene, label, spec, method, params, adapter and map size stay; the figures were
            // never measured.
            for c in &mut cells[7..27] {
                c.clear();
            }
            cells.push(reason.clone());
        } else if any_failed {
            cells.push(String::new());
        }
        records.push(cells);
    }
    lines(records)
}

#[cfg(test)]
mod tests {
    use super::lines;

    #[test]
    fn quoting() {
        assert_eq!(lines([["a,b", "plain"]]), "\"a,b\",plain\n");
        assert_eq!(lines([["say \"x\""]]), "\"say \"\"x\"\"\"\n");
        // A comma, a quote and a line break in one field: quoted once, the quote doubled, the
        // break kept inside the quotes; the fields around it stay bare.
        let text = lines([
            vec!["scene", "label", "n"],
            vec!["tiny", "regular:n=5,layout=\"centred\"\nsecond line", "5"],
        ]);
        assert_eq!(
            text,
            "scene,label,n\ntiny,\"regular:n=5,layout=\"\"centred\"\"\nsecond line\",5\n"
        );
        let back: Vec<::csv::StringRecord> = ::csv::Reader::from_reader(text.as_bytes())
            .records()
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(&back[0][1], "regular:n=5,layout=\"centred\"\nsecond line");
    }
}
