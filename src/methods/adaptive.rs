//! Adaptive light-source sampling (placeholder until the adaptive stages land).
use super::AdaptiveParams;
use crate::frame::{FrameGpu, MethodOutput};
use crate::timing::StageTimer;
use crate::{Error, Result};

pub fn run(_fg: &FrameGpu, _timer: &mut StageTimer, _p: &AdaptiveParams) -> Result<MethodOutput> {
    Err(Error::Param("adaptive: not built yet".into()))
}
