//! Shadow maps kept from frame to frame (docs/reuse.md). A map depends on its light sample's view
//! (the sample record: the point on the light, the frustum, the projection), on the map's size and
//! on the geometry it saw; never on the camera. So a method that keeps its maps looks each one up
//! by that key ([`MapKey`]) before it rasterizes it, and rasterizes only what it does not hold.
//!
//! - [`Slots`]: which key each layer of a method's arrays holds, and what of it a moved mesh left
//!   to draw again ([`Redraw`]). Layers are handed out by the method (a fixed place per sample, or
//!   the least recently used layer); a full cache evicts, and the evicted map is rendered again
//!   when it is needed.
//! - [`KeptMaps`]: a method's arrays with their slots, between two method states (a sequence
//!   builds the state again every frame: the renderer keeps these in [`MapCache`]).
//! - [`MapCache`]: the renderer's, carried across frames by `frame::Detached`; with reuse off it
//!   keeps nothing and every map is rendered, as before reuse existed.

use crate::gpu::structs::GpuSample;
use crate::render::shadow_raster::ShadowMapArray;
use crate::scene::light::Bounds;
use glam::{Mat4, Vec3};
use std::cell::RefCell;

/// What a map depends on, bit for bit: its sample record's view-projection, position, texel
/// angle, depth linearisation, projection kind and cube face (not its layer, array or lattice
/// index, which only say where it is kept), and the map's side.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(crate) struct MapKey {
    view: [u32; 25],
    size: u32,
}

impl MapKey {
    pub(crate) fn of(sample: &GpuSample, size: u32) -> MapKey {
        let mut view = [0u32; 25];
        let depth = [sample.texel_angle, sample.depth_lin_a, sample.depth_lin_b];
        let matrix = sample
            .light_from_world
            .iter()
            .flatten()
            .chain(&sample.position)
            .chain(&depth);
        for (w, x) in view.iter_mut().zip(matrix) {
            *w = x.to_bits();
        }
        view[23] = sample.orthographic;
        view[24] = sample.cube_face;
        MapKey { view, size }
    }

    /// The map's clip-from-world matrix (the sample record's `light_from_world`).
    fn clip_from_world(&self) -> Mat4 {
        let f: Vec<f32> = self.view[..16].iter().map(|&w| f32::from_bits(w)).collect();
        Mat4::from_cols_slice(&f)
    }

    /// The texel rectangle `[x, y, w, h]` that `b`'s projection covers, one texel of margin around
    /// it (the raster snaps vertices by less than a texel) and clamped to the map; None when it
    /// misses the map; the whole map when a corner lies at or behind the light's plane.
    pub(crate) fn footprint(&self, b: &Bounds) -> Option<[u32; 4]> {
        let m = self.clip_from_world();
        let size = self.size as f32;
        let (mut lo, mut hi) = (
            glam::Vec2::splat(f32::INFINITY),
            glam::Vec2::splat(f32::NEG_INFINITY),
        );
        for c in b.corners() {
            let p = m * c.extend(1.0);
            if !(p.w > 1e-6) || !p.is_finite() {
                return Some([0, 0, self.size, self.size]);
            }
            // NDC to texels: x to the right, y down (as shadow_lookup reads them).
            let t = glam::Vec2::new(
                (p.x / p.w + 1.0) * 0.5 * size,
                (1.0 - p.y / p.w) * 0.5 * size,
            );
            lo = lo.min(t);
            hi = hi.max(t);
        }
        let x0 = (lo.x.floor() - 1.0).max(0.0);
        let y0 = (lo.y.floor() - 1.0).max(0.0);
        let x1 = (hi.x.ceil() + 1.0).min(size);
        let y1 = (hi.y.ceil() + 1.0).min(size);
        (x1 > x0 && y1 > y0).then_some([x0 as u32, y0 as u32, (x1 - x0) as u32, (y1 - y0) as u32])
    }
}

/// What a kept layer still needs before it is the map its key names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Redraw {
    /// Nothing: the layer is the map, bit for bit.
    Kept,
    /// The texels of `[x, y, w, h]` (what a moved mesh covered before or covers now): cleared and
    /// drawn again, the rest kept.
    Rect([u32; 4]),
    /// All of it (a new key, an evicted layer, or a move that covers most of the map).
    Whole,
}

/// A rectangle larger than this share of the map is drawn whole instead.
pub(crate) const WHOLE_SHARE: f64 = 0.5;

