//! Which parameters drive the risk: first-order and total Sobol indices from a Saltelli design
//! (sample_id = j·(k+2) + block), with bootstrap intervals.

use std::collections::BTreeMap;

use super::inputs::RunInfo;
use super::rows::Rows;
use super::stats::sobol_with_bootstrap;
use super::AnalysisError;
use polywear_core::classify::Class;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::ParamId;
use polywear_core::records::RecordColumn;
use polywear_core::sampling::design::Design;

/// The output name of the vibration indicator: 1 when the wheel vibrates (limit cycle or
/// bistable), 0 when stable.
pub(crate) const VIBRATION: &str = "vibration";

/// First-order and total Sobol indices of one output with respect to one parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    /// The friction variant.
    pub variant: Variant,
    /// The wheel.
    pub wheel: Wheel,
    /// `VIBRATION` (the 0/1 indicator: limit cycle or bistable) or `amp_v_mps` (0 without a
    /// cycle).
    pub output: &'static str,
    /// The drawn parameter the indices belong to.
    pub param: ParamId,
    /// Base points of the Saltelli design used.
    pub base_samples: u64,
    /// Base points left out because a block is missing or unclassified.
    pub left_out: u64,
    /// First-order index (Saltelli 2010) with its bootstrap 95% interval: (estimate, lo, hi).
    pub s: (f64, f64, f64),
    /// Total index (Jansen 1999) with its bootstrap 95% interval: (estimate, lo, hi).
    pub st: (f64, f64, f64),
}

/// Sobol indices from a Saltelli design; None for other designs. The estimators and their
/// bootstrap need every row's outputs, in (j, block) order per variant and wheel.
pub(crate) fn sensitivity(
    rows: &Rows,
    info: &RunInfo,
    resamples: usize,
) -> Result<Option<Vec<Sensitivity>>, AnalysisError> {
    if info.design != Design::Saltelli {
        return Ok(None);
    }
    let k = info.drawn_names.len();
    let stride = k as i64 + 2;
    let outcomes = rows.outcomes_by_sample()?;
    let mut out = Vec::new();
    let mut i = 0;
    while i < outcomes.len() {
        let (variant, wheel) = (outcomes[i].variant, outcomes[i].wheel);
        // rows[j][block] = Some((indicator, amplitude)) for classified rows, None otherwise.
        type Block = Option<Option<(f64, f64)>>;
        let mut blocks: BTreeMap<i64, Vec<Block>> = BTreeMap::new();
        while i < outcomes.len() && (outcomes[i].variant, outcomes[i].wheel) == (variant, wheel) {
            let r = &outcomes[i];
            let v = if r.class.vibrates() {
                Some((1.0, r.amp_v_mps))
            } else if r.class == Class::Stable {
                Some((0.0, 0.0))
            } else {
                None
            };
            blocks
                .entry(r.sample_id / stride)
                .or_insert_with(|| vec![None; k + 2])[(r.sample_id % stride) as usize] = Some(v);
            i += 1;
        }
        let total = blocks.len() as u64;
        // Only complete base points, every block classified.
        let complete: Vec<Vec<(f64, f64)>> = blocks
            .into_values()
            .filter_map(|r| r.into_iter().collect::<Option<Option<Vec<_>>>>().flatten())
            .collect();
        if complete.len() < 2 {
            continue;
        }
        // The vibration indicator (0/1) and the velocity amplitude (0 without a cycle).
        for (pick, output) in [VIBRATION, RecordColumn::AmpVMps.name()]
            .into_iter()
            .enumerate()
        {
            let raw = |r: &Vec<(f64, f64)>, b: usize| if pick == 0 { r[b].0 } else { r[b].1 };
            // Outputs centred on the mean of every evaluated row (A, B and all AB blocks), as
            // SALib's `sobol.analyze` does: the first-order estimator mean(f_B (f_ABi − f_A))
            // is not shift-invariant, and centring lowers its variance. Total indices and the
            // variance are unchanged by the shift.
            let mean = complete
                .iter()
                .map(|r| (0..k + 2).map(|b| raw(r, b)).sum::<f64>())
                .sum::<f64>()
                / (complete.len() * (k + 2)) as f64;
            let f = |r: &Vec<(f64, f64)>, b: usize| raw(r, b) - mean;
            let fa: Vec<f64> = complete.iter().map(|r| f(r, 0)).collect();
            let fb: Vec<f64> = complete.iter().map(|r| f(r, 1)).collect();
            for (m, param) in info.drawn_names.iter().enumerate() {
                let fab: Vec<f64> = complete.iter().map(|r| f(r, 2 + m)).collect();
                let (s, st) = sobol_with_bootstrap(&fa, &fb, &fab, resamples, 17 + m as u64);
                out.push(Sensitivity {
                    variant,
                    wheel,
                    output,
                    param: *param,
                    base_samples: complete.len() as u64,
                    left_out: total - complete.len() as u64,
                    s,
                    st,
                });
            }
        }
    }
    Ok(Some(out))
}
