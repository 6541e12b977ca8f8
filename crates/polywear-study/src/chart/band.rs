//! The boundary's uncertainty: K tire structures drawn from a study's distributions of the
//! parameters that are not the operating point (the groups "Tire structure", "Friction and
//! damping" and "Vehicle" of `polywear params`, MODEL.md#parameter-table), each one's stability on the chart's grid, and per cell the share of
//! structures for which the wheel is unstable. Cells with a share between 5% and 95% form the
//! band in which 90% of the structures put the boundary.

use super::ChartRequest;
use std::path::Path;

use crate::param_sources::{Conflict, ParamSources, Refusal};
use crate::study::Study;
use polywear_core::ensemble::{self, Control};
use polywear_core::model::Wheel;
use polywear_core::params::{Group, ParamId, Params};

/// The shares at which the band starts and ends.
pub(crate) const BAND: (f64, f64) = (0.05, 0.95);

/// The structures' draws and, per wheel, the unstable share of each grid cell.
#[derive(Debug, Clone)]
pub struct StructureBand {
    /// The drawn parameters.
    pub drawn: Vec<ParamId>,
    /// The K structures: the chart's base parameters with the drawn ones set per sample.
    pub structures: Vec<Params>,
    /// Cells per axis; shares are row-major in y, then x.
    pub cells: usize,
    /// (wheel, share of structures unstable per cell; NaN where no structure has a model).
    pub shares: Vec<(Wheel, Vec<f64>)>,
}

/// The study's drawn parameters that are neither operating-point parameters nor chart axes.
pub(crate) fn structure_params(req: &ChartRequest, study: &Study) -> Vec<ParamId> {
    study
        .drawn
        .iter()
        .map(|d| d.param)
        .filter(|&id| id.spec().group != Group::OperatingPoint && id != req.x && id != req.y)
        .collect()
}

/// Draws `k` structures (sample indices 0..k of the study's design with `seed`) on top of the
/// chart's parameters and evaluates each wheel's stability on a `cells`² grid.
pub fn structure_band(
    req: &ChartRequest,
    study: &Study,
    seed: u64,
    k: u64,
    cells: usize,
) -> StructureBand {
    let drawn = structure_params(req, study);
    let sampler = study.sampler(seed, k);
    let structures: Vec<Params> = (0..k)
        .map(|i| {
            let (_, values) = sampler.sample(i);
            let mut q = req.base;
            for (d, v) in study.drawn.iter().zip(values) {
                if drawn.contains(&d.param) {
                    q[d.param] = v;
                }
            }
            q
        })
        .collect();
    let shares = req
        .wheels
        .iter()
        .map(|&wheel| {
            let grid = |k: usize| {
                let r = ChartRequest {
                    base: structures[k],
                    ..req.clone()
                };
                r.stability_grid(wheel, cells, cells)
            };
            let grids: Vec<Vec<Option<bool>>> =
                ensemble::solve(structures.len(), grid, &Control::QUIET).all();
            let share = (0..cells * cells)
                .map(|c| {
                    let known: Vec<bool> = grids.iter().filter_map(|g| g[c]).collect();
                    if known.is_empty() {
                        f64::NAN
                    } else {
                        known.iter().filter(|u| **u).count() as f64 / known.len() as f64
                    }
                })
                .collect();
            (wheel, share)
        })
        .collect();
    StructureBand {
        drawn,
        structures,
        cells,
        shares,
    }
}

impl StructureBand {
    /// Whether a cell lies in the band: unstable for more than 5% and at most 95% of the
    /// structures.
    pub fn in_band(share: f64) -> bool {
        share > BAND.0 && share <= BAND.1
    }
}
/// The study a chart's uncertainty band draws its tire structures from, checked before work: a parameter it draws for the
/// band and the command line or `--params` sets too is refused (the band would replace it).
pub fn band_study(
    path: &Path,
    k: u64,
    req: &ChartRequest,
    sources: &ParamSources,
    accept_implausible: bool,
) -> Result<Study, Refusal> {
    let text = Refusal::read_text("--study", path)?;
    let in_study = |e| Refusal::study(format!("--study {}", path.display()), e);
    let study = Study::parse_with_base(&text, req.base).map_err(in_study)?;
    study
        .check_samples(k)
        .map_err(|e| Refusal::study(format!("--structure-samples {k}"), e))?;
    let drawn = structure_params(req, &study);
    if drawn.is_empty() {
        return Err(Refusal::NoBandDrawn {
            study: path.to_path_buf(),
        });
    }
    for d in study.drawn.iter().filter(|d| drawn.contains(&d.param)) {
        if let Some(by) = sources.given_by(d.param) {
            return Err(Conflict::BandDrawn {
                by,
                id: d.param,
                study: path.to_path_buf(),
            }
            .into());
        }
        if !(accept_implausible || study.accept_implausible) {
            d.check_plausible().map_err(in_study)?;
        }
    }
    Ok(study)
}

impl StructureBand {
    /// The band table's metadata: the chart's, then the study it was drawn from.
    pub fn metadata(
        &self,
        chart: &[(String, String)],
        study: &Study,
        k: u64,
    ) -> Vec<(String, String)> {
        let mut band_meta = chart.to_vec();
        band_meta.push(("study".into(), study.name.clone()));
        band_meta.push(("study_source".into(), study.source.clone()));
        band_meta.push(("seed".into(), study.seed.to_string()));
        band_meta.push(("structure_samples".into(), k.to_string()));
        band_meta.push((
            "structure_params".into(),
            self.drawn
                .iter()
                .map(|d| d.name())
                .collect::<Vec<_>>()
                .join(","),
        ));
        band_meta
    }
}