#[derive(Clone, Copy, Debug)]
struct Slot {
    key: Option<MapKey>,
    redraw: Redraw,
    /// The frame that last used it (least recently used goes first).
    used: u64,
    /// Claimed by the current frame and not yet drawn: a frame that fails leaves it unknown.
    pending: bool,
}

/// Maps rendered and kept in one frame (run.json's `reuse`, the sequence's rows).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReuseCounts {
    /// Maps rasterized whole.
    pub rendered: u32,
    /// Maps taken as they were.
    pub kept: u32,
    /// Maps of which a rectangle was drawn again (a moved mesh's).
    pub redrawn: u32,
    /// Texels rasterized: whole maps and the redrawn rectangles.
    pub texels: u64,
    /// Texels of every map the frame used.
    pub texels_used: u64,
    /// Maps rendered whole that the frame before used too: the layers could not hold them
    /// (the cache was full, so they were evicted and rendered again).
    #[serde(default)]
    pub evicted: u32,
}

impl ReuseCounts {
    pub(crate) fn add(&mut self, other: &ReuseCounts) {
        self.rendered += other.rendered;
        self.kept += other.kept;
        self.redrawn += other.redrawn;
        self.texels += other.texels;
        self.texels_used += other.texels_used;
        self.evicted += other.evicted;
    }

    /// A frame that rasterized all of its `maps` maps of `size`².
    pub(crate) fn all_rendered(maps: u32, size: u32) -> ReuseCounts {
        let texels = maps as u64 * size as u64 * size as u64;
        ReuseCounts {
            rendered: maps,
            kept: 0,
            redrawn: 0,
            texels,
            texels_used: texels,
            evicted: 0,
        }
    }
}

/// The layers of a method's arrays and the keys they hold. `keeps = false` (reuse off, or maps
/// that depend on the frame's pixels: culled or scissored) hands out every layer as `Whole`.
#[derive(Clone, Debug)]
pub(crate) struct Slots {
    slots: Vec<Slot>,
    frame: u64,
    keeps: bool,
    pub(crate) counts: ReuseCounts,
    /// The keys this frame and the frame before placed (what `evicted` counts against); boxed, so
    /// the slots stay small beside the enums that hold them.
    keys: Box<[std::collections::HashSet<MapKey>; 2]>,
}

impl Slots {
    pub(crate) fn new(capacity: u32, keeps: bool) -> Slots {
        Slots {
            slots: vec![
                Slot {
                    key: None,
                    redraw: Redraw::Whole,
                    used: 0,
                    pending: false
                };
                capacity as usize
            ],
            frame: 0,
            keeps,
            counts: ReuseCounts::default(),
            keys: Default::default(),
        }
    }

    pub(crate) fn capacity(&self) -> u32 {
        self.slots.len() as u32
    }

    pub(crate) fn keeps(&self) -> bool {
        self.keeps
    }

    /// Starts a frame: the counts at zero; a layer a failed frame claimed but may not have drawn
    /// is forgotten.
    pub(crate) fn begin_frame(&mut self) {
        self.frame += 1;
        self.counts = ReuseCounts::default();
        let [used, last] = &mut *self.keys;
        *last = std::mem::take(used);
        for s in &mut self.slots {
            if s.pending {
                *s = Slot {
                    key: None,
                    redraw: Redraw::Whole,
                    used: 0,
                    pending: false,
                };
            }
        }
    }

    /// The frame's maps were all drawn (its commands are submitted).
    pub(crate) fn commit(&mut self) {
        for s in &mut self.slots {
            s.pending = false;
        }
    }

    /// The layer holding `key`, if any.
    pub(crate) fn find(&self, key: &MapKey) -> Option<u32> {
        if !self.keeps {
            return None;
        }
        self.slots
            .iter()
            .position(|s| s.key.as_ref() == Some(key))
            .map(|i| i as u32)
    }

    /// The least recently used layer that `busy` does not hold (the current chunk's).
    pub(crate) fn least_recent(&self, busy: impl Fn(u32) -> bool) -> Option<u32> {
        (0..self.capacity())
            .filter(|&i| !busy(i))
            .min_by_key(|&i| (self.slots[i as usize].used, i))
    }

    /// Whether layer `slot` was used by the current frame.
    pub(crate) fn used_now(&self, slot: u32) -> bool {
        self.slots[slot as usize].used == self.frame
    }

