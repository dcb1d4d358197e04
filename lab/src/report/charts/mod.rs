//! Charts of result rows as SVG strings (plotters' SVG backend), and SVG → PNG with resvg.
//!
//! Each chart is a pure function of the rows it is given: filter rows (e.g. by scene) first. A
//! study's own chart lives in its folder (`studies/<study>/charts.rs`) on the scatter plot here.

mod dominance;
mod error_maps;
mod error_time;
mod labels;
mod maps_pm;
pub(crate) mod pareto;
mod raster;
pub(crate) mod scatter;
mod stages;
pub(crate) mod style;
mod temporal;

pub use crate::record::row::{params_short, ResultRow};
pub use dominance::{verdicts, Point as DominancePoint, Verdict};
pub use error_maps::error_vs_maps_svg;
pub use error_time::error_vs_time_svg;
pub use maps_pm::maps_vs_pm_svg;
pub use pareto::{pareto_front, pareto_steps};
pub use raster::svg_to_png;
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
