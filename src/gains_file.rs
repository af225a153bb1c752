//! Gains a user brings (`sporadic verify --gains FILE.json`, `sporadic.verify` in Python): the
//! `gains` (and `certificate`) of a design report, edited or designed elsewhere, read from JSON.

use sporadic_model::{Gain, GainSchedule, NamedMatrix};

/// What is wrong with a gains JSON text.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct GainsFileError(pub String);

/// A gain or certificate matrix of a gains JSON: `name` and `rows` (other fields optional).
fn named_rows(
    v: &serde_json::Value,
    what: &str,
    k: usize,
) -> Result<(String, Vec<Vec<f64>>), String> {
    let name = v
        .get("name")
        .and_then(|n| n.as_str())
        .ok_or_else(|| format!("{what} {k} has no string field \"name\""))?;
    let rows: Vec<Vec<f64>> = v
        .get("rows")
        .cloned()
        .ok_or_else(|| format!("{what} {name} has no field \"rows\""))
        .and_then(|r| {
            serde_json::from_value(r).map_err(|e| {
                format!("{what} {name}: \"rows\" must be an array of rows of numbers: {e}")
            })
        })?;
    let width = rows.first().map_or(0, Vec::len);
    if rows.is_empty() || width == 0 || rows.iter().any(|r| r.len() != width) {
        return Err(format!(
            "{what} {name}: \"rows\" must be a non-empty rectangular matrix"
        ));
    }
    if rows.iter().flatten().any(|x| !x.is_finite()) {
        return Err(format!(
            "{what} {name} has an entry that is not a finite number"
        ));
    }
    Ok((name.to_string(), rows))
}

/// The gains (and certificate, if any) of a gains JSON text (`sporadic verify --gains
/// FILE.json`, `sporadic.verify` in Python): a design report (its `gains` and `certificate`),
/// an object `{"gains": [...], "certificate": [...]}` or an array of gains; each entry
/// `{"name", "rows"}` with a finite rectangular `rows`, optional `meaning` and (gains)
/// `schedule`.
///
/// # Errors
/// [`GainsFileError`] naming the entry and what is wrong with it.
pub fn parse_gains(text: &str) -> Result<(Vec<Gain>, Vec<NamedMatrix>), GainsFileError> {
    parse(text).map_err(GainsFileError)
}

fn parse(text: &str) -> Result<(Vec<Gain>, Vec<NamedMatrix>), String> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let (gains, certificate) = match &value {
        serde_json::Value::Array(_) => (value.clone(), serde_json::Value::Null),
        serde_json::Value::Object(o) => (
            o.get("gains")
                .cloned()
                .ok_or("the object has no \"gains\" array")?,
            o.get("certificate")
                .cloned()
                .unwrap_or(serde_json::Value::Null),
        ),
        _ => {
            return Err("expected a design report, {\"gains\": [...]} or an array of gains".into());
        }
    };
    let gains = gains
        .as_array()
        .ok_or("\"gains\" must be an array")?
        .iter()
        .enumerate()
        .map(|(k, g)| {
            let (name, rows) = named_rows(g, "gain", k)?;
            let schedule = match g.get("schedule") {
                None | Some(serde_json::Value::Null) => None,
                Some(s) => Some(
                    serde_json::from_value::<GainSchedule>(s.clone())
                        .map_err(|e| format!("gain {name}: bad \"schedule\": {e}"))?,
                ),
            };
            Ok(Gain {
                meaning: g
                    .get("meaning")
                    .and_then(|m| m.as_str())
                    .unwrap_or("given by the user")
                    .to_string(),
                name,
                rows,
                schedule,
            })
        })
        .collect::<Result<Vec<_>, String>>()?;
    if gains.is_empty() {
        return Err("no gains given".into());
    }
    let certificate = match certificate {
        serde_json::Value::Null => Vec::new(),
        serde_json::Value::Array(items) => items
            .iter()
            .enumerate()
            .map(|(k, m)| {
                let (name, rows) = named_rows(m, "certificate matrix", k)?;
                Ok(NamedMatrix {
                    meaning: m
                        .get("meaning")
                        .and_then(|x| x.as_str())
                        .unwrap_or("given by the user")
                        .to_string(),
                    name,
                    rows,
                })
            })
            .collect::<Result<Vec<_>, String>>()?,
        _ => return Err("\"certificate\" must be an array".into()),
    };
    Ok((gains, certificate))
}
