//! The buffers the adaptive stages read and write, grouped by the pass that writes them, and the
//! constants their kernels mirror. The passes take these groups (not the whole method state); the
//! adaptive method (methods/adaptive/buffers.rs) allocates and owns them, and a test or bench can
//! build them to drive one pass alone.

use crate::gpu::structs::GpuControl;

pub const LATTICE_SIDE: u32 = 17;
pub const LATTICE_POINTS: u32 = 289;
pub const MASK_WORDS: u32 = 10;
/// Quads of one level: at most 4^4 = 256 (level 4 of the 17x17 lattice).
pub const QUAD_CAPACITY: u32 = 256;
pub const NO_SPLIT: u32 = u32::MAX;
/// Culling tiles per side of a map, and the u32 words of one sample's tiles (common.wgsl): per
/// tile 0, or the largest depth limit its pixels test (f32 bits).
pub const CULL_TILES: u32 = 256;
pub const CULL_TILE_WORDS: u32 = CULL_TILES * CULL_TILES;
/// word_state of a word whose comparison-map words differ by quad (common.wgsl MIXED_WORD).
pub const MIXED_WORD: u32 = u32::MAX;
pub const CONTROL_BYTES: u64 = std::mem::size_of::<GpuControl>() as u64;

/// Workgroups in one dimension of scope = local's list passes (kernels/shared/common.wgsl
/// `LIST_GROUPS_X`, WebGPU's guaranteed limit): a longer list's workgroups go on in rows.
pub(crate) const LIST_GROUPS_X: u32 = 65535;

/// The CPU twin of common.wgsl `list_dispatch`: the indirect dispatch size that reproject_count's
/// and probe's `begin` write for a list of `n` items, 64 per workgroup.
pub fn list_dispatch(n: u32) -> [u32; 3] {
    let groups = n.div_ceil(64);
    [
        groups.min(LIST_GROUPS_X),
        groups.div_ceil(LIST_GROUPS_X).max(1),
        1,
    ]
}

/// The sizes every adaptive buffer and dispatch derives from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shape {
    pub width: u32,
    pub height: u32,
    pub words_per_row: u32,
    pub flag_words_per_row: u32,
    /// Quads whose comparison maps fit at once (dense mode batches beyond it).
    pub count_quads: u32,
    pub item_capacity: u32,
}

impl Shape {
    pub fn counts_bytes_per_quad(&self) -> u64 {
        self.height as u64 * self.words_per_row as u64 * 4
    }
    pub fn flags_bytes_per_quad(&self) -> u64 {
        self.height as u64 * self.flag_words_per_row as u64 * 4
    }
    /// Bytes of one per-pixel lattice mask buffer.
    pub fn mask_bytes(&self) -> u64 {
        self.width as u64 * self.height as u64 * MASK_WORDS as u64 * 4
    }
    /// The comparison maps of `n` quads as every quad's full map: uniform words from `word_state`.
    pub fn dense_counts(counts: &mut [u32], word_state: &[u32]) {
        for map in counts.chunks_exact_mut(word_state.len()) {
            for (c, &s) in map.iter_mut().zip(word_state) {
                if s != MIXED_WORD {
                    *c = s;
                }
            }
        }
    }
}

/// shadow_test's output, per pixel MASK_WORDS words each.
pub struct Masks {
    /// Bit k = lattice sample k lights the pixel (tested samples only).
    pub lit: wgpu::Buffer,
    /// scope = local: bit k = the pixel consulted sample k (shadow_test tested it).
    pub(crate) consulted: wgpu::Buffer,
}

/// reproject_count's output: the comparison maps (one count byte per pixel and quad).
pub struct CountMaps {
    pub maps: wgpu::Buffer,
    /// One word per comparison-map word: its bytes when uniform (the same in every quad's map, which
    /// then holds nothing for it), else MIXED_WORD. Scope = local never writes it: all MIXED_WORD.
    pub word_state: wgpu::Buffer,
}

/// neighbourhood's low-quality flags (a bit per pixel and quad) and quad_count's counters.
pub struct LowQuality {
    pub flags: wgpu::Buffer,
    /// Low-quality pixels per quad (neighbourhood `list` counts them itself under scope = local).
    pub per_quad: wgpu::Buffer,
}

/// subdivide's decisions, kept across levels.
pub struct Decisions {
    /// Per lattice sample: requested (rendered or to render).
    pub lattice_state: wgpu::Buffer,
    /// The samples requested for the next level (control.new_sample_count of them).
    pub new_samples: wgpu::Buffer,
    /// Deepest evaluated level per lattice sample.
    pub sample_level: wgpu::Buffer,
    /// First child index per quad of the level, or NO_SPLIT.
    pub split_base: wgpu::Buffer,
    /// The next level's quad_count dispatch (flag words x quads).
    pub(crate) dispatch_args: wgpu::Buffer,
    /// One bit per quad node (`quad_node`): split in the previous frame (hysteresis, `hold`).
    pub held: wgpu::Buffer,
}

/// Quads of every level of the lattice's quadtree: 1 + 4 + 16 + 64 + 256.
pub const QUAD_NODES: u32 = 341;
/// u32 words of the `held` bits.
pub const HELD_WORDS: u32 = QUAD_NODES.div_ceil(32);

/// A quad's place among every level's quads (kernels/subdivide.wgsl `quad_node`): the coarser
/// levels' (4^d − 1) / 3 first, then its row and column at its own level.
pub fn quad_node(i: u32, j: u32, size: u32) -> u32 {
    let side = 16 / size;
    (side * side - 1) / 3 + (j / size) * side + i / size
}

/// scope = local: the (pixel, quad) items of this level and the next, the probes, their counts
/// and dispatches, and V's integer sums.
pub struct ItemLists {
    pub items: [wgpu::Buffer; 2],
    pub total: wgpu::Buffer,
    pub list_args: wgpu::Buffer,
    /// Uniform pixels of split quads for the next level, their count and dispatch.
    pub probes: wgpu::Buffer,
    pub probe_total: wgpu::Buffer,
    pub probe_args: wgpu::Buffer,
    pub visibility_fixed: wgpu::Buffer,
}

/// Per lattice sample, what compact grows for the next maps: texel rectangles (scissor) and
/// CULL_TILE_WORDS culling tiles (the largest depth limit each tile's pixels test).
pub struct Footprints {
    pub(crate) rects: wgpu::Buffer,
    pub(crate) tiles: wgpu::Buffer,
}

/// What a count pass reads of the frame and the level: the frame uniform (the screen), the level
/// uniform, the level's quads, the frame's control counters, which of the double-buffered item
/// lists is the level's (`ItemLists::items[cur]`), and the sizes its dispatch derives from. A test
/// or bench builds one from its own buffers to drive a pass alone.
#[derive(Clone, Copy)]
pub struct Level<'a> {
    pub frame: &'a wgpu::Buffer,
    pub uniform: &'a wgpu::Buffer,
    pub quads: &'a wgpu::Buffer,
    pub control: &'a wgpu::Buffer,
    pub cur: usize,
    pub shape: Shape,
}

/// What shadow_test reads besides the maps: the sample records, subdivide's requests and the
/// control counters (the steered list's count).
#[derive(Clone, Copy)]
pub struct Requests<'a> {
    pub samples: &'a wgpu::Buffer,
    pub decisions: &'a Decisions,
    pub control: &'a wgpu::Buffer,
}
