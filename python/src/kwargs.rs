//! Parameters from `**kwargs`: keyword arguments mapped onto the serde fields of the library's
//! parameter structs, the drop presets, and lowercase serde enums from their names.

use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rocking_stones::dynamics::size::{dimension, Dimension, RealSize};
use serde::Serialize;

/// `base` with the fields named in `params` replaced, each value given in real units for the
/// stone of size `size` as the command line's options are ([`real_value`]): the keyword
/// arguments map to the serde fields of the parameter struct (nested structs are searched too,
/// e.g. `RestingParams.sim`), so the binding follows the library's structs without a list of its
/// own.
pub(crate) fn with_params<T: Serialize + serde::de::DeserializeOwned>(
    what: &str,
    base: &T,
    params: Option<&Bound<'_, PyDict>>,
    size: &RealSize,
) -> PyResult<T> {
    let mut value = serde_json::to_value(base).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    if let Some(params) = params {
        for (k, v) in params.iter() {
            let given: String = k.extract()?;
            let (key, scale) = real_value(what, &given, size)?;
            let new = if let Ok(b) = v.extract::<bool>() {
                serde_json::Value::from(b)
            } else if let Ok(text) = v.extract::<String>() {
                serde_json::Value::from(text) // an enum field, e.g. spin_distribution
            } else {
                let x: f64 = v.extract().map_err(|_| {
                    PyTypeError::new_err(format!(
                        "{what}: parameter {key} must be a number (or a name), got {}",
                        v.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                    ))
                })?;
                serde_json::Number::from_f64(scale(x))
                    .map(serde_json::Value::Number)
                    .ok_or_else(|| PyValueError::new_err(format!("{what}: {given} must be finite, got {x}")))?
            };
            if !set_field(&mut value, key, new) {
                let mut names = Vec::new();
                field_names(&value, &mut names);
                for n in &mut names {
                    if matches!(n.as_str(), "rolling_resistance" | "torsional_friction") {
                        n.push_str("_mm");
                    }
                }
                return Err(PyTypeError::new_err(format!(
                    "{what}: unknown parameter {given:?} (parameters: {})",
                    names.join(", ")
                )));
            }
        }
    }
    serde_json::from_value(value).map_err(|e| PyValueError::new_err(format!("{what}: {e}")))
}

/// How a keyword's value turns into the scaled frame's number.
type ToScaled = Box<dyn Fn(f64) -> f64>;

/// The parameter a keyword names and how its value turns into the scaled frame: a time, speed,
/// spin, damping or frequency is given in SI for the stone's real size; the rolling-resistance
/// and torsional-friction lengths as `rolling_resistance_mm` / `torsional_friction_mm`, in mm;
/// the rest as they are (friction, restitution, solver iterations, heights in R_max…). The
/// lengths' former keywords (relative to R_max) are refused, naming the new ones.
fn real_value<'k>(what: &str, key: &'k str, size: &RealSize) -> PyResult<(&'k str, ToScaled)> {
    let size = *size;
    if let Some(stem @ ("rolling_resistance" | "torsional_friction")) = key.strip_suffix("_mm") {
        return Ok((stem, Box::new(move |mm| size.scaled(Dimension::Length, mm * 1e-3))));
    }
    if matches!(key, "rolling_resistance" | "torsional_friction") {
        return Err(PyTypeError::new_err(format!(
            "{what}: {key} (relative to R_max) is now {key}_mm, the length in mm"
        )));
    }
    Ok(match dimension(key) {
        Some(d) => (key, Box::new(move |x| size.scaled(d, x))),
        None => (key, Box::new(|x| x)),
    })
}

fn set_field(v: &mut serde_json::Value, key: &str, new: serde_json::Value) -> bool {
    let Some(map) = v.as_object_mut() else { return false };
    if let Some(slot) = map.get_mut(key) {
        if !slot.is_object() {
            // Keep integers integers (serde refuses 3.0 for a u32).
            *slot = match (slot.is_u64() || slot.is_i64(), new.as_f64()) {
                (true, Some(x)) if x.fract() == 0.0 && x >= 0.0 => serde_json::Value::from(x as u64),
                _ => new,
            };
            return true;
        }
    }
    map.values_mut().any(|child| child.is_object() && set_field(child, key, new.clone()))
}

fn field_names(v: &serde_json::Value, out: &mut Vec<String>) {
    if let Some(map) = v.as_object() {
        for (k, child) in map {
            if child.is_object() {
                field_names(child, out);
            } else {
                out.push(k.clone());
            }
        }
    }
}

/// A lowercase serde enum (certificate mode, family) from its name.
pub(crate) fn enum_from_str<T: serde::de::DeserializeOwned>(what: &str, s: &str, allowed: &str) -> PyResult<T> {
    serde_json::from_value(serde_json::Value::String(s.to_string()))
        .map_err(|_| PyValueError::new_err(format!("{what} must be one of {allowed}, got {s:?}")))
}
