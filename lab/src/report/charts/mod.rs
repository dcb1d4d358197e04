//! Charts of result rows as SVG strings (plotters' SVG backend), and SVG → PNG with resvg.
//!
//! Each chart is a pure function of the rows it is given: filter rows (e.g. by scene) first.

mod calibration;
mod cascades;
mod dominance;
mod environment;
mod error_maps;
mod estimate;
mod error_time;
mod framing;
mod frontier;
mod hybrid;
mod labels;
mod maps_pm;
mod pareto;
mod raster;
mod scatter;
mod stages;
mod style;
mod temporal;

pub use calibration::{calibration_svg, parts_svg};
pub use cascades::{cascades_svg, CascadePoint};
pub use dominance::{verdicts, Point as DominancePoint, Verdict};
pub use environment::{env_chart_svg, EnvAxis};
pub use error_maps::error_vs_maps_svg;
pub use estimate::{estimate_svg, EstimatePoint};
pub use error_time::error_vs_time_svg;
pub use framing::{framing_svg, WidthAxis, WidthPoint};
pub use frontier::{frontier_svg, FrontierPoint};
pub use hybrid::{error_memory_svg, MemoryPoint};
pub use maps_pm::maps_vs_pm_svg;
pub use pareto::{pareto_front, pareto_steps};
pub use raster::svg_to_png;
pub use crate::record::row::{params_short, ResultRow};
pub use stages::{frame_split_svg, stage_breakdown_svg};
pub use temporal::{per_frame_svg, FrameSeries};

#[derive(Debug, thiserror::Error)]
pub enum ChartError {
    #[error("no row can be plotted on this chart: {0}")]
    NoData(&'static str),
    #[error("plotting failed: {0}")]
    Plot(String),
    #[error("SVG parse failed: {0}")]
    Svg(String),
    #[error("bad PNG scale {0} (must be finite, > 0, and give at most 16384 px a side)")]
    BadScale(f32),
    #[error("PNG encoding failed: {0}")]
    Png(String),
}

#[cfg(test)]
pub(crate) mod tests;
