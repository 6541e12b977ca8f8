//! The calibration band (MODEL.md#the-calibration-band): the sets of fitted wear constants the
//! field facts allow, and every wear answer re-evaluated under each of them on the same samples.
//!
//! One file per job: this one reads and checks a file of calibrated sets (the shipped one is
//! `data/calibration_band.toml`); [`fit`] finds the sets by history matching against the field
//! facts' targets and writes that file; [`evaluate`] re-evaluates a run's subsample under every
//! set, into rows that `analyze` turns into the band beside each sampling interval;
//! [`long_term`] runs `wear`'s loop again under chosen sets.

pub mod evaluate;
pub mod fit;
pub mod long_term;

use std::collections::BTreeSet;

use polywear_core::params::{ParamId, Params};
use polywear_core::wear::FittedConstants;
use polywear_core::wording::plain;

/// The shipped sets.
pub const SHIPPED: &str = include_str!("../../../../data/calibration_band.toml");
/// Their name in messages and metadata.
pub const SHIPPED_NAME: &str = "data/calibration_band.toml";

/// The most sets a file may hold: each costs a few order evaluations per wheel of the band's
/// subsample, and the band is their range, which 50 sets already resolve.
pub const MAX_SETS: usize = 200;

/// One calibrated set: the fitted constants, and what the fit found for it.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibratedSet {
    /// Its name in the band's rows.
    pub id: String,
    /// The set the shipped defaults are (exactly one per file).
    #[serde(default)]
    pub nominal: bool,
    /// φ_s.
    pub wear_share_straight: f64,
    /// σ_V \[km/h\].
    pub speed_spread_kmh: f64,
    /// k_d.
    pub wear_rate_driven_factor: f64,
    /// The fit's median distance of the highway followers \[km\] (informative).
    #[serde(default)]
    pub highway_median_km: Option<f64>,
    /// The fit's median distance of the default study's wheels \[km\] (informative).
    #[serde(default)]
    pub fleet_median_km: Option<f64>,
    /// The fit's share of 10–20 sides among the visible polygons (informative).
    #[serde(default)]
    pub sides_share: Option<f64>,
}

impl CalibratedSet {
    /// The constants.
    pub fn constants(&self) -> FittedConstants {
        FittedConstants {
            wear_share_straight: self.wear_share_straight,
            speed_spread_kmh: self.speed_spread_kmh,
            wear_rate_driven_factor: self.wear_rate_driven_factor,
        }
    }
}

/// A checked file of calibrated sets.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CalibrationBand {
    /// How the sets were found, named (for the report).
    pub method: String,
    /// The command that regenerates the file.
    pub generated_by: String,
    /// The sets, the nominal among them.
    #[serde(rename = "set")]
    pub sets: Vec<CalibratedSet>,
}

/// Why a file of calibrated sets is refused: the file, and the set and key where that applies.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{file}: {what}")]
pub struct BandError {
    /// The file named in the message.
    pub file: String,
    /// What is wrong.
    pub what: String,
}

impl CalibrationBand {
    /// The shipped sets (checked by the tests, so this cannot fail on a build that passed them).
    pub fn shipped() -> Self {
        Self::parse(SHIPPED, SHIPPED_NAME)
            .expect("the shipped calibration band is checked by tests")
    }

    /// Reads a file of sets. Refused: text that is not TOML of that shape, no set, more than
    /// [`MAX_SETS`], a repeated or malformed id, not exactly one nominal set, and a constant
    /// outside its parameter's accepted range (`polywear params`).
    pub fn parse(text: &str, file: &str) -> Result<Self, BandError> {
        let refuse = |what: String| BandError {
            file: file.to_string(),
            what,
        };
        if text.trim().is_empty() {
            return Err(refuse("empty file; accepted: TOML with `method`, `generated_by` and one `[[set]]` per calibrated set".into()));
        }
        let band: CalibrationBand =
            toml::from_str(text).map_err(|e| refuse(toml_refusal(text, &e)))?;
        for (key, value) in [
            ("method", &band.method),
            ("generated_by", &band.generated_by),
        ] {
            if let Some(why) = not_a_plain_line(value) {
                return Err(refuse(format!(
                    "`{key}` {why}; accepted: one line of printable text, at most {MAX_TEXT_CHARS} characters"
                )));
            }
        }
        if band.sets.is_empty() {
            return Err(refuse("no [[set]]: a band needs at least one".into()));
        }
        if band.sets.len() > MAX_SETS {
            return Err(refuse(format!(
                "{} sets; accepted at most {MAX_SETS}",
                band.sets.len()
            )));
        }
        let mut ids = BTreeSet::new();
        for (i, s) in band.sets.iter().enumerate() {
            let at = format!("set {} (`{}`)", i + 1, s.id);
            if s.id.is_empty()
                || !s
                    .id
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
            {
                return Err(refuse(format!(
                    "{at}: `id` must be non-empty letters, digits, `_`, `-` or `.`"
                )));
            }
            if s.id == evaluate::RUN_SET {
                return Err(refuse(format!(
                    "{at}: `id` = `{}` is reserved for the run's own constants in the band's rows; choose another id",
                    evaluate::RUN_SET
                )));
            }
            if !ids.insert(s.id.clone()) {
                return Err(refuse(format!("{at}: `id` repeats an earlier set's")));
            }
            for (id, v) in FittedConstants::PARAMS.iter().zip(s.constants().values()) {
                let spec = id.spec();
                if spec.check(v).is_err() {
                    return Err(refuse(format!(
                        "{at}: `{}` = {}: accepted {} ({})",
                        spec.name,
                        plain(v, 12),
                        spec.range_text(),
                        spec.unit
                    )));
                }
            }
        }
        let nominal = band.sets.iter().filter(|s| s.nominal).count();
        if nominal != 1 {
            return Err(refuse(format!(
                "{nominal} sets say `nominal = true`; accepted: exactly one"
            )));
        }
        Ok(band)
    }

