//! The calibration band (MODEL.md#the-calibration-band): how far each wear figure moves across
//! the calibrated sets of fitted constants, beside its sampling interval.
//!
//! explore re-evaluates a subsample of the run under every set and under the run's own
//! constants (set `run`), on the same samples (`calibration_band.parquet`). A figure's band is
//! the full run's figure moved by each set's difference from `run` on the subsample (a control
//! variate: the subsample's sampling error cancels in the difference), its range over the sets.
//! Which wheel is more exposed is said only where the sign holds under every set.

use std::path::{Path, PathBuf};

use super::footer::FileFooter;
use super::rows::{band_counts, BandCount, OutcomeColumn};
use super::scenarios::ScenarioEffect;
use super::wear_risk::{sample_weight, WearAnalysis};
use super::{AnalysisError, RunInfo};
use polywear_core::model::{Variant, Wheel};
use polywear_core::wording::{one_line, plain};
use polywear_study::calibration_band::evaluate::{
    band_state, set_column, BandState, BAND_DIGEST, BAND_FILE, RUN_SET,
};
use polywear_study::calibration_band::{constant_ranges, CalibratedSet, MAX_TEXT_CHARS};
use polywear_study::study::BASELINE;

/// The range of a figure over the calibrated sets.
#[derive(Debug, Clone, PartialEq)]
pub struct BandRange {
    /// The lowest value (a probability or a difference of two, as a share).
    pub lo: f64,
    /// The set that gives it.
    pub lo_set: String,
    /// The highest value.
    pub hi: f64,
    /// The set that gives it.
    pub hi_set: String,
}

/// The band of P(visible polygon within a distance) of one wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct OccurrenceBand {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The distance \[km\].
    pub within_km: f64,
    /// The range.
    pub range: BandRange,
}

/// Follower against driving wheel across the sets.
#[derive(Debug, Clone, PartialEq)]
pub struct PairedBand {
    /// The friction variant.
    pub variant: Variant,
    /// The distance \[km\].
    pub within_km: f64,
    /// P(follower) − P(driving) over the sets.
    pub follower_minus_driving: BandRange,
    /// Sets under which the follower is more exposed.
    pub follower_ahead: usize,
    /// Sets under which the driving wheel is.
    pub driving_ahead: usize,
}

impl PairedBand {
    /// The wheel more exposed under every set, or None where the sign changes across the band.
    pub fn holds(&self) -> Option<Wheel> {
        let r = &self.follower_minus_driving;
        if r.lo > 0.0 {
            Some(Wheel::Follower)
        } else if r.hi < 0.0 {
            Some(Wheel::Driving)
        } else {
            None
        }
    }
}

/// A scenario's effect (scenario minus its reference) across the sets.
#[derive(Debug, Clone, PartialEq)]
pub struct EffectBand {
    /// The scenario.
    pub scenario: String,
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// The distance of the wear outcome compared \[km\].
    pub within_km: f64,
    /// The range of the difference.
    pub range: BandRange,
}

/// The band of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationBand {
    /// The band's file.
    pub file: PathBuf,
    /// Where the sets come from.
    pub source: String,
    /// How they were found.
    pub method: String,
    /// Where the calibration's accepted region lies, in one sentence (empty for a band that
    /// recorded none).
    pub region: String,
    /// The sets.
    pub sets: Vec<CalibratedSet>,
    /// Samples of the subsample.
    pub samples: u64,
    /// The headline per wheel at each distance.
    pub occurrence: Vec<OccurrenceBand>,
    /// Follower against driving wheel at each distance.
    pub paired: Vec<PairedBand>,
    /// Each scenario's wear effect at the scenarios' distance.
    pub scenarios: Vec<EffectBand>,
}

impl CalibrationBand {
    /// The band of `variant`, `wheel` at `within_km`.
    pub fn occurrence_of(
        &self,
        variant: Variant,
        wheel: Wheel,
        within_km: f64,
    ) -> Option<&BandRange> {
        self.occurrence
            .iter()
            .find(|o| (o.variant, o.wheel, o.within_km) == (variant, wheel, within_km))
            .map(|o| &o.range)
    }

