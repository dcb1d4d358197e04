//! What `regions` decided for one class of a frame, shared by the method's run record and its
//! pictures (so neither module imports the other).

/// One class of a frame: its grid, map size, tiles and window.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ClassRecord {
    pub class: u32,
    pub n: u32,
    pub map_size: u32,
    pub tiles: u32,
    pub maps: u32,
    /// The finest texel its pixels need (tangent units from the light, per texel).
    pub texel_need: f32,
    /// The window's side in tangent units, as the centre sees it.
    pub extent: f32,
    pub triangles_per_map_mean: f64,
}