    /// Layer `slot` will hold `key` this frame: what must be drawn for it (and the counts).
    pub(crate) fn place(&mut self, key: MapKey, slot: u32) -> Redraw {
        let s = &mut self.slots[slot as usize];
        let redraw = if self.keeps && s.key == Some(key) {
            s.redraw
        } else {
            Redraw::Whole
        };
        let [used, last] = &mut *self.keys;
        if self.keeps && redraw == Redraw::Whole && last.contains(&key) {
            self.counts.evicted += 1;
        }
        if self.keeps {
            used.insert(key);
        }
        let texels = key.size as u64 * key.size as u64;
        self.counts.texels_used += texels;
        match redraw {
            Redraw::Kept => self.counts.kept += 1,
            Redraw::Rect([_, _, w, h]) => {
                self.counts.redrawn += 1;
                self.counts.texels += w as u64 * h as u64;
            }
            Redraw::Whole => {
                self.counts.rendered += 1;
                self.counts.texels += texels;
            }
        }
        *s = Slot {
            key: self.keeps.then_some(key),
            redraw: Redraw::Kept,
            used: self.frame,
            pending: true,
        };
        redraw
    }

    /// The geometry inside `before` moved to `after`: every kept map draws again what either box
    /// covers, or all of it where that is more than `WHOLE_SHARE` of the map.
    pub(crate) fn moved(&mut self, before: &Bounds, after: &Bounds) {
        for s in &mut self.slots {
            let Some(key) = s.key else { continue };
            let rect = union_rect(key.footprint(before), key.footprint(after));
            s.redraw = match (s.redraw, rect) {
                (r, None) => r,
                (Redraw::Whole, _) => Redraw::Whole,
                (Redraw::Kept, Some(r)) => Redraw::Rect(r),
                (Redraw::Rect(a), Some(b)) => {
                    Redraw::Rect(union_rect(Some(a), Some(b)).expect("two rectangles"))
                }
            };
            if let Redraw::Rect([_, _, w, h]) = s.redraw {
                if (w as f64 * h as f64) > WHOLE_SHARE * (key.size as f64 * key.size as f64) {
                    s.redraw = Redraw::Whole;
                }
            }
        }
    }

    /// Layers holding a key.
    pub(crate) fn held(&self) -> u32 {
        self.slots.iter().filter(|s| s.key.is_some()).count() as u32
    }
}

/// The smallest rectangle holding both (either may be absent).
fn union_rect(a: Option<[u32; 4]>, b: Option<[u32; 4]>) -> Option<[u32; 4]> {
    match (a, b) {
        (None, r) | (r, None) => r,
        (Some([ax, ay, aw, ah]), Some([bx, by, bw, bh])) => {
            let (x0, y0) = (ax.min(bx), ay.min(by));
            let (x1, y1) = ((ax + aw).max(bx + bw), (ay + ah).max(by + bh));
            Some([x0, y0, x1 - x0, y1 - y0])
        }
    }
}

/// A method's arrays and their slots, kept between two states of the same renderer.
pub struct KeptMaps {
    /// Which of the method's map sets this is (`fixed`, `adaptive`, `auto 5x512`, ...).
    pub(crate) owner: String,
    pub(crate) size: u32,
    pub arrays: Vec<ShadowMapArray>,
    pub(crate) slots: Slots,
}

impl KeptMaps {
    /// Bytes the arrays hold.
    pub(crate) fn bytes(&self) -> u64 {
        self.arrays.iter().map(|a| a.layers() as u64).sum::<u64>()
            * self.size as u64
            * self.size as u64
            * 4
    }
}

/// The renderer's kept maps between method states (`frame::Detached` carries it from frame to
/// frame). With `on` false it keeps nothing.
#[derive(Default)]
pub struct MapCache {
    pub(crate) on: bool,
    kept: RefCell<Vec<KeptMaps>>,
}

impl MapCache {
    pub(crate) fn new(on: bool) -> MapCache {
        MapCache {
            on,
            kept: RefCell::new(Vec::new()),
        }
    }

    /// The kept maps of `owner` when they have this size and shape (`layers` per array); None
    /// otherwise (the caller allocates, and what was kept is dropped).
    pub(crate) fn take(&self, owner: &str, size: u32, layers: &[u32]) -> Option<KeptMaps> {
        let mut kept = self.kept.borrow_mut();
        let at = kept.iter().position(|k| k.owner == owner)?;
        let k = kept.swap_remove(at);
        let shape: Vec<u32> = k.arrays.iter().map(ShadowMapArray::layers).collect();
        (self.on && k.size == size && shape == layers).then_some(k)
    }