    /// The band of a scenario's effect on the wear outcome (None for its vibration effect,
    /// which the fitted wear constants do not move).
    pub fn effect_of(&self, e: &ScenarioEffect) -> Option<&BandRange> {
        let OutcomeColumn::WithinKm { km, .. } = e.outcome else {
            return None;
        };
        self.scenarios
            .iter()
            .find(|b| {
                (b.scenario.as_str(), b.variant, b.wheel, b.within_km)
                    == (e.scenario.as_str(), e.variant, e.wheel, km)
            })
            .map(|b| &b.range)
    }

    /// The paired band of `variant` at `within_km`.
    pub fn paired_of(&self, variant: Variant, within_km: f64) -> Option<&PairedBand> {
        self.paired
            .iter()
            .find(|p| (p.variant, p.within_km) == (variant, within_km))
    }

    /// Each constant's range over the sets, in words: "phi_s 0.05–0.23, sigma_V 2–10 km/h,
    /// k_d 1.5–2".
    pub fn constants_words(&self) -> String {
        constant_ranges(&self.sets)
            .iter()
            .map(|&(id, lo, hi)| {
                let spec = id.spec();
                let range = if lo == hi {
                    plain(lo, 6)
                } else {
                    format!("{}–{}", plain(lo, 6), plain(hi, 6))
                };
                let unit = if spec.unit == "-" {
                    String::new()
                } else {
                    format!(" {}", spec.unit)
                };
                format!("{} {range}{unit}", spec.symbol)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The band file of the run: [`BAND_FILE`] in the first directory of its chunk files that
/// holds a band or its digest, verified against the digest and checked to be of this run (every
/// setting the run's footer records: study, seed, samples, design, variants, parameters, the
/// wear stage and its level, the version); None where the run has none. A band asked for and
/// not finished, a band that changed, or one of another run is refused with what to do.
pub(super) fn band_file(info: &RunInfo) -> Result<Option<FileFooter>, AnalysisError> {
    let Some(dir) = info
        .files
        .iter()
        .filter_map(|f| f.parent())
        .find(|d| band_state(d) != BandState::Absent)
        .map(Path::to_path_buf)
    else {
        return Ok(None);
    };
    let path = dir.join(BAND_FILE);
    let resume = format!("polywear explore --resume --out {}", dir.display());
    let refuse = |why: String| {
        AnalysisError::Band {
        path: path.clone(),
        message: format!(
            "the calibration band cannot be used: {why}; write it again with `{resume}` (it keeps the chunks), or remove it"
        ),
    }
    };
    match band_state(&dir) {
        BandState::Verified => {}
        BandState::Pending => {
            return Err(AnalysisError::Band {
                path: dir.join(BAND_DIGEST),
                message: format!(
                    "the run's calibration band was asked for and is not finished (the run stopped before or during its band pass); finish it with `{resume}` (it keeps the chunks)"
                ),
            })
        }
        BandState::Refused(why) => return Err(refuse(why)),
        BandState::Absent => unreachable!("a directory with a band was found"),
    }
    let footer = FileFooter::read(&path).map_err(|e| refuse(e.to_string()))?;
    if !footer.has_column(&set_column(RUN_SET)) {
        return Err(AnalysisError::Band {
            path,
            message: format!(
                "the calibration band is in the format of an older polywear (a row per set, no column `{}`); write it again with `{resume}`, or remove it",
                set_column(RUN_SET)
            ),
        });
    }
    let rows_footer = FileFooter::read(&info.files[0])?;
    for key in RUN_IDENTITY_KEYS {
        let (theirs, ours) = (footer.value(key), rows_footer.value(key));
        if theirs != ours {
            let (key, theirs, ours) = first_difference(key, theirs, ours);
            let shown = |v: Option<String>| v.map_or("none".to_string(), |v| snippet_long(&v));
            return Err(AnalysisError::Band {
                path,
                message: format!(
                    "the calibration band belongs to another run: its `{key}` is {}, the rows' {}; remove it, or rerun explore",
                    shown(theirs),
                    shown(ours)
                ),
            });
        }
    }
    Ok(Some(footer))
}

/// Where two recorded values of `key` differ: for JSON objects the first field that does
/// (`wear.wear_estimate`), else the values themselves.
fn first_difference(
    key: &str,
    a: Option<&str>,
    b: Option<&str>,
) -> (String, Option<String>, Option<String>) {
    let json = |v: Option<&str>| v.and_then(|t| serde_json::from_str::<serde_json::Value>(t).ok());
    if let (Some(serde_json::Value::Object(x)), Some(serde_json::Value::Object(y))) =
        (json(a), json(b))
    {
        let fields: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
        for f in fields {
            if x.get(f) != y.get(f) {
                let text = |v: Option<&serde_json::Value>| {
                    v.map(|v| v.as_str().map_or(v.to_string(), str::to_string))
                };
                return (format!("{key}.{f}"), text(x.get(f)), text(y.get(f)));
            }
        }
    }
    (
        key.to_string(),
        a.map(str::to_string),
        b.map(str::to_string),
    )
}

/// The footer keys that say which run a band is of: a band evaluated under any other value of
/// one of them (another wear level, another parameter set) answers another question.
const RUN_IDENTITY_KEYS: [&str; 11] = [
    "polywear_version",
    "study_name",
    "study_hash",
    "seed",
    "samples",
    "design",
    "variant",
    "params",
    "wear",
    "operating_points",
    "scenarios",
];

/// A recorded value as a message quotes it: at most 80 characters, escaped.
fn snippet_long(v: &str) -> String {
    let cut = v.chars().count() > 80;
    let head: String = v.chars().take(80).collect();
    format!("`{}{}`", head.escape_debug(), if cut { "…" } else { "" })
}

/// The full run's probability `full` moved under each set of `ids` by that set's difference
/// from the run's own constants on the subsample (`of`, [`RUN_SET`] the run's), kept within
/// [0, 1].
fn moved_under_sets<'a>(
    ids: &[&'a str],
    full: f64,
    of: &dyn Fn(&str) -> f64,
) -> Vec<(f64, &'a str)> {
    let base = of(RUN_SET);
    ids.iter()
        .map(|id| ((full + of(id) - base).clamp(0.0, 1.0), *id))
        .collect()
}

/// P(a) − P(b) under each set of `ids` (the follower's against the driving wheel's, a scenario's
/// against its reference's): each full-run probability (`full`, a's then b's) moved as its
/// occurrence band moves it, within [0, 1], then their difference. Moving the difference itself
/// would call a tie of two figures near zero a lead where one moved figure fell below 0 (over
/// the tread's life, where the driving wheel has none, 18 of the 96 shipped sets were said to
/// favour it).
fn difference_under_sets<'a>(
    ids: &[&'a str],
    (a, b): (f64, f64),
    of_a: &dyn Fn(&str) -> f64,
    of_b: &dyn Fn(&str) -> f64,
) -> Vec<(f64, &'a str)> {
    moved_under_sets(ids, a, of_a)
        .into_iter()
        .zip(moved_under_sets(ids, b, of_b))
        .map(|((x, id), (y, _))| (x - y, id))
        .collect()
}

/// The band of a run whose inputs hold a band file, for the wear answer `wear` and the
/// scenarios' effects `effects` (those on the wear outcome get a band).
pub(super) fn band(
    footer: &FileFooter,
    info: &RunInfo,
    wear: &WearAnalysis,
    effects: &[ScenarioEffect],
    scenario_within_km: f64,
) -> Result<CalibrationBand, AnalysisError> {
    let path = footer.path.clone();
    let meta = |key: &str| {
        footer
            .value(key)
            .map(str::to_string)
            .ok_or_else(|| AnalysisError::Metadata {
                path: path.clone(),
                message: format!("no `{key}` recorded"),
            })
    };
    let sets: Vec<CalibratedSet> =
        serde_json::from_str(&meta("band_sets")?).map_err(|e| AnalysisError::Metadata {
            path: path.clone(),
            message: format!("`band_sets`: {e}"),
        })?;
    let samples: u64 = meta("band_samples")?
        .parse()
        .map_err(|e| AnalysisError::Metadata {
            path: path.clone(),
            message: format!("`band_samples`: {e}"),
        })?;
    let mut within = wear.within_km();
    if !within.contains(&scenario_within_km) {
        within.push(scenario_within_km);
    }
    let set_ids: Vec<&str> = std::iter::once(RUN_SET)
        .chain(sets.iter().map(|s| s.id.as_str()))
        .collect();
    let counts = band_counts(&path, &within, sample_weight(info), &set_ids)?;
    let ids: Vec<&str> = sets.iter().map(|s| s.id.as_str()).collect();
    let occurrence = occurrence_bands(wear, &counts, &within, &ids);
    let paired = paired_bands(wear, &counts, &within, &ids);
    let k = within
        .iter()
        .position(|x| *x == scenario_within_km)
        .expect("asked");
    let scenarios = scenario_effect_bands(effects, &counts, k, scenario_within_km, &ids);
    Ok(CalibrationBand {
        file: path.clone(),
        // What a file says of itself is quoted as one bounded line (a band file's `method`
        // is checked so when explore reads it; a footer is taken as it is found).
        source: one_line(&meta("band_source")?, MAX_TEXT_CHARS),
        method: one_line(&meta("band_method")?, MAX_TEXT_CHARS),
        region: one_line(footer.value("band_region").unwrap_or(""), MAX_TEXT_CHARS),
        sets,
        samples,
        occurrence,
        paired,
        scenarios,
    })
}

/// The share of the known samples of `scenario`, `variant`, `wheel` under the set `set` that
/// show a visible polygon within the `k`-th distance of the band counts; NaN where there is no
/// such count or it knows no sample.
fn visible_share(
    counts: &[BandCount],
    scenario: &str,
    variant: Variant,
    wheel: Wheel,
    set: &str,
    k: usize,
) -> f64 {
    counts
        .iter()
        .find(|c| {
            (c.scenario.as_str(), c.variant, c.wheel, c.set.as_str())
                == (scenario, variant, wheel, set)
        })
        .map_or(f64::NAN, |c: &BandCount| {
            if c.known > 0 {
                c.visible[k] as f64 / c.known as f64
            } else {
                f64::NAN
            }
        })
}

/// The range of figures under the sets, and the sets at its ends: None where the full run's
/// figure `full` or every moved figure is not finite.
fn range_over_sets(full: f64, mut moved: Vec<(f64, &str)>) -> Option<BandRange> {
    moved.retain(|(x, _)| x.is_finite());
    if moved.is_empty() || !full.is_finite() {
        return None;
    }
    moved.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (first, last) = (moved[0], moved[moved.len() - 1]);
    Some(BandRange {
        lo: first.0,
        lo_set: first.1.to_string(),
        hi: last.0,
        hi_set: last.1.to_string(),
    })
}

/// The band of the headline P(visible polygon within a distance) of each wheel at each of the
/// wear answer's distances, on the baseline.
fn occurrence_bands(
    wear: &WearAnalysis,
    counts: &[BandCount],
    within: &[f64],
    ids: &[&str],
) -> Vec<OccurrenceBand> {
    let mut occurrence = Vec::new();
    for (km, o) in wear.occurrence_rows() {
        let k = within.iter().position(|x| *x == km).expect("asked");
        let of = |set: &str| visible_share(counts, BASELINE, o.variant, o.wheel, set, k);
        if let Some(r) = range_over_sets(o.p(), moved_under_sets(ids, o.p(), &of)) {
            occurrence.push(OccurrenceBand {
                variant: o.variant,
                wheel: o.wheel,
                within_km: km,
                range: r,
            });
        }
    }
    occurrence
}

/// The band of follower against driving wheel at each of the wear answer's distances, on the
/// baseline, with how many sets put each wheel ahead.
fn paired_bands(
    wear: &WearAnalysis,
    counts: &[BandCount],
    within: &[f64],
    ids: &[&str],
) -> Vec<PairedBand> {
    let mut paired = Vec::new();
    for (km, pr) in wear.paired_rows() {
        let k = within.iter().position(|x| *x == km).expect("asked");
        let v = pr.variant;
        let Some(answer) = wear.by_distance.iter().find(|d| d.within_km == km) else {
            continue;
        };
        let at = |wheel| answer.answer.occurrence_of(v, wheel);
        let (f, d) = match (at(Wheel::Follower), at(Wheel::Driving)) {
            (Some(f), Some(d)) => (f.p(), d.p()),
            _ => continue,
        };
        let of = |wheel: Wheel| move |set: &str| visible_share(counts, BASELINE, v, wheel, set, k);
        let differences =
            difference_under_sets(ids, (f, d), &of(Wheel::Follower), &of(Wheel::Driving));
        let ahead = |sign: f64| differences.iter().filter(|(x, _)| x * sign > 0.0).count();
        let (follower_ahead, driving_ahead) = (ahead(1.0), ahead(-1.0));
        if let Some(r) = range_over_sets(f - d, differences) {
            paired.push(PairedBand {
                variant: v,
                within_km: km,
                follower_minus_driving: r,
                follower_ahead,
                driving_ahead,
            });
        }
    }
    paired
}

/// The band of each scenario's effect on the wear outcome at the scenarios' distance
/// `scenario_within_km` (the `k`-th of the band counts); effects on other outcomes have none.
fn scenario_effect_bands(
    effects: &[ScenarioEffect],
    counts: &[BandCount],
    k: usize,
    scenario_within_km: f64,
    ids: &[&str],
) -> Vec<EffectBand> {
    let mut scenarios = Vec::new();
    for e in effects {
        if !matches!(e.outcome, OutcomeColumn::WithinKm { km, .. } if km == scenario_within_km) {
            continue;
        }
        let under_scenario =
            |set: &str| visible_share(counts, &e.scenario, e.variant, e.wheel, set, k);
        let under_reference =
            |set: &str| visible_share(counts, &e.reference, e.variant, e.wheel, set, k);
        let differences = difference_under_sets(
            ids,
            (e.p_scenario(), e.p_baseline()),
            &under_scenario,
            &under_reference,
        );
        if let Some(r) = range_over_sets(e.difference(), differences) {
            scenarios.push(EffectBand {
                scenario: e.scenario.clone(),
                variant: e.variant,
                wheel: e.wheel,
                within_km: scenario_within_km,
                range: r,
            });
        }
    }
    scenarios
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two figures near zero: under a set where the follower's moved figure would fall below
    /// zero and the driving wheel has none, the wheels tie; they are not the driving wheel ahead.
    /// Where neither figure is clamped, the difference is the difference moved.
    #[test]
    fn a_tie_near_zero_is_not_a_lead() {
        let ids = ["low", "high"];
        let follower = |set: &str| match set {
            RUN_SET => 0.0012,
            "low" => 0.0,
            _ => 0.0020,
        };
        let driving = |_: &str| 0.0;
        let d = difference_under_sets(&ids, (0.0009, 0.0), &follower, &driving);
        assert_eq!(d[0], (0.0, "low"));
        assert!((d[1].0 - 0.0017).abs() < 1e-15, "{d:?}");
        let driving = |set: &str| if set == RUN_SET { 0.001 } else { 0.0005 };
        let d = difference_under_sets(&ids, (0.3, 0.2), &follower, &driving);
        let moved_difference = |set: &str| 0.1 + (follower(set) - driving(set)) - (0.0012 - 0.001);
        for (x, id) in d {
            assert!((x - moved_difference(id)).abs() < 1e-15, "{id}: {x}");
        }
    }
}
