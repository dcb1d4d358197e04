//! The second look (docs/frontier.md): before the front is drawn, the regular grids' n list is
//! filled near the front (every n between a front grid's neighbours in its list, same layout and
//! maps), and every front setting and its nearest challengers are timed again, interleaved round
//! by round in one window, so a setting is on the front because it is faster, not because its
//! own window was timed while the machine was quiet.

use super::{front, grid, FrontierJob, FrontierLine};
use crate::frame::{FrameOptions, Renderer};
use crate::gpu::timing::TimingMode;
use crate::gpu::GpuContext;
use crate::methods::Method;
use crate::record::measure::median;
use crate::Result;
use serde::{Deserialize, Serialize};

/// An off-front setting is a challenger when its time is within this factor of the fastest
/// setting at most as wrong (what keeps it off the front) …
pub const CHALLENGE: f64 = 1.5;
/// … and among the nearest this many to that front setting.
pub const PER_FRONT: usize = 3;
/// The window's renderers may hold at most this share of the memory the host has free.
const MEMORY_SHARE: f64 = 0.5;

/// What the second look did to one setting.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Look {
    /// Added by filling the n list near the front.
    #[serde(default)]
    pub filled: bool,
    /// Timed again side by side: `front` or `challenger` (what it was before), else None.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub retimed_as: Option<String>,
    /// Its first window's median, min and max (frame_ms then holds the second look's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub first_ms: Option<[f64; 3]>,
    /// On the front by its first window's time.
    #[serde(default)]
    pub was_on: bool,
}

/// `regular:n=5,layout=centred,cull=on` → (5, "regular:n={},layout=centred,cull=on").
fn grid_n(spec: &str) -> Option<(u32, String)> {
    let rest = spec.strip_prefix("regular:")?;
    let parts: Vec<&str> = rest.split(',').collect();
    let i = parts.iter().position(|p| p.starts_with("n="))?;
    let n = parts[i][2..].parse().ok()?;
    let mut pattern = parts.clone();
    pattern[i] = "n={}";
    Some((n, format!("regular:{}", pattern.join(","))))
}

/// The settings to fill: for every regular grid on the front, each n strictly between its
/// neighbours in its group's list of the same layout that the list lacks. They are added to
/// `groups` and returned, grouped by map configuration, to be measured.
pub fn fill(groups: &mut [grid::Group], lines: &[FrontierLine]) -> Vec<grid::Group> {
    let mut out: Vec<grid::Group> = Vec::new();
    for l in lines.iter().filter(|l| l.on_frontier && l.failed.is_none()) {
        let Some((n, pattern)) = grid_n(&l.core.spec) else {
            continue;
        };
        let Some(g) = groups.iter_mut().find(|g| g.maps.label() == l.map_config) else {
            continue;
        };
        let mut list: Vec<u32> = g
            .specs
            .iter()
            .filter_map(|s| grid_n(s))
            .filter(|(_, p)| *p == pattern)
            .map(|(m, _)| m)
            .collect();
        list.sort_unstable();
        let below = list.iter().copied().filter(|&m| m < n).max().unwrap_or(n);
        let above = list.iter().copied().filter(|&m| m > n).min().unwrap_or(n);
        for m in (below + 1..above).filter(|m| *m != n && !list.contains(m)) {
            let spec = pattern.replace("{}", &m.to_string());
            let Ok(method) = Method::parse(&spec, &[]) else {
                continue;
            };
            g.specs.push(spec.clone());
            g.methods.push(method.clone());
            match out.iter_mut().find(|o| o.maps == g.maps) {
                Some(o) => {
                    o.specs.push(spec);
                    o.methods.push(method);
                }
                None => out.push(grid::Group {
                    maps: g.maps,
                    specs: vec![spec],
                    methods: vec![method],
                }),
            }
        }
    }
    out
}