    /// Keeps `maps` for the next state (nothing with reuse off).
    pub(crate) fn give(&self, maps: KeptMaps) {
        if self.on && maps.slots.keeps() {
            let mut kept = self.kept.borrow_mut();
            kept.retain(|k| k.owner != maps.owner);
            kept.push(maps);
        }
    }

    /// See [`Slots::moved`], for every kept map.
    pub(crate) fn moved(&self, before: &Bounds, after: &Bounds) {
        for k in self.kept.borrow_mut().iter_mut() {
            k.slots.moved(before, after);
        }
    }

    /// Keeps at most `budget` bytes of maps between frames: the sets that hold the most maps
    /// first, the rest dropped (a method with several sets, `regions`' groups, can hold more than
    /// one budget's worth in a frame; what it keeps for the next is bounded).
    pub(crate) fn trim(&self, budget: u64) {
        let mut kept = self.kept.borrow_mut();
        kept.sort_by_key(|k| std::cmp::Reverse(k.slots.held()));
        let mut total = 0;
        kept.retain(|k| {
            total += k.bytes();
            total <= budget
        });
    }

    /// Drops every kept map.
    pub(crate) fn clear(&self) {
        self.kept.borrow_mut().clear();
    }

    /// Bytes of the maps kept now.
    pub fn bytes(&self) -> u64 {
        self.kept.borrow().iter().map(KeptMaps::bytes).sum()
    }

    /// `f` of `owner`'s kept maps (tests read and write their layers).
    pub fn with_kept<R>(&self, owner: &str, f: impl FnOnce(Option<&KeptMaps>) -> R) -> R {
        f(self.kept.borrow().iter().find(|k| k.owner == owner))
    }
}

/// What moved between two versions of a scene's meshes.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Moved {
    /// No vertex position changed.
    Nothing,
    /// The boxes of the moved triangles before and after.
    Boxes(Bounds, Bounds),
    /// Not comparable vertex by vertex (other meshes): nothing kept holds.
    Other,
}

