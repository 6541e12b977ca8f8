//! Reads an explore output (a Parquet file or a directory of chunk files, several directories
//! for shards) lazily with polars: only the needed columns are read, then handed on as plain
//! vectors.

use std::path::{Path, PathBuf};

use polars::prelude::*;

use crate::model::{Variant, Wheel};

/// Class codes of the rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RowClass {
    Stable,
    LimitCycle,
    Bistable,
    NoTraction,
    Failed,
}

impl RowClass {
    fn parse(s: &str) -> RowClass {
        match s {
            "stable" => RowClass::Stable,
            "limit_cycle" => RowClass::LimitCycle,
            "bistable" => RowClass::Bistable,
            "no_traction" => RowClass::NoTraction,
            _ => RowClass::Failed,
        }
    }

    pub fn as_str(self) -> &'static str {
        match self {
            RowClass::Stable => "stable",
            RowClass::LimitCycle => "limit_cycle",
            RowClass::Bistable => "bistable",
            RowClass::NoTraction => "no_traction",
            RowClass::Failed => "failed",
        }
    }

    /// Self-excited vibration (the polygonal-wear risk).
    pub fn vibrates(self) -> bool {
        matches!(self, RowClass::LimitCycle | RowClass::Bistable)
    }
}

/// An input axis of the analysis: an explored parameter with its values per row.
#[derive(Debug, Clone)]
pub struct Axis {
    pub name: String,
    pub unit: String,
    pub values: Vec<f64>,
}

/// What the files' metadata says about the run.
#[derive(Debug, Clone, Default)]
pub struct RunInfo {
    pub study_name: String,
    pub study: String,
    pub seed: String,
    pub samples: String,
    pub design: String,
    pub variant: String,
    pub version: String,
    pub drawn_names: Vec<String>,
    pub files: usize,
}

/// The rows needed by the analysis.
#[derive(Debug, Clone, Default)]
pub struct Dataset {
    pub sample_id: Vec<i64>,
    pub wheel: Vec<Wheel>,
    pub variant: Vec<Variant>,
    pub class: Vec<RowClass>,
    /// The drawn parameters (in the study's order), operating axes included.
    pub axes: Vec<Axis>,
    pub amp_y_m: Vec<f64>,
    pub amp_v_mps: Vec<f64>,
    pub energy_per_cycle_j: Vec<f64>,
    pub polygon_order: Vec<f64>,
    pub info: RunInfo,
}

impl Dataset {
    pub fn len(&self) -> usize {
        self.wheel.len()
    }

    pub fn is_empty(&self) -> bool {
        self.wheel.is_empty()
    }

    pub fn axis(&self, name: &str) -> Option<&Axis> {
        self.axes.iter().find(|a| a.name == name)
    }

    /// (variant, wheel) pairs present, in a fixed order.
    pub fn groups(&self) -> Vec<(Variant, Wheel)> {
        let mut g: Vec<(Variant, Wheel)> = Variant::ALL
            .iter()
            .flat_map(|v| Wheel::BOTH.map(|w| (*v, w)))
            .filter(|(v, w)| {
                self.variant
                    .iter()
                    .zip(&self.wheel)
                    .any(|(a, b)| a == v && b == w)
            })
            .collect();
        g.dedup();
        g
    }
}

/// The Parquet files behind the given inputs (files or directories).
pub fn parquet_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut files = Vec::new();
    for input in inputs {
        if input.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(input)
                .map_err(|e| format!("{}: {e}", input.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.extension().is_some_and(|x| x == "parquet")
                        && !p
                            .file_name()
                            .is_some_and(|n| n.to_string_lossy().starts_with('_'))
                })
                .collect();
            found.sort();
            files.extend(found);
        } else if input.is_file() {
            files.push(input.clone());
        } else {
            return Err(format!("{}: no such file or directory", input.display()));
        }
    }
    if files.is_empty() {
        return Err("no Parquet files found in the given inputs".into());
    }
    Ok(files)
}

/// Footer key–value metadata of one Parquet file.
pub fn file_metadata(path: &Path) -> Result<Vec<(String, String)>, String> {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    let f = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let r = SerializedFileReader::new(f).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(r.metadata()
        .file_metadata()
        .key_value_metadata()
        .map(|kv| {
            kv.iter()
                .map(|k| (k.key.clone(), k.value.clone().unwrap_or_default()))
                .collect()
        })
        .unwrap_or_default())
}

fn pl_err(e: PolarsError) -> String {
    format!("reading Parquet: {e}")
}