/// Which settings the second look times again: every front setting, and for each its nearest
/// challengers, the off-front settings it keeps off (the fastest setting at most as wrong) whose
/// time is within [`CHALLENGE`] of its own, at most [`PER_FRONT`] of them, nearest first.
/// Returns (line index, `front` or `challenger`).
pub fn chosen(lines: &[FrontierLine]) -> Vec<(usize, &'static str)> {
    let points: Vec<(f64, f64)> = lines.iter().map(FrontierLine::point).collect();
    let mut out: Vec<(usize, &'static str)> = (0..lines.len())
        .filter(|&i| lines[i].on_frontier)
        .map(|i| (i, "front"))
        .collect();
    let mut challengers: Vec<(usize, usize, f64)> = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        if l.on_frontier || l.is_budget() || l.failed.is_some() {
            continue;
        }
        let Some(j) = front::cheapest_reaching(&points, l.core.rmse)
            .filter(|&j| j != i && lines[j].on_frontier)
        else {
            continue;
        };
        let lead = points[i].0 / points[j].0;
        if lead <= CHALLENGE {
            challengers.push((j, i, lead));
        }
    }
    challengers.sort_by(|a, b| a.0.cmp(&b.0).then(a.2.total_cmp(&b.2)).then(a.1.cmp(&b.1)));
    let mut taken: Vec<(usize, usize)> = Vec::new();
    for (j, i, _) in challengers {
        let count = taken.iter().filter(|(f, _)| *f == j).count();
        if count < PER_FRONT {
            taken.push((j, i));
            out.push((i, "challenger"));
        }
    }
    out
}

/// Times the chosen settings again, interleaved round by round (a warm-up each, then `repeats`
/// rounds of one frame each), in one window where the host's free memory holds every renderer,
/// else in as few windows as it allows (said on stderr). Each retimed line's frame figures
/// become the second look's; its first window's stay in `second_look.first_ms`.
pub fn retime(
    ctx: &GpuContext,
    job: &FrontierJob,
    groups: &[grid::Group],
    lines: &mut [FrontierLine],
    log: &dyn Fn(&str),
) -> Result<()> {
    let picked = chosen(lines);
    if picked.is_empty() {
        return Ok(());
    }
    let scenes: Vec<crate::scene::Scene> = groups
        .iter()
        .map(|g| g.maps.apply(job.scene, 0.25))
        .collect();
    let mut items: Vec<(usize, &str, usize, Method)> = Vec::new();
    for &(i, why) in &picked {
        let l = &lines[i];
        let found = groups.iter().enumerate().find_map(|(gi, g)| {
            (g.maps.label() == l.map_config)
                .then(|| {
                    g.specs
                        .iter()
                        .position(|s| *s == l.core.spec)
                        .map(|k| (gi, g.methods[k].clone()))
                })
                .flatten()
        });
        if let Some((gi, m)) = found {
            items.push((i, why, gi, m));
        }
    }
    let cpu = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    let bytes: Vec<u64> = items
        .iter()
        .map(|(_, _, gi, m)| {
            crate::methods::sizes::plan(&scenes[*gi], m, &ctx.limits(), cpu).host_bytes
        })
        .collect();
    let room = penumbra::research::gpu::size_plan::mem_available()
        .map_or(u64::MAX, |b| (b as f64 * MEMORY_SHARE) as u64);
    let windows = windows(&bytes, room);
    log(&format!(
        "second look: {} front settings and {} challengers timed again side by side, {} round{} each, in {}",
        picked.iter().filter(|p| p.1 == "front").count(),
        picked.iter().filter(|p| p.1 == "challenger").count(),
        job.repeats,
        if job.repeats == 1 { "" } else { "s" },
        if windows.len() == 1 { "one window".to_string() } else { format!("{} windows (their renderers need more than half the free memory at once)", windows.len()) }
    ));
    for w in windows {
        let window: Vec<&(usize, &str, usize, Method)> = w.iter().map(|&k| &items[k]).collect();
        let times = interleaved(ctx, &scenes, &window, job.repeats);
        for ((i, why, _, _), t) in window.into_iter().zip(times) {
            let l = &mut lines[*i];
            match t {
                Ok(t) if !t.is_empty() => {
                    let first = [l.core.frame_ms, l.frame_ms_min, l.frame_ms_max];
                    l.core.frame_ms = median(&t);
                    l.frame_ms_min = t.iter().copied().fold(f64::INFINITY, f64::min);
                    l.frame_ms_max = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                    let look = l.second_look.get_or_insert_with(Look::default);
                    (look.retimed_as, look.first_ms, look.was_on) =
                        (Some(why.to_string()), Some(first), l.on_frontier);
                    log(&format!(
                        "second look: {}: {:.1} ms (first {:.1})",
                        l.setting(),
                        l.core.frame_ms,
                        first[0]
                    ));
                }
                Ok(_) => {}
                Err(why) => log(&format!(
                    "second look: {}: timing again failed, its first window's time stays: {why}",
                    l.setting()
                )),
            }
        }
    }
    Ok(())
}

