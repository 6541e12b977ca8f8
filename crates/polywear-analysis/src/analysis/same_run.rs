//! Whether two explore files belong to one run: every parameter value and stage setting their
//! footers record, compared key by key, and inside a JSON value field by field, so that a
//! refusal names the first that differs (`params.wear_share_straight`, `wear.zone`).

use super::footer::FileFooter;

/// Keys that differ between the files of one run: which shard and chunk a file is and the
/// command line that wrote it (a resume, a shard of a job array). The program version is not
/// among them: rows that two versions wrote are not one run's.
const PER_FILE_KEYS: [&str; 4] = ["shard", "chunk", "command", "ARROW:schema"];

/// Fields inside a value that differ between the files of one run: where the operating-point
/// file was found from the working directory of each shard.
const PER_FILE_FIELDS: [&str; 1] = ["operating_points.path"];

/// The first key (or field of a JSON value, `params.phi_s`) whose value differs between the two
/// footers, with both values (`(absent)` where one has none).
pub(super) fn first_difference(a: &FileFooter, b: &FileFooter) -> Option<(String, String, String)> {
    let mut keys: Vec<&str> = a.meta.iter().map(|(k, _)| k.as_str()).collect();
    for (k, _) in &b.meta {
        if !keys.contains(&k.as_str()) {
            keys.push(k);
        }
    }
    for key in keys.into_iter().filter(|k| !PER_FILE_KEYS.contains(k)) {
        match (a.value(key), b.value(key)) {
            (Some(x), Some(y)) if x == y => continue,
            (Some(x), Some(y)) => {
                let json = |t: &str| serde_json::from_str::<serde_json::Value>(t).ok();
                if let (Some(u), Some(v)) = (json(x), json(y)) {
                    if let Some(d) = json_difference(key.to_string(), &u, &v) {
                        return Some(d);
                    }
                    continue;
                }
                return Some((key.to_string(), x.to_string(), y.to_string()));
            }
            (x, y) => {
                let text = |v: Option<&str>| v.unwrap_or("(absent)").to_string();
                return Some((key.to_string(), text(x), text(y)));
            }
        }
    }
    None
}

/// The first field at or below `path` where `a` and `b` differ.
fn json_difference(
    path: String,
    a: &serde_json::Value,
    b: &serde_json::Value,
) -> Option<(String, String, String)> {
    use serde_json::Value;
    if PER_FILE_FIELDS.contains(&path.as_str()) || a == b {
        return None;
    }
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let absent = Value::String("(absent)".into());
            let mut keys: Vec<&String> = x.keys().collect();
            keys.extend(y.keys().filter(|k| !x.contains_key(*k)));
            keys.into_iter().find_map(|k| {
                json_difference(
                    format!("{path}.{k}"),
                    x.get(k).unwrap_or(&absent),
                    y.get(k).unwrap_or(&absent),
                )
            })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (u, v))| json_difference(format!("{path}[{i}]"), u, v)),
        _ => {
            let text = |v: &Value| match v {
                Value::String(s) => s.clone(),
                v => v.to_string(),
            };
            Some((path, text(a), text(b)))
        }
    }
}
