//! The files of a classified cycle: `cycle.parquet` (one row per structure sample, step and
//! wheel: the explorer's columns plus the step's time and the quasi-static assessment),
//! `cycle_summary.csv` (with a `cycle_summary.parquet` sidecar carrying the metadata) and
//! `cycle.png`.

use std::path::{Path, PathBuf};

use super::FilesError;
use crate::plot::cycle::{cycle_figure, WheelTrace};
use crate::plot::{FigureFile, FigureFormat, PlotError};
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params, OPERATING_AXES};
use polywear_core::records::{record_columns, OPERATING_POINT_ROW, SAMPLE_ID};
use polywear_core::wear::FittedConstants;
use polywear_study::cycle::request::CyclePlan;
use polywear_study::cycle::summary::{summarise, summary_columns, WheelSummary};
use polywear_study::cycle::wear::CycleLife;
use polywear_study::cycle::{ClassifiedCycle, DriveCycle, StepWheel};
use polywear_study::operating_points::OperatingPoints;
use polywear_study::parquet_out::{write_csv, write_table, Column};

/// A classified cycle, for one or several tire structures.
pub struct CycleRun<'a> {
    /// The drive cycle classified.
    pub cycle: &'a DriveCycle,
    /// The model variant used for both wheels.
    pub variant: Variant,
    /// The parameters drawn per structure sample (empty without a study).
    pub structure_names: Vec<ParamId>,
    /// `structure_values[k][j]`: sample k's value of `structure_names[j]`.
    pub structure_values: Vec<Vec<f64>>,
    /// `steps[k][i]`: sample k, step i, both wheels.
    pub steps: Vec<Vec<[StepWheel; 2]>>,
    /// `life[k][w]`: sample k's wheel w over the tread's life, its steps' profiles summed by
    /// distance (None without the wear stage); empty for none.
    pub life: Vec<[Option<CycleLife>; 2]>,
    /// Written into every file (version, command, parameters, variant, cycle, study).
    pub metadata: Vec<(String, String)>,
    /// The study's fleet, when its `[operating_points]` gave each structure sample a row.
    pub fleet: Option<FleetDraw<'a>>,
    /// `bases[k]`: structure sample k's parameters, when the steps ran the wear stage (the
    /// seed and the visible depth of its distance to a visible polygon); empty otherwise.
    pub wear_bases: Vec<Params>,
    /// The calibrated sets each structure's wear is also evaluated under (the calibration band;
    /// empty for none). σ_V does not enter: a cycle's speeds are its spread.
    pub band_sets: Vec<FittedConstants>,
}

/// The operating-point rows a study's fleet gave the structure samples: each sample drives the
/// whole cycle with one row's load, pressure and toe-in (and any other column but the speed).
pub struct FleetDraw<'a> {
    /// The study's operating points.
    pub points: &'a OperatingPoints,
    /// `rows[k]`: the row (0-based) structure sample k drew.
    pub rows: Vec<usize>,
}

impl<'a> CycleRun<'a> {
    /// The run of `plan` whose structures `classified` holds, in its order: the one place that
    /// pairs a checked plan with its steps, so that the files and the words read the same
    /// structures, fleet rows and wear bases. The lifetime verdict reads the tire's life
    /// constants as its steps do: a cycle's constant column of one of them is the whole life's
    /// (MODEL.md#along-a-drive-cycle).
    pub fn new(plan: &'a CyclePlan, classified: Vec<ClassifiedCycle>) -> Self {
        let request = &plan.request;
        let (steps, life) = classified.into_iter().map(|c| (c.steps, c.life)).unzip();
        let structures = &request.structures;
        let fleet = match (&request.study, &structures.fleet_rows) {
            (Some(s), Some(rows)) => s.operating_points.as_ref().map(|points| FleetDraw {
                points,
                rows: rows.clone(),
            }),
            _ => None,
        };
        let wear_bases = match plan.wear {
            Some(_) => structures
                .bases
                .iter()
                .map(|b| request.cycle.whole_life(b))
                .collect(),
            None => Vec::new(),
        };
        CycleRun {
            cycle: &request.cycle,
            variant: request.variant,
            structure_names: structures.names.clone(),
            structure_values: structures.values.clone(),
            steps,
            life,
            metadata: request.metadata.clone(),
            fleet,
            wear_bases,
            band_sets: plan.band_sets.clone(),
        }
    }
}

