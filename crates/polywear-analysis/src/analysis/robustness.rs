//! Robustness to the paper's lost digits: P(limit cycle) of both wheels for each *decoding* (a
//! combination of the levels of the parameters the study draws with `levels`, operating axes
//! aside), and for what share of decodings the driving wheel is less exposed.

use std::collections::BTreeMap;

use super::counts::ClassCounts;
use super::inputs::RunInfo;
use super::rows::{GroupKey, Rows};
use super::stats::wilson;
use super::AnalysisError;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::sampling::distribution::Distribution;

/// One decoding of the paper's lost digits: a combination of the levels of the parameters the
/// study draws with `levels` (operating axes aside), with the class counts of both wheels.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoding {
    /// The friction variant.
    pub variant: Variant,
    /// Values of the decoded parameters, in [`Robustness::params`] order.
    pub values: Vec<f64>,
    /// The follower's rows per class in this decoding.
    pub follower: ClassCounts,
    /// The driving wheel's rows per class in this decoding.
    pub driving: ClassCounts,
}

impl Decoding {
    /// Whether both wheels have at least `min_count` classified rows: enough to compare.
    pub fn comparable(&self, min_count: u64) -> bool {
        self.follower.enough(min_count) && self.driving.enough(min_count)
    }

    /// Whether the driving wheel vibrates less often than the follower.
    pub fn driving_less_exposed(&self) -> bool {
        self.driving.p() < self.follower.p()
    }
}

/// P(limit cycle) per wheel for each decoding, and how often the driving wheel is less exposed.
#[derive(Debug, Clone, PartialEq)]
pub struct Robustness {
    /// The decoded parameters (those drawn with `levels`, operating axes aside).
    pub params: Vec<ParamId>,
    /// Every decoding present in the rows.
    pub decodings: Vec<Decoding>,
}

/// The share of decodings (of one variant) with the driving wheel less exposed than the
/// follower, over the decodings with at least `min_count` classified rows on each wheel.
#[derive(Debug, Clone, PartialEq)]
pub struct RobustnessSummary {
    /// The friction variant.
    pub variant: Variant,
    /// Decodings present.
    pub decodings: u64,
    /// Decodings with at least `min_count` classified rows on each wheel.
    pub compared: u64,
    /// Compared decodings where the driving wheel vibrates less often than the follower.
    pub driving_less: u64,
    /// Decodings left out for too few classified rows.
    pub too_few: u64,
    /// `driving_less / compared`.
    pub share: f64,
    /// Lower end of the 95% Wilson interval of `share`.
    pub lo: f64,
    /// Upper end of the 95% Wilson interval of `share`.
    pub hi: f64,
}

impl Robustness {
    /// The summary of each variant, comparing decodings with at least `min_count` classified rows on each wheel.
    pub fn summary(&self, min_count: u64) -> Vec<RobustnessSummary> {
        let mut variants: Vec<Variant> = self.decodings.iter().map(|d| d.variant).collect();
        variants.sort();
        variants.dedup();
        variants
            .into_iter()
            .map(|variant| {
                let ds: Vec<&Decoding> = self
                    .decodings
                    .iter()
                    .filter(|d| d.variant == variant)
                    .collect();
                let enough: Vec<&&Decoding> =
                    ds.iter().filter(|d| d.comparable(min_count)).collect();
                let less = enough.iter().filter(|d| d.driving_less_exposed()).count() as u64;
                let n = enough.len() as u64;
                let (lo, hi) = wilson(less, n);
                RobustnessSummary {
                    variant,
                    decodings: ds.len() as u64,
                    compared: n,
                    driving_less: less,
                    too_few: ds.len() as u64 - n,
                    share: if n == 0 {
                        f64::NAN
                    } else {
                        less as f64 / n as f64
                    },
                    lo,
                    hi,
                }
            })
            .collect()
    }
}

/// The parameters a study draws with `levels`, the operating axes aside: the decoded constants.
pub(crate) fn decoded_params(info: &RunInfo) -> Vec<ParamId> {
    let Some(study) = &info.study else {
        return Vec::new();
    };
    study
        .drawn
        .iter()
        .filter(|d| matches!(d.dist, Distribution::Levels(_)) && !d.param.is_operating_axis())
        .map(|d| d.param)
        .collect()
}

/// Class counts per decoding and wheel; None when the study draws no parameter with `levels`
/// besides the operating axes.
pub(crate) fn robustness(rows: &Rows, info: &RunInfo) -> Result<Option<Robustness>, AnalysisError> {
    let params = decoded_params(info);
    if params.is_empty() {
        return Ok(None);
    }
    let keys: Vec<GroupKey<'_>> = params.iter().map(|p| GroupKey::Value(p.name())).collect();
    // (variant, value bits) -> (values, follower, driving)
    type Entry = (Vec<f64>, ClassCounts, ClassCounts);
    let mut map: BTreeMap<(Variant, Vec<u64>), Entry> = BTreeMap::new();
    for g in rows.class_counts(&keys)? {
        let key: Vec<u64> = g.values.iter().map(|x| x.to_bits()).collect();
        let e = map.entry((g.variant, key)).or_insert_with(|| {
            (
                g.values.clone(),
                ClassCounts::default(),
                ClassCounts::default(),
            )
        });
        let slot = if g.wheel == Wheel::Follower {
            &mut e.1
        } else {
            &mut e.2
        };
        slot.merge(&g.counts);
    }
    let mut decodings: Vec<Decoding> = map
        .into_iter()
        .map(|((variant, _), (values, follower, driving))| Decoding {
            variant,
            values,
            follower,
            driving,
        })
        .collect();
    decodings.sort_by(|a, b| {
        a.variant.cmp(&b.variant).then_with(|| {
            a.values
                .iter()
                .zip(&b.values)
                .map(|(x, y)| x.total_cmp(y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        })
    });
    Ok(Some(Robustness { params, decodings }))
}
