//! Drawing a study's parameter sets: sample `index` of a run is a pure function of the study,
//! the seed, the sample count and the index (the reproducibility contract: shards and threads
//! do not change it).

use super::Study;
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::{grid_digits, Coordinates, Design};
use polywear_core::sampling::Streams;

impl Study {
    /// The sampler for a run of `samples` points with `seed`.
    pub fn sampler(&self, seed: u64, samples: u64) -> Sampler<'_> {
        let grid = if self.design == Design::Grid {
            self.drawn
                .iter()
                .map(|d| d.dist.grid_values().unwrap_or_default())
                .collect()
        } else {
            Vec::new()
        };
        // The operating-point columns were checked to be parameter names when the file was read.
        let op_params = self
            .operating_points
            .iter()
            .flat_map(|o| &o.names)
            .map(|n| {
                n.parse()
                    .expect("operating-point columns are parameter names")
            })
            .collect();
        Sampler {
            study: self,
            coords: Coordinates::new(self.design, seed, samples, self.drawn.len()),
            grid,
            streams: Streams::new(seed),
            op_params,
        }
    }
}

/// Draws parameter sets: a pure function of (study, seed, samples, index).
pub struct Sampler<'a> {
    pub(super) study: &'a Study,
    coords: Coordinates,
    grid: Vec<Vec<f64>>,
    pub(super) streams: Streams,
    /// The parameters of the operating-point file's columns, in its column order.
    pub(super) op_params: Vec<ParamId>,
}

impl Sampler<'_> {
    /// Parameter set of sample `index`, and its values in [`Study::value_names`] order: the
    /// drawn parameters, then the operating-point row's columns where the study has
    /// `[operating_points]` ([`Sampler::sample_with_row`] names the row). Every evaluation of a
    /// run's sample (its rows, the calibration band, optimize) draws it here, so that none
    /// leaves the fleet's row out.
    pub fn sample(&self, index: u64) -> (Params, Vec<f64>) {
        let (p, values, _) = self.sample_with_row(index);
        (p, values)
    }

    /// The design's values of sample `index` alone, in the study's `drawn` order, on the
    /// study's base (without the operating-point row).
    pub(super) fn design_sample(&self, index: u64) -> (Params, Vec<f64>) {
        let mut p = self.study.base;
        let values: Vec<f64> = if self.study.design == Design::Grid {
            let sizes: Vec<usize> = self.grid.iter().map(Vec::len).collect();
            grid_digits(index, &sizes)
                .iter()
                .zip(&self.grid)
                .map(|(k, levels)| levels[*k])
                .collect()
        } else {
            self.study
                .drawn
                .iter()
                .enumerate()
                .map(|(dim, d)| self.coords.value(index, dim, &d.dist))
                .collect()
        };
        for (d, v) in self.study.drawn.iter().zip(&values) {
            p[d.param] = *v;
        }
        (p, values)
    }
}