impl CycleRun<'_> {
    /// The per-wheel summary of every structure sample.
    pub fn summaries(&self) -> Vec<[WheelSummary; 2]> {
        self.steps
            .iter()
            .enumerate()
            .map(|(k, s)| {
                [0, 1].map(|w| {
                    let base = self.wear_bases.get(k);
                    let life = self.life.get(k).and_then(|l| l[w].as_ref());
                    let (wear, wear_band) = match (base, life) {
                        // Over the tread's life: the structure's own constants, then each set's.
                        (Some(base), Some(life)) => {
                            let sets: Vec<FittedConstants> =
                                std::iter::once(FittedConstants::of(base))
                                    .chain(self.band_sets.iter().copied())
                                    .collect();
                            let mut all = life.wear_with(base, &sets).into_iter();
                            (all.next(), all.collect())
                        }
                        _ => (None, Vec::new()),
                    };
                    WheelSummary {
                        wear,
                        wear_band,
                        ..summarise(self.cycle, s, w)
                    }
                })
            })
            .collect()
    }

    /// The columns of `cycle.parquet`.
    pub fn columns(&self) -> Vec<Column> {
        let c = self.cycle;
        let n = c.len();
        let dt = c.step_durations_s();
        // Row order: sample, step, wheel (follower, driving).
        let idx: Vec<(usize, usize, usize)> = (0..self.steps.len())
            .flat_map(|k| (0..n).flat_map(move |i| [(k, i, 0), (k, i, 1)]))
            .collect();
        let rows: Vec<&StepWheel> = idx.iter().map(|&(k, i, w)| &self.steps[k][i][w]).collect();
        let mut cols = vec![Column::i64(
            SAMPLE_ID.name,
            SAMPLE_ID.unit,
            idx.iter().map(|r| r.0 as i64).collect(),
        )];
        if let Some(f) = &self.fleet {
            let rows: Vec<usize> = idx.iter().map(|r| f.rows[r.0]).collect();
            cols.push(Column::i64(
                OPERATING_POINT_ROW.name,
                OPERATING_POINT_ROW.unit,
                rows.iter().map(|&r| r as i64 + 1).collect(),
            ));
            cols.extend(f.points.pass_through_columns(&rows));
        }
        cols.extend([
            Column::i64("step", "", idx.iter().map(|r| r.1 as i64).collect()),
            Column::f64("time_s", "s", idx.iter().map(|r| c.time_s[r.1]).collect()),
            Column::f64(
                "step_duration_s",
                "s",
                idx.iter().map(|r| dt[r.1]).collect(),
            ),
        ]);
        let records: Vec<_> = rows.iter().map(|s| s.record.clone()).collect();
        let record_cols = record_columns(&records);
        // A file never holds one name twice: the operating axes are record columns already, and
        // so is a wear constant the wear stage writes (`wear_share_straight`): the record's
        // column is the step's value.
        let recorded = |id: &ParamId| record_cols.iter().any(|c| c.name == id.name());
        for (j, id) in self.structure_names.iter().enumerate() {
            if !recorded(id) {
                let v = idx.iter().map(|r| self.structure_values[r.0][j]).collect();
                cols.push(Column::f64(id.name(), id.spec().unit, v));
            }
        }
        for (j, id) in c.names.iter().enumerate() {
            if !OPERATING_AXES.contains(id) && !recorded(id) {
                let v = idx.iter().map(|r| c.values[r.1][j]).collect();
                cols.push(Column::f64(id.name(), id.spec().unit, v));
            }
        }
        cols.extend(record_cols);
        cols.push(Column::f64(
            "tread_time_constant_s",
            "s",
            rows.iter().map(|s| s.tread_time_constant_s).collect(),
        ));
        cols.push(Column::f64(
            "stability_change_time_s",
            "s",
            rows.iter().map(|s| s.stability_change_time_s).collect(),
        ));
        cols.push(Column::i64(
            "quasi_static",
            "",
            rows.iter().map(|s| i64::from(s.quasi_static)).collect(),
        ));
        cols
    }

    /// Writes `cycle.parquet`, `cycle_summary.csv` (+ `.parquet`) and `cycle.png` into `dir`,
    /// the summary from `summaries` ([`CycleRun::summaries`], taken once for the files and the
    /// words: on the saturated level each is a walk of every set); returns the paths written.
    pub fn write(
        &self,
        dir: &Path,
        summaries: &[[WheelSummary; 2]],
    ) -> Result<Vec<PathBuf>, FilesError> {
        polywear_study::safe_write::create_dir(dir).map_err(|source| FilesError::CreateDir {
            dir: dir.to_path_buf(),
            source,
        })?;
        let mut meta = self.metadata.clone();
        meta.push((
            "columns".into(),
            "one row per structure sample (sample_id), step and wheel; class `standstill` at 0 km/h; quasi_static = 1 where tread_time_constant_s <= stability_change_time_s".into(),
        ));
        let mut written = Vec::new();
        let table = dir.join("cycle.parquet");
        write_table(&table, &self.columns(), &meta)?;
        written.push(table);
        let summary = summary_columns(summaries);
        let csv = dir.join("cycle_summary.csv");
        write_csv(&csv, &summary)?;
        written.push(csv);
        let sidecar = dir.join("cycle_summary.parquet");
        write_table(&sidecar, &summary, &self.metadata)?;
        written.push(sidecar);
        let picture = FigureFile::named(dir, "cycle", FigureFormat::Png);
        self.figure(&picture)?;
        written.push(picture.path);
        Ok(written)
    }

    /// The picture of structure sample 0.
    fn figure(&self, file: &FigureFile) -> Result<(), PlotError> {
        let steps = &self.steps[0];
        let traces: Vec<WheelTrace<'_>> = (0..2)
            .map(|w| WheelTrace {
                label: polywear_core::model::Wheel::BOTH[w].as_str(),
                vibrates: steps.iter().map(|s| s[w].vibrates()).collect(),
                polygon_order: steps
                    .iter()
                    .map(|s| {
                        if s[w].vibrates() {
                            s[w].record.polygon_order
                        } else {
                            f64::NAN
                        }
                    })
                    .collect(),
            })
            .collect();
        let name = self
            .cycle
            .path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let which = if self.steps.len() > 1 {
            " (structure sample 0)"
        } else {
            ""
        };
        let title = format!(
            "{name}: vibrating stretches and polygon order, variant {}{which}",
            self.variant.as_str()
        );
        cycle_figure(
            file,
            &title,
            &self.cycle.time_s,
            &self.cycle.speed_kmh,
            &traces,
        )
    }
}