    /// Refuses a band whose sets a scenario of `study` takes outside a parameter's accepted
    /// range: a scenario's changes are made to each set's constants as to the run's
    /// ([`evaluate::BandPlan`]), so `wear_share_straight = { scale = 5 }` takes a set at
    /// φ_s = 0.23 to 1.15, outside (0, 1], even where the run's own value stays inside. Named:
    /// the file, the scenario's key, the set and the range.
    pub fn check_scenarios(
        &self,
        study: &crate::study::Study,
        file: &str,
    ) -> Result<(), BandError> {
        for scenario in &study.scenarios {
            for change in &scenario.changes {
                let Some(k) = FittedConstants::PARAMS
                    .iter()
                    .position(|&id| id == change.param)
                else {
                    continue;
                };
                let spec = change.param.spec();
                let out: Vec<(&CalibratedSet, f64, f64)> = self
                    .sets
                    .iter()
                    .map(|set| {
                        let from = set.constants().values()[k];
                        (set, from, change.change.apply(from))
                    })
                    .filter(|(_, _, to)| spec.check(*to).is_err())
                    .collect();
                if let Some(&(set, from, to)) = out.first() {
                    return Err(BandError {
                        file: file.to_string(),
                        what: format!(
                            "{}: {} takes {} of the band's {} sets outside the accepted range {} of `{}` (set `{}` from {} to {}); change the scenario, or give another band (--calibration-band FILE or off)",
                            scenario.key(change.param),
                            change.words(),
                            out.len(),
                            self.sets.len(),
                            spec.range_text(),
                            spec.name,
                            set.id,
                            plain(from, 12),
                            plain(to, 12),
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// The nominal set.
    pub fn nominal(&self) -> &CalibratedSet {
        self.sets
            .iter()
            .find(|s| s.nominal)
            .expect("a checked band has one nominal set")
    }

    /// Whether `p`'s fitted constants are the nominal set's.
    pub fn nominal_is(&self, p: &Params) -> bool {
        self.nominal().constants() == FittedConstants::of(p)
    }

    /// Each constant's range over the sets ([`constant_ranges`]).
    pub fn ranges(&self) -> Vec<(ParamId, f64, f64)> {
        constant_ranges(&self.sets)
    }

    /// The file's text (TOML), with a header saying what it is.
    pub fn to_toml(&self) -> String {
        let text = |s: &str| serde_json::Value::String(s.to_string()).to_string();
        let mut body = format!(
            "method = {}\ngenerated_by = {}\n",
            text(&self.method),
            text(&self.generated_by)
        );
        for s in &self.sets {
            body.push_str(&format!(
                "\n[[set]]\nid = {}\nnominal = {}\nwear_share_straight = {}\nspeed_spread_kmh = {}\nwear_rate_driven_factor = {}\n",
                text(&s.id),
                s.nominal,
                toml_number(s.wear_share_straight),
                toml_number(s.speed_spread_kmh),
                toml_number(s.wear_rate_driven_factor)
            ));
            for (key, v) in [
                ("highway_median_km", s.highway_median_km),
                ("fleet_median_km", s.fleet_median_km),
                ("sides_share", s.sides_share),
            ] {
                if let Some(v) = v {
                    body.push_str(&format!("{key} = {}\n", toml_number(v)));
                }
            }
        }
        format!(
            "# The wear stage's calibrated sets: the fitted constants (phi_s, sigma_V, k_d) that meet\n\
             # every fitting target of data/field_facts.toml within its range (MODEL.md#the-calibration-band).\n\
             # explore re-evaluates its wear answer under each set on a subsample of the same samples\n\
             # and reports the range beside the sampling interval. Regenerate with `generated_by`.\n\n{body}"
        )
    }
}

/// The most characters of a band file's `method` and `generated_by`: what the report quotes
/// (a sentence, a command), never a document.
pub const MAX_TEXT_CHARS: usize = 400;

/// Why `text` is not one plain line for the report and the summary (a line break, a control
/// character, or more than [`MAX_TEXT_CHARS`]), or None.
fn not_a_plain_line(text: &str) -> Option<String> {
    let n = text.chars().count();
    if n > MAX_TEXT_CHARS {
        return Some(format!("holds {n} characters"));
    }
    if text.trim().is_empty() {
        return Some("is empty".into());
    }
    text.chars()
        .find(|c| c.is_control())
        .map(|c| format!("holds the control character {:?}", c))
}

/// A TOML error of a band file in words: where (line, and the `[[set]]` it falls in) and what.
fn toml_refusal(text: &str, e: &toml::de::Error) -> String {
    let what = e.message().trim_end().to_string();
    let Some(span) = e.span() else {
        return what;
    };
    let before = &text[..span.start.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let sets_before = before
        .lines()
        .filter(|l| l.trim_start().starts_with("[[set]]"))
        .count();
    if sets_before == 0 {
        format!("line {line}: {what}")
    } else {
        format!("line {line} (set {sets_before}): {what}")
    }
}

/// Each constant's (lowest, highest) over `sets`, in [`FittedConstants::PARAMS`] order.
pub fn constant_ranges(sets: &[CalibratedSet]) -> Vec<(ParamId, f64, f64)> {
    FittedConstants::PARAMS
        .iter()
        .enumerate()
        .map(|(k, &id)| {
            let v = sets.iter().map(|s| s.constants().values()[k]);
            let lo = v.clone().fold(f64::INFINITY, f64::min);
            let hi = v.fold(f64::NEG_INFINITY, f64::max);
            (id, lo, hi)
        })
        .collect()
}

/// A number as TOML writes it: `inf`, `-inf` and `nan` spelled as TOML spells them, and a
/// whole number with a decimal point so that it reads back as a float.
fn toml_number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else if x == x.trunc() && x.abs() < 1e15 {
        format!("{x:.1}")
    } else {
        plain_data(x)
    }
}

/// A TOML float: [`polywear_core::wording::data_number`] (exact, `1e300` not 301 digits).
fn plain_data(x: f64) -> String {
    polywear_core::wording::data_number(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_band_reads_and_holds_the_shipped_defaults_as_its_nominal() {
        let band = CalibrationBand::shipped();
        assert!(band.nominal_is(&Params::default()), "{:?}", band.nominal());
        assert!(band.sets.len() >= 2);
        let again = CalibrationBand::parse(&band.to_toml(), "again").unwrap();
        assert_eq!(again, band);
    }

    #[test]
    fn a_damaged_empty_or_out_of_range_file_is_refused_naming_file_key_and_range() {
        let err = |t: &str| CalibrationBand::parse(t, "c.toml").unwrap_err().to_string();
        assert!(err("").contains("c.toml: empty file"), "{}", err(""));
        assert!(err("method = [").starts_with("c.toml: "));
        let head = "method = \"m\"\ngenerated_by = \"g\"\n";
        assert!(
            err(head).contains("no [[set]]") || err(head).contains("missing field"),
            "{}",
            err(head)
        );
        let set = |extra: &str| {
            format!("{head}[[set]]\nid = \"a\"\nnominal = true\nwear_share_straight = 0.12\nspeed_spread_kmh = 5\nwear_rate_driven_factor = 1.75\n{extra}")
        };
        assert!(CalibrationBand::parse(&set(""), "c.toml").is_ok());
        let e = err(&set("").replace("0.12", "1.5"));
        assert!(
            e.contains("set 1 (`a`): `wear_share_straight` = 1.5: accepted (0, 1]"),
            "{e}"
        );
        let e = err(&set("").replace("speed_spread_kmh = 5", "speed_spread_kmh = -1"));
        assert!(e.contains("`speed_spread_kmh` = -1: accepted"), "{e}");
        let e = err(&set("").replace("nominal = true", "nominal = false"));
        assert!(e.contains("0 sets say `nominal = true`"), "{e}");
        let e = err(&set("bogus = 1\n"));
        assert!(e.contains("bogus"), "{e}");
        let two = format!(
            "{}{}",
            set(""),
            set("").replace(head, "").replace("nominal = true\n", "")
        );
        assert!(err(&two).contains("`id` repeats"), "{}", err(&two));
    }
}
