//! What `penumbra.analysis` reads of the engine and the lab instead of copying it: the
//! calibration's factors, the promise `auto` is judged by, a spec's parameters as the engine
//! parses it, and the two laws the results' analyses replay (`auto::predicted_at`,
//! `regions::half_octave`).

use penumbra::research::methods::calibration::{self, Class, Factors};
use penumbra::research::methods::estimate::Prediction;
use penumbra::research::methods::{auto, regions, Method};
use penumbra_lab::studies::calibration::{COVERAGE_PERCENT, SPLIT};
use penumbra_lab::studies::frontier::budget;
use pyo3::prelude::*;
use pyo3::types::{PyAny, PyDict};

fn factors(f: Factors) -> serde_json::Value {
    serde_json::json!({ "sampling": f.sampling, "map": f.map })
}

/// The constants as one dict: `calibration` (per light class, the even sides' sampling factors,
/// the fitted range, the share of pairs a fit covers and the split of the shipped scenes), `promise` (the shares and
/// the time ratio) and `auto` (the sampling order).
#[pyfunction]
pub fn analysis_constants(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let value = serde_json::json!({
        "calibration": {
            "plane": factors(calibration::PLANE),
            "cube": factors(calibration::CUBE),
            "even_sampling": { "plane": calibration::EVEN_PLANE_SAMPLING, "cube": calibration::EVEN_CUBE_SAMPLING },
            "max_fitted_even": calibration::MAX_FITTED_EVEN,
            "min_fitted_size": calibration::MIN_FITTED_SIZE,
            "coverage_percent": COVERAGE_PERCENT,
            "split": SPLIT.iter().map(|(scene, half)| ((*scene).to_string(), serde_json::Value::from(half.name()))).collect::<serde_json::Map<_, _>>(),
        },
        "promise": { "met_share": budget::MET_SHARE, "time_ratio": budget::TIME_RATIO, "time_share": budget::TIME_SHARE },
        "auto": { "sampling_order": auto::SAMPLING_ORDER },
    });
    crate::json_to_py(py, &value)
}

/// A spec's parameters as the engine parses it (defaults included), and its name as `method`.
#[pyfunction]
pub fn method_params<'py>(py: Python<'py>, spec: &str) -> PyResult<Bound<'py, PyAny>> {
    let m = Method::parse(spec, &[]).map_err(crate::engine)?;
    let mut params = m.params_json();
    if let Some(map) = params.as_object_mut() {
        map.insert("method".into(), m.name().into());
    }
    crate::json_to_py(py, &params)
}

fn class(name: &str) -> PyResult<Class> {
    match name {
        "plane" => Ok(Class::Plane),
        "cube" => Ok(Class::Cube),
        other => Err(crate::PenumbraError::new_err(format!(
            "light class {other:?}: expected plane or cube"
        ))),
    }
}

fn part(p: &Bound<'_, PyDict>, key: &str) -> PyResult<f64> {
    match p.get_item(key)? {
        Some(v) => v.extract(),
        None => Err(crate::PenumbraError::new_err(format!(
            "prediction: no {key:?}"
        ))),
    }
}

/// `auto::predicted_at`: the predicted RMSE of the centred grid (n2, size2) from a try's parts at
/// (n, size), in a scene of `light_class` (`plane` or `cube`).
#[pyfunction]
pub fn auto_predicted_at(
    light_class: &str,
    n: u32,
    size: u32,
    prediction: &Bound<'_, PyDict>,
    n2: u32,
    size2: u32,
) -> PyResult<f64> {
    let p = Prediction {
        predicted_rmse: f64::NAN,
        predicted_sampling: part(prediction, "predicted_sampling")?,
        predicted_map: part(prediction, "predicted_map")?,
        predicted_quantization: f64::NAN,
        predicted_bias: f64::NAN,
        predicted_map_averaging: part(prediction, "predicted_map_averaging")?,
    };
    Ok(auto::predicted_at(
        class(light_class)?,
        &auto::At::new(n, size, p),
        (n2, size2),
    ))
}

/// `regions::half_octave`: the map side `regions` gives a wanted side.
#[pyfunction]
pub fn regions_half_octave(want: f32) -> u32 {
    regions::half_octave(want)
}

/// `regions::density_floor` with the `density` parameter unset: the least texels per pixel
/// footprint a frame takes under a scene's bias (in texels).
#[pyfunction]
pub fn regions_density_floor(constant: f32, slope: f32, normal_offset: f32) -> f32 {
    let bias = penumbra::research::scene::BiasDef {
        constant,
        slope,
        normal_offset,
        ..Default::default()
    };
    regions::density_floor(0.0, &bias)
}
