//! The run's identity as one serde type, [`RunManifest`]: explore writes it as the output
//! directory's `_manifest.json` and, with the chunk's own fields, as every chunk file's Parquet
//! key–value metadata (`key_value`); `--resume`, [`crate::explore::recorded_run`] and the
//! analysis read it back typed. The keys and values are those pandas/pyarrow users read
//! (docs/book/src/reference/output-files.md#output-files): text fields as text, numbers and lists as JSON.

use std::path::PathBuf;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::Shard;
use crate::key_value::{self, KeyValueError};
use crate::operating_points::OperatingPoints;
use polywear_core::evaluate::WearStage;
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::Design;
use polywear_core::wear::{Calibration, WearPower, WearSettings, WearZone, SHIPPED_LEVEL};

/// What a run is: written once into the manifest and into every chunk's footer. Fields that
/// only one of the two holds are `None` in the other (and then left out when written).
/// The declaration order is the order of the chunk footer's keys.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunManifest {
    /// The polywear version that wrote the run (`polywear_version`).
    pub polywear_version: String,
    /// The command line of the process that wrote a chunk (chunks only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub command: Option<String>,
    /// The random generator's name ([`polywear_core::sampling::RNG_NAME`]); None for runs of polywear
    /// before 0.2.0, which did not record it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rng: Option<String>,
    /// The study's `name`.
    #[serde(default)]
    pub study_name: String,
    /// The study file's text (the manifest only: chunks carry its hash).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study: Option<String>,
    /// Fingerprint of the study text ([`crate::study::text_hash`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub study_hash: Option<String>,
    /// The seed of the random streams.
    pub seed: u64,
    /// Samples of the whole run (all shards).
    pub samples: u64,
    /// The sampling design (chunks only).
    #[serde(default, skip_serializing_if = "Option::is_none", with = "opt_text")]
    pub design: Option<Design>,
    /// The friction variants, in the order of the rows (chunks only; `variant`, comma-separated).
    #[serde(
        rename = "variant",
        default,
        skip_serializing_if = "Option::is_none",
        with = "variant_list"
    )]
    pub variants: Option<Vec<Variant>>,
    /// The chunk's global index (chunks only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chunk: Option<u64>,
    /// Names of the drawn values, in column order (chunks only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drawn_names: Option<Vec<ParamId>>,
    /// Samples per chunk file.
    #[serde(default)]
    pub chunk_size: u64,
    /// The shard that wrote the run.
    #[serde(default = "whole", with = "shard_text")]
    pub shard: Shard,
    /// Every parameter's value before the draws (defaults, a parameter file and the study's
    /// fixed values).
    #[serde(default, with = "params_map")]
    pub params: Params,
    /// The drawn parameters' distributions, in the study file's terms (chunks only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drawn: Option<serde_json::Value>,
    /// The study's operating-point file, when it has one (`null` in the manifest otherwise).
    #[serde(default)]
    pub operating_points: Option<OperatingPointsRecord>,
    /// Name of the journal of finished chunks (the manifest only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chunks: Option<String>,
    /// How the journal's checksums are computed (the manifest only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checksum: Option<String>,
    /// What a row is (chunks only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<String>,
    /// The study's scenarios, in the order of each sample's row blocks after the baseline's, in
    /// the study file's terms (chunks of a study with scenarios only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scenarios: Option<serde_json::Value>,
    /// The wear stage (its zone and calibration), when the run has one; absent for a run
    /// without wear columns (`--no-wear`, `wear = false`, and runs of polywear before 0.6.0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wear: Option<WearRecord>,
}

/// The wear stage as a run records it (`wear` in the manifest and in every chunk's footer):
/// the answer's name, where and which friction power wore the tread, and the calibration of γ.
/// Read once, here, with one default for each thing older runs did not record: a run from
/// before the answer had a name answered as the new tire (`new_tire`, a retired level), one
/// from before the slip power counted wore by the lateral power alone (`lateral_only`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct WearRecord {
    /// The wear answer's name (`wear_estimate`): the one polywear gives, or a retired one.
    #[serde(default = "WearRecord::unnamed_level")]
    pub wear_estimate: String,
    /// Where the friction power wore the tread.
    pub wear_zone: WearZone,
    /// Which friction power wore it.
    #[serde(default = "WearRecord::before_slip_power")]
    pub wear_power: WearPower,
    /// The calibration of γ on the run's reference follower.
    pub calibration: Calibration,
}

impl WearRecord {
    /// The record of a run's wear stage.
    pub fn of(stage: &WearStage) -> Self {
        WearRecord {
            wear_estimate: SHIPPED_LEVEL.to_string(),
            wear_zone: stage.settings.zone,
            wear_power: stage.settings.power,
            calibration: stage.calibration,
        }
    }