/// Loads the analysis columns of an explore output.
pub fn load(inputs: &[PathBuf]) -> Result<Dataset, String> {
    let files = parquet_files(inputs)?;
    let meta = file_metadata(&files[0])?;
    let get = |k: &str| {
        meta.iter()
            .find(|(n, _)| n == k)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    let mut drawn_names: Vec<String> =
        serde_json::from_str(&get("drawn_names")).unwrap_or_default();
    if drawn_names.is_empty() {
        // Files of polywear 0.1.0 before `drawn_names`: the names lead the `drawn` entries.
        let drawn: Vec<String> = serde_json::from_str(&get("drawn")).unwrap_or_default();
        drawn_names = drawn
            .iter()
            .filter_map(|d| d.split(':').next().map(str::to_string))
            .collect();
    }
    if drawn_names.is_empty() {
        return Err(format!(
            "{}: not an explore output (no `drawn_names` metadata); analyze reads what `polywear explore` writes",
            files[0].display()
        ));
    }
    let units: serde_json::Map<String, serde_json::Value> =
        serde_json::from_str(&get("units")).unwrap_or_default();
    let info = RunInfo {
        study_name: get("study_name"),
        // Chunks carry only `study_hash`; the text is kept once, in the run's manifest.
        study: Some(get("study"))
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| crate::output_dir::manifest_study(&files[0])),
        seed: get("seed"),
        samples: get("samples"),
        design: get("design"),
        variant: get("variant"),
        version: get("polywear_version"),
        drawn_names: drawn_names.clone(),
        files: files.len(),
    };

    let paths: Vec<PlRefPath> = files
        .iter()
        .map(|p| PlRefPath::new(p.to_string_lossy().as_ref()))
        .collect();
    let lf = LazyFrame::scan_parquet_files(
        paths.into_iter().collect(),
        ScanArgsParquet {
            low_memory: true,
            ..ScanArgsParquet::default()
        },
    )
    .map_err(pl_err)?;
    let mut cols: Vec<Expr> = [
        "sample_id",
        "wheel",
        "variant",
        "class",
        "amp_y_m",
        "amp_v_mps",
        "energy_per_cycle_j",
        "polygon_order",
    ]
    .iter()
    .map(|c| col(*c))
    .collect();
    cols.extend(drawn_names.iter().map(|c| col(c.as_str())));
    let mut df = lf.select(cols).collect().map_err(pl_err)?;
    // Each column is taken out of the frame as it is converted, so the frame and the vectors
    // never both hold the whole table (peak memory about one copy).
    let mut take = |name: &str| df.drop_in_place(name).map_err(pl_err);
    let f64s = |c: Column| -> Result<Vec<f64>, String> {
        Ok(c.f64()
            .map_err(pl_err)?
            .iter()
            .map(|v| v.unwrap_or(f64::NAN))
            .collect())
    };
    let sample_id: Vec<i64> = take("sample_id")?
        .i64()
        .map_err(pl_err)?
        .iter()
        .map(|v| v.unwrap_or(-1))
        .collect();
    let wheel = take("wheel")?
        .str()
        .map_err(pl_err)?
        .iter()
        .map(|s| s.unwrap_or("").parse::<Wheel>())
        .collect::<Result<Vec<_>, _>>()?;
    let variant = take("variant")?
        .str()
        .map_err(pl_err)?
        .iter()
        .map(|s| s.unwrap_or("").parse::<Variant>())
        .collect::<Result<Vec<_>, _>>()?;
    let class = take("class")?
        .str()
        .map_err(pl_err)?
        .iter()
        .map(|s| RowClass::parse(s.unwrap_or("")))
        .collect();
    let mut axes = Vec::new();
    for name in &drawn_names {
        axes.push(Axis {
            name: name.clone(),
            unit: units
                .get(name)
                .and_then(|u| u.as_str())
                .unwrap_or("")
                .to_string(),
            values: f64s(take(name)?)?,
        });
    }
    let amp_y_m = f64s(take("amp_y_m")?)?;
    let amp_v_mps = f64s(take("amp_v_mps")?)?;
    let energy_per_cycle_j = f64s(take("energy_per_cycle_j")?)?;
    let polygon_order = f64s(take("polygon_order")?)?;
    Ok(Dataset {
        sample_id,
        wheel,
        variant,
        class,
        axes,
        amp_y_m,
        amp_v_mps,
        energy_per_cycle_j,
        polygon_order,
        info,
    })
}
