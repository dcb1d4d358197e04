//! scope = local: the (pixel, quad) item list follows the need. A level that overflows it stops
//! the frame (the overflow flag stays the guard: nothing is clipped); the list is then rebuilt
//! from what that level counted and the whole frame runs again. V sums integers in any order, so
//! the frame that fits gives the V it would have given on a list that was large enough at once.

use super::record::ItemsRecord;

/// What frames that overflowed asked for, and what they cost, until the next frame reports it.
#[derive(Clone, Debug, Default)]
pub(crate) struct Growth {
    /// Set by a frame that overflowed the item list: the items (or probes) its level appended.
    pub(crate) needed: Option<u64>,
    /// Read-backs made by the frames that overflowed and ran again: the frame that fits counts them.
    pub(crate) syncs: u32,
    /// The capacities the list grew to since the last frame that fitted.
    pub(crate) grown: Vec<u32>,
    /// The list never grows (`PENUMBRA_ITEMS_FIXED`).
    pub(crate) fixed: bool,
}

/// The variable of [`fixed_from_env`].
pub(crate) const FIXED_VAR: &str = "PENUMBRA_ITEMS_FIXED";

/// `PENUMBRA_ITEMS_FIXED=N`: the item list of every scope = local setting that names no `items`
/// holds N items and never grows. A test hook: it makes the local settings of a study whose
/// settings come from a grid (frontier, bench) overflow, as a held-out scene does.
pub(crate) fn fixed_from_env() -> crate::Result<Option<u32>> {
    let Some(v) = std::env::var_os(FIXED_VAR) else {
        return Ok(None);
    };
    let v = v.to_string_lossy();
    match v.parse::<u32>() {
        Ok(n) if n >= 1 => Ok(Some(n)),
        _ => Err(crate::Error::Param(format!(
            "{FIXED_VAR} = `{v}`: use a whole number of items, at least 1"
        ))),
    }
}

impl Growth {
    /// A frame overflowed the item list after `syncs` read-backs; its level appended `appended`.
    pub(crate) fn overflowed(&mut self, appended: u64, syncs: u32) {
        self.needed = Some(appended);
        self.syncs += syncs;
    }

    /// The frame that fitted (`out`, on a list of `capacity`): it counts the read-backs of the
    /// frames run before it, and its record says what the list grew to (run.json `items`).
    /// The record is adaptive's (`AdaptiveRecord`), already a value: `items` joins it here,
    /// after the frame, since only the frame that fitted knows it was the last.
    pub(crate) fn report(
        &mut self,
        capacity: u32,
        out: &mut crate::methods::MethodOutput,
    ) -> crate::Result<()> {
        out.syncs += self.syncs;
        if out.record.get("syncs").is_some() {
            out.record["syncs"] = out.syncs.into();
        }
        let items = ItemsRecord {
            capacity,
            frames_run_again: self.grown.len(),
            grown_to: std::mem::take(&mut self.grown),
        };
        out.record["items"] = crate::methods::record_value("adaptive", &items)?;
        self.syncs = 0;
        Ok(())
    }
}

/// The capacity to run again with after an overflow at `current` whose level appended `needed`:
/// twice the larger of the two (the next levels split further), at most `max` (what one binding
/// holds). None when the list is already at `max`: the frame fails with its overflow.
pub(crate) fn next_capacity(current: u32, needed: u64, max: u64) -> Option<u32> {
    if current as u64 >= max {
        return None;
    }
    let want = needed.max(current as u64).saturating_mul(2);
    Some(want.min(max).min(u32::MAX as u64) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_capacity_doubles_past_the_need_and_stops_at_one_binding() {
        // The count known: twice it. An overflow whose count was lost (the probes' own, restarted
        // by the next level): twice the capacity.
        assert_eq!(next_capacity(1000, 3000, 1 << 20), Some(6000));
        assert_eq!(next_capacity(1000, 0, 1 << 20), Some(2000));
        assert_eq!(next_capacity(1000, 700_000, 1 << 20), Some(1 << 20));
        assert_eq!(next_capacity(1 << 20, 5_000_000, 1 << 20), None);
        assert_eq!(
            next_capacity(u32::MAX - 1, u32::MAX as u64, u64::MAX),
            Some(u32::MAX)
        );
    }

    #[test]
    fn the_frame_that_fits_counts_the_syncs_once() {
        let mut g = Growth::default();
        g.overflowed(5000, 3);
        g.grown.push(10_000);
        let mut out = crate::methods::MethodOutput {
            shadow_maps: 9,
            syncs: 4,
            record: serde_json::json!({ "syncs": 4 }),
            pictures: Vec::new(),
            bound: None,
        };
        g.report(10_000, &mut out).unwrap();
        assert_eq!((out.syncs, out.record["syncs"].as_u64()), (7, Some(7)));
        assert_eq!(
            out.record["items"],
            serde_json::json!({ "capacity": 10_000, "frames_run_again": 1, "grown_to": [10_000] })
        );
        g.report(10_000, &mut out).unwrap();
        assert_eq!(out.syncs, 7);
        assert_eq!(out.record["items"]["frames_run_again"], 0);
    }
}
