//! Reading numbers from the kept JSON: a whole number may be written `3` or `3.0` (JSON has
//! one number type, and the validator accepts both), so indices and counts are read as either.

use serde_json::Value;

/// `v` as a whole, non-negative number.
pub(super) fn whole(v: &Value) -> Option<u64> {
    v.as_u64().or_else(|| {
        v.as_f64()
            .filter(|x| x.fract() == 0.0 && *x >= 0.0 && *x <= u64::MAX as f64)
            .map(|x| x as u64)
    })
}

/// A copy of `v` with every whole number written as a float turned into an integer, for the
/// typed `gltf` structures (whose indices are integers).
pub(super) fn with_whole_numbers(v: &Value) -> Value {
    match v {
        Value::Number(n) if n.as_u64().is_none() && n.as_i64().is_none() => match whole(v) {
            Some(i) => Value::from(i),
            None => v.clone(),
        },
        Value::Array(a) => Value::Array(a.iter().map(with_whole_numbers).collect()),
        Value::Object(o) => Value::Object(
            o.iter()
                .map(|(k, x)| (k.clone(), with_whole_numbers(x)))
                .collect(),
        ),
        _ => v.clone(),
    }
}