    /// The settings it records.
    pub fn settings(&self) -> WearSettings {
        WearSettings {
            zone: self.wear_zone,
            power: self.wear_power,
        }
    }

    fn unnamed_level() -> String {
        "new_tire".into()
    }

    fn before_slip_power() -> WearPower {
        WearPower::LateralOnly
    }
}

/// Written as one JSON object with its keys sorted (the calibration's too), as every run has
/// written it.
impl Serialize for WearRecord {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serde_json::json!({
            "calibration": self.calibration,
            "wear_estimate": self.wear_estimate,
            "wear_power": self.wear_power,
            "wear_zone": self.wear_zone,
        })
        .serialize(s)
    }
}

/// An operating-point file as the run recorded it. Fields in alphabetical order, as the
/// recorded JSON object has them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OperatingPointsRecord {
    /// Size of the file \[bytes\].
    pub bytes: u64,
    /// The file's parameter columns.
    pub columns: Vec<String>,
    /// How a sample draws its row.
    pub draw: String,
    /// The file as the study names it.
    pub file: String,
    /// Hash of the file's bytes.
    pub hash: String,
    /// Which hash.
    pub hash_kind: String,
    /// The file as read (absolute).
    pub path: String,
    /// The columns passed through to the output (`pass_through`; empty where the run recorded none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pass_through: Vec<String>,
    /// Rows of the file.
    pub rows: u64,
    /// The weight column, if any.
    pub weight: Option<String>,
    /// How the weight is computed where the file has no such column (`hours * speed_kmh`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weight_computed: Option<String>,
    /// What the weight measures: `time`, `distance`, `equal` or `other` (None where the run did not record it).
    #[serde(default)]
    pub weight_kind: Option<String>,
}

impl OperatingPointsRecord {
    /// The record of a loaded operating-point file.
    pub fn of(op: &OperatingPoints) -> OperatingPointsRecord {
        serde_json::from_value(op.to_json()).expect("the record's own fields")
    }

    /// The folder a relative file was found in: `path` less the `file` the study gives, where
    /// the recorded study finds its file again.
    pub fn dir(&self) -> Option<PathBuf> {
        self.path.strip_suffix(&self.file).map(PathBuf::from)
    }
}

/// Why a manifest or a chunk footer cannot be read as a [`RunManifest`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ManifestError {
    /// The manifest is not JSON of a run manifest.
    #[error("unreadable: {0}")]
    Json(String),
    /// The footer's key–value metadata is not a run's.
    #[error("{0}")]
    KeyValue(#[from] KeyValueError),
}

impl RunManifest {
    /// The manifest file's text: pretty JSON with sorted keys.
    pub fn to_json_text(&self) -> String {
        let value = serde_json::to_value(self).expect("a manifest is JSON");
        serde_json::to_string_pretty(&value).expect("JSON")
    }

    /// The manifest as a JSON value (for messages that show recorded values as JSON).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("a manifest is JSON")
    }

    /// Reads a manifest file's text.
    pub fn from_json_text(text: &str) -> Result<RunManifest, ManifestError> {
        serde_json::from_str(text).map_err(|e| ManifestError::Json(e.to_string()))
    }

    /// The chunk footer's key–value metadata.
    pub fn to_key_values(&self) -> Vec<(String, String)> {
        key_value::to_key_values(self).expect("a manifest is a struct")
    }

    /// Reads a chunk footer's key–value metadata (other keys, such as `units`, are ignored).
    pub fn from_key_values(pairs: &[(String, String)]) -> Result<RunManifest, ManifestError> {
        Ok(key_value::from_key_values(pairs)?)
    }

    /// The variants as written (`paper,combined`), or "" when none are recorded.
    pub fn variant_text(&self) -> String {
        self.variants
            .as_deref()
            .map(variant_list::text)
            .unwrap_or_default()
    }
}

fn whole() -> Shard {
    Shard::WHOLE
}

/// `Option<T>` as its `Display` text and back through `FromStr`.
mod opt_text {
    use super::*;

    pub fn serialize<T: std::fmt::Display, S: Serializer>(
        v: &Option<T>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.collect_str(v),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, T, D>(d: D) -> Result<Option<T>, D::Error>
    where
        T: std::str::FromStr,
        T::Err: std::fmt::Display,
        D: Deserializer<'de>,
    {
        Option::<String>::deserialize(d)?
            .map(|s| s.parse().map_err(serde::de::Error::custom))
            .transpose()
    }
}

/// Variants as one comma-separated text, `paper,combined`.
mod variant_list {
    use super::*;

    pub fn text(v: &[Variant]) -> String {
        v.iter().map(|v| v.as_str()).collect::<Vec<_>>().join(",")
    }