/// The boxes of the geometry that moved between two versions of one mesh set (the same
/// triangles, vertices in the same order), before and after: over every vertex of each triangle
/// that has a vertex whose position changed (a triangle covers texels between all three).
pub(crate) fn moved_boxes(
    before: &[crate::scene::Vertex],
    after: &[crate::scene::Vertex],
    indices: &[u32],
) -> Moved {
    if before.len() != after.len() {
        return Moved::Other;
    }
    let moved: Vec<bool> = before
        .iter()
        .zip(after)
        .map(|(a, b)| bytemuck::bytes_of(&a.position) != bytemuck::bytes_of(&b.position))
        .collect();
    if !moved.contains(&true) {
        return Moved::Nothing;
    }
    let empty = || Bounds {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    let (mut a, mut b) = (empty(), empty());
    for t in indices.chunks_exact(3) {
        if t.iter().any(|&i| moved[i as usize]) {
            for &i in t {
                a.min = a.min.min(Vec3::from(before[i as usize].position));
                a.max = a.max.max(Vec3::from(before[i as usize].position));
                b.min = b.min.min(Vec3::from(after[i as usize].position));
                b.max = b.max.max(Vec3::from(after[i as usize].position));
            }
        }
    }
    // Moved vertices that no triangle uses draw nothing.
    if a.min.x <= a.max.x {
        Moved::Boxes(a, b)
    } else {
        Moved::Nothing
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(x: f32) -> MapKey {
        let s = GpuSample {
            light_from_world: Mat4::IDENTITY.to_cols_array_2d(),
            position: [x, 0.0, 0.0, 1.0],
            ..Default::default()
        };
        MapKey::of(&s, 64)
    }

    #[test]
    fn a_key_ignores_where_the_map_is_kept() {
        let s = GpuSample {
            light_from_world: Mat4::IDENTITY.to_cols_array_2d(),
            layer: 3,
            array: 1,
            lattice: 7,
            ..Default::default()
        };
        let t = GpuSample {
            layer: 9,
            array: 0,
            lattice: 2,
            ..s
        };
        assert_eq!(MapKey::of(&s, 64), MapKey::of(&t, 64));
        assert_ne!(MapKey::of(&s, 64), MapKey::of(&s, 128));
        assert_ne!(
            MapKey::of(&s, 64),
            MapKey::of(&GpuSample { cube_face: 2, ..s }, 64)
        );
    }

    #[test]
    fn slots_keep_what_they_hold_and_count_it() {
        let mut s = Slots::new(2, true);
        s.begin_frame();
        assert_eq!(s.place(key(1.0), 0), Redraw::Whole);
        assert_eq!(s.place(key(2.0), 1), Redraw::Whole);
        s.commit();
        assert_eq!(
            s.counts,
            ReuseCounts {
                rendered: 2,
                kept: 0,
                redrawn: 0,
                texels: 2 * 64 * 64,
                texels_used: 2 * 64 * 64,
                evicted: 0,
            }
        );
        s.begin_frame();
        assert_eq!(s.find(&key(2.0)), Some(1));
        assert_eq!(s.place(key(2.0), 1), Redraw::Kept);
        // Layer 0 is the least recent now: a new key evicts it.
        assert_eq!(s.least_recent(|i| i == 1), Some(0));
        assert_eq!(s.place(key(3.0), 0), Redraw::Whole);
        assert_eq!(s.find(&key(1.0)), None);
        assert_eq!((s.counts.kept, s.counts.rendered), (1, 1));
        // Key 3 is new, not evicted: the frame before did not use it.
        assert_eq!(s.counts.evicted, 0);
        s.commit();
        // Key 2, used by the frame before, no longer has its layer: evicted.
        s.begin_frame();
        assert_eq!(s.place(key(2.0), 0), Redraw::Whole);
        assert_eq!((s.counts.rendered, s.counts.evicted), (1, 1));
    }

    #[test]
    fn a_failed_frame_forgets_what_it_claimed() {
        let mut s = Slots::new(1, true);
        s.begin_frame();
        s.place(key(1.0), 0);
        // No commit: the next frame cannot trust the layer.
        s.begin_frame();
        assert_eq!(s.place(key(1.0), 0), Redraw::Whole);
    }

    #[test]
    fn without_keeping_every_map_is_drawn() {
        let mut s = Slots::new(1, false);
        for _ in 0..2 {
            s.begin_frame();
            assert_eq!(s.find(&key(1.0)), None);
            assert_eq!(s.place(key(1.0), 0), Redraw::Whole);
            s.commit();
        }
    }

    #[test]
    fn a_moved_vertex_brings_its_whole_triangle_into_the_boxes() {
        let v = |x: f32, y: f32| crate::scene::Vertex {
            position: [x, y, 0.0],
            normal: [0.0, 0.0, 1.0],
            material: 0,
        };
        let before = [
            v(0.0, 0.0),
            v(1.0, 0.0),
            v(0.0, 1.0),
            v(5.0, 5.0),
            v(6.0, 5.0),
            v(5.0, 6.0),
        ];
        let mut after = before;
        after[2] = v(0.0, 2.0);
        let Moved::Boxes(a, b) = moved_boxes(&before, &after, &[0, 1, 2, 3, 4, 5]) else {
            panic!("a vertex moved")
        };
        // The moved triangle's three vertices, not the other triangle's.
        assert_eq!((a.min, a.max), (Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0)));
        assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::new(1.0, 2.0, 0.0)));
        assert!(matches!(
            moved_boxes(&before, &before, &[0, 1, 2]),
            Moved::Nothing
        ));
        assert!(matches!(
            moved_boxes(&before, &before[..3], &[0, 1, 2]),
            Moved::Other
        ));
    }

    #[test]
    fn a_move_redraws_the_rectangle_both_boxes_cover_or_the_whole_map() {
        // Identity view-projection: NDC x, y in [-1, 1] span the 64² map.
        let mut s = Slots::new(1, true);
        s.begin_frame();
        s.place(key(0.0), 0);
        s.commit();
        let small = |x: f32| Bounds {
            min: Vec3::new(x, 0.0, 0.5),
            max: Vec3::new(x + 0.1, 0.1, 0.5),
        };
        s.moved(&small(0.0), &small(0.2));
        s.begin_frame();
        // x from 0 to 0.3 in NDC: texels 32 to 41.6, one texel of margin; y 0..0.1: rows 28.8..32.
        assert_eq!(s.place(key(0.0), 0), Redraw::Rect([31, 27, 12, 6]));
        s.commit();
        s.moved(
            &Bounds {
                min: Vec3::splat(-0.9),
                max: Vec3::splat(0.9),
            },
            &small(0.0),
        );
        s.begin_frame();
        assert_eq!(s.place(key(0.0), 0), Redraw::Whole);
        // A box that misses the map leaves it kept.
        s.commit();
        s.moved(&small(5.0), &small(6.0));
        s.begin_frame();
        assert_eq!(s.place(key(0.0), 0), Redraw::Kept);
    }
}