/// Splits settings (their host bytes) into consecutive windows of at most `room` bytes each, one
/// setting at least per window.
fn windows(bytes: &[u64], room: u64) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = Vec::new();
    let mut used = 0u64;
    for (k, &b) in bytes.iter().enumerate() {
        match out.last_mut() {
            Some(w) if used.saturating_add(b) <= room => {
                w.push(k);
                used += b;
            }
            _ => {
                out.push(vec![k]);
                used = b;
            }
        }
    }
    out
}

/// One window: every renderer built, one warm-up frame each, then `repeats` rounds of one timed
/// frame each in turn. Returns each setting's frame times, or why it failed.
fn interleaved(
    ctx: &GpuContext,
    scenes: &[crate::scene::Scene],
    window: &[&(usize, &str, usize, Method)],
    repeats: u32,
) -> Vec<std::result::Result<Vec<f64>, String>> {
    let options = |mode| FrameOptions {
        mode,
        pictures: false,
    };
    let mut renderers: Vec<std::result::Result<Renderer<'_>, String>> = window
        .iter()
        .map(|(_, _, gi, m)| Renderer::new(ctx, &scenes[*gi], m).map_err(|e| e.to_string()))
        .collect();
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); window.len()];
    for round in 0..=repeats.max(1) {
        for (r, t) in renderers.iter_mut().zip(times.iter_mut()) {
            let Ok(renderer) = r else { continue };
            match renderer.frame(options(TimingMode::Frame)) {
                // Round 0 is the warm-up: pipelines and caches, not timed.
                Ok(f) if round > 0 => t.push(f.total_ms),
                Ok(_) => {}
                Err(e) => *r = Err(e.to_string()),
            }
        }
    }
    renderers
        .into_iter()
        .zip(times)
        .map(|(r, t)| r.map(|_| t))
        .collect()
}