    pub fn serialize<S: Serializer>(v: &Option<Vec<Variant>>, s: S) -> Result<S::Ok, S::Error> {
        match v {
            Some(v) => s.serialize_str(&text(v)),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<Variant>>, D::Error> {
        Option::<String>::deserialize(d)?
            .map(|s| {
                s.split(',')
                    .map(|v| v.parse::<Variant>().map_err(serde::de::Error::custom))
                    .collect()
            })
            .transpose()
    }
}

/// A shard as `k/N`.
mod shard_text {
    use super::*;

    pub fn serialize<S: Serializer>(v: &Shard, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(v)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Shard, D::Error> {
        let s = String::deserialize(d)?;
        s.split_once('/')
            .and_then(|(k, n)| Shard::new(k.parse().ok()?, n.parse().ok()?))
            .ok_or_else(|| serde::de::Error::custom(format!("`shard` {s:?} is not k/N")))
    }
}

/// Parameters as an object of every parameter's value, read back by name.
mod params_map {
    use super::*;

    pub fn serialize<S: Serializer>(v: &Params, s: S) -> Result<S::Ok, S::Error> {
        v.serialize(s)
    }

    /// Every number by name, and the drivetrain by its name (`fwd` for a run written before
    /// polywear knew the car: its pair was a front-wheel-drive car's).
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Params, D::Error> {
        let values = std::collections::BTreeMap::<String, serde_json::Value>::deserialize(d)?;
        let mut params = Params::default();
        let bad = |e: String| serde::de::Error::custom(format!("`params`: {e}"));
        for (name, value) in &values {
            if name == "drivetrain" {
                params.drivetrain = serde_json::from_value(value.clone())
                    .map_err(|e| bad(format!("`drivetrain`: {e}")))?;
                continue;
            }
            let x = value
                .as_f64()
                .ok_or_else(|| bad(format!("`{name}` = {value} is not a number")))?;
            params.set(name, x).map_err(|e| bad(e.to_string()))?;
        }
        Ok(params)
    }
}

#[cfg(test)]
mod tests {
    use super::WearRecord;
    use polywear_core::classify::Class;
    use polywear_core::evaluate::WearStage;
    use polywear_core::wear::{Calibration, WearPower, WearSettings, WearZone};

    fn stage(zone: WearZone, power: WearPower) -> WearStage {
        WearStage {
            settings: WearSettings { zone, power },
            calibration: Calibration {
                reference_power_w: 37.10074758977802,
                reference_band_m3_per_s: 7.427143934209326,
                reference_class: Class::LimitCycle,
                gamma_m3_per_j: 2.882714759151682e-12,
            },
        }
    }

    /// The typed record is written as the stage always was (the same JSON text, keys sorted,
    /// as every manifest and chunk footer has it), and reads back to itself; a record of a run
    /// from before the answer had a name, or before the slip power counted, reads with the one
    /// default for each: the new tire's (retired) level, the lateral power alone.
    #[test]
    fn the_wear_record_is_written_as_the_stage_and_read_with_one_default() {
        for (zone, power) in [
            (WearZone::Trailing, WearPower::WithSlip),
            (WearZone::WholePatch, WearPower::LateralOnly),
        ] {
            let stage = stage(zone, power);
            let record = WearRecord::of(&stage);
            let text = serde_json::to_string(&record).unwrap();
            assert_eq!(text, serde_json::to_value(stage).unwrap().to_string());
            let back: WearRecord = serde_json::from_str(&text).unwrap();
            assert_eq!(back, record);
            assert_eq!(back.settings(), stage.settings);
        }
        let old = r#"{"calibration":{"gamma_m3_per_j":2.882714759151682e-12,"reference_band_m3_per_s":7.427143934209326,"reference_class":"limit_cycle","reference_power_w":37.10074758977802},"wear_zone":"trailing"}"#;
        let old: WearRecord = serde_json::from_str(old).unwrap();
        assert_eq!(old.wear_estimate, "new_tire");
        assert_eq!(old.wear_power, WearPower::LateralOnly);
    }

    /// What the manifest records reads back bit for bit: serde_json parses floats exactly only
    /// with its `float_roundtrip` feature, without which γ = 2.882714759151682e-12 (the shipped
    /// calibration) read back one ulp off and `--resume` refused its own run.
    #[test]
    fn recorded_floats_read_back_bit_for_bit() {
        let mut x = 2.882714759151682e-12_f64;
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..20_000 {
            let text = serde_json::to_string(&x).unwrap();
            let back: f64 = serde_json::from_str(&text).unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{text}");
            // The next value: random bits of a finite double.
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            x = f64::from_bits(state >> 2);
        }
    }
}