/// frontier.md's section: the settings filled in, the settings timed again, and which moved on
/// or off the front. Empty when the second look did nothing.
pub fn table(lines: &[FrontierLine]) -> String {
    let filled: Vec<String> = lines
        .iter()
        .filter(|l| l.second_look.as_ref().is_some_and(|k| k.filled))
        .map(FrontierLine::setting)
        .collect();
    // The settings timed again, and any other that moved when the one keeping it off slowed.
    let shown: Vec<(&FrontierLine, &Look)> = lines
        .iter()
        .filter_map(|l| {
            l.second_look
                .as_ref()
                .filter(|k| k.retimed_as.is_some() || k.was_on != l.on_frontier)
                .map(|k| (l, k))
        })
        .collect();
    if filled.is_empty() && shown.is_empty() {
        return String::new();
    }
    let on = shown
        .iter()
        .filter(|(l, k)| l.on_frontier && !k.was_on)
        .count();
    let off = shown
        .iter()
        .filter(|(l, k)| !l.on_frontier && k.was_on)
        .count();
    let retimed = shown.iter().filter(|(_, k)| k.retimed_as.is_some()).count();
    let mut s = format!(
        "\n## The second look\n\nBefore the front was drawn, the n list was filled near it ({} setting{} added{}) and the front's settings with their nearest challengers (an off-front setting within {CHALLENGE}× of the time of the front setting that keeps it off, at most {PER_FRONT} each) were timed again, interleaved round by round in one window. \
         Moved onto the front: {on}; moved off it: {off}, of {} settings timed again.\n\n\
         | setting | timed again as | RMSE | first window ms | side by side ms | on the front: first → after |\n|---|---|---:|---:|---:|---|\n",
        filled.len(),
        if filled.len() == 1 { "" } else { "s" },
        if filled.is_empty() { String::new() } else { format!(": {}", filled.join(", ")) },
        retimed
    );
    let yes = |b: bool| if b { "yes" } else { "no" };
    for (l, k) in &shown {
        let (first, again) = match k.first_ms {
            Some(f) => (format!("{:.1}", f[0]), format!("{:.1}", l.core.frame_ms)),
            None => (format!("{:.1}", l.core.frame_ms), "-".to_string()),
        };
        s += &format!(
            "| {} | {} | {:.5} | {first} | {again} | {} → {} |\n",
            l.setting(),
            k.retimed_as.as_deref().unwrap_or("not timed again"),
            l.core.rmse,
            yes(k.was_on),
            yes(l.on_frontier)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(spec: &str, maps: &str, ms: f64, rmse: f64) -> FrontierLine {
        let text = format!(
            r#"{{"scene":"s","spec":"{spec}","map_config":"{maps}","kind":"regular centred","label":"{spec}","maps":1,"map_size":64,"rmse":{rmse},"flip":null,"frame_ms":{ms},"frame_ms_min":{ms},"frame_ms_max":{ms},"on_frontier":false,"beaten_by":null,"thinning":"","resolution":[32,32],"reference":"","repeats":1,"clock":"","adapter":""}}"#
        );
        serde_json::from_str(&text).unwrap()
    }

    #[test]
    fn the_n_list_is_filled_between_a_front_grids_neighbours() {
        assert_eq!(
            grid_n("regular:n=5,layout=centred,cull=on"),
            Some((5, "regular:n={},layout=centred,cull=on".into()))
        );
        assert_eq!(grid_n("regular:n=17"), Some((17, "regular:n={}".into())));
        assert_eq!(grid_n("pcss"), None);
        let specs = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let list = specs(&[
            "regular:n=2",
            "regular:n=4",
            "regular:n=8,layout=centred",
            "regular:n=4,layout=centred",
            "regular:n=11,layout=centred",
            "pcss",
        ]);
        let methods = list
            .iter()
            .map(|s| Method::parse(s, &[]).unwrap())
            .collect();
        let mut groups = vec![grid::Group {
            maps: crate::studies::hybrid::Maps::Plain(512),
            specs: list,
            methods,
        }];
        let mut lines = vec![
            line("regular:n=8,layout=centred", "plain 512", 10.0, 0.02),
            line("regular:n=4", "plain 512", 5.0, 0.05),
            line("pcss", "plain 512", 1.0, 0.1),
        ];
        lines[0].on_frontier = true;
        lines[2].on_frontier = true;
        let filled = fill(&mut groups, &lines);
        // Centred 8 between 4 and 11: 5, 6, 7, 9, 10; the lattice's 4 is off the front; pcss has no n.
        assert_eq!(filled.len(), 1);
        assert_eq!(
            filled[0].specs,
            specs(&[
                "regular:n=5,layout=centred",
                "regular:n=6,layout=centred",
                "regular:n=7,layout=centred",
                "regular:n=9,layout=centred",
                "regular:n=10,layout=centred"
            ])
        );
        assert_eq!(groups[0].specs.len(), 11);
        // Filled once: the same front fills nothing more.
        assert!(fill(&mut groups, &lines).is_empty());
    }

    #[test]
    fn front_settings_and_their_nearest_challengers() {
        // (ms, rmse): a and c on the front; b within 1.5× of a (its keeper) is a challenger,
        // d at 3× of c is not; e, f, g, h all kept off by c within 1.5×: the nearest three.
        let mut lines = vec![
            line("a", "plain 64", 10.0, 0.05),
            line("b", "plain 64", 14.0, 0.06),
            line("c", "plain 64", 20.0, 0.02),
            line("d", "plain 64", 60.0, 0.03),
            line("e", "plain 64", 29.0, 0.025),
            line("f", "plain 64", 21.0, 0.025),
            line("g", "plain 64", 25.0, 0.025),
            line("h", "plain 64", 22.0, 0.025),
        ];
        super::super::mark(&mut lines);
        assert_eq!(
            lines
                .iter()
                .filter(|l| l.on_frontier)
                .map(|l| l.core.spec.as_str())
                .collect::<Vec<_>>(),
            ["a", "c"]
        );
        let picked: Vec<(&str, &str)> = chosen(&lines)
            .into_iter()
            .map(|(i, w)| (lines[i].core.spec.as_str(), w))
            .collect();
        assert_eq!(
            picked,
            [
                ("a", "front"),
                ("c", "front"),
                ("b", "challenger"),
                ("f", "challenger"),
                ("h", "challenger"),
                ("g", "challenger")
            ]
        );
        assert_eq!(
            windows(&[5, 5, 5, 20, 1], 10),
            [vec![0, 1], vec![2], vec![3], vec![4]]
        );
        assert_eq!(windows(&[5, 5, 5], u64::MAX), [vec![0, 1, 2]]);
    }
}
