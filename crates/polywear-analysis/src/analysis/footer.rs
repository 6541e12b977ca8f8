//! One chunk file's footer as the input checks read it: its key–value metadata (the run, read
//! typed), its row count, the range of its sample ids and the type of each column; and the
//! chunks of an explore directory verified against its journal. Nothing here reads a row.

use std::path::{Path, PathBuf};

use parquet::basic::{ConvertedType, LogicalType, Type as PhysicalType};
use parquet::schema::types::ColumnDescriptor;

use super::AnalysisError;
use polywear_core::params::ParamId;
use polywear_study::explore::RunManifest;
use polywear_study::output_dir::{self, ChunkMismatch};
use polywear_study::safe_read::{self, Limit};

/// A column's type as the checks compare it, and as messages name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ColumnType {
    /// 64-bit floating point.
    Double,
    /// 64-bit integer.
    Int64,
    /// UTF-8 text.
    Text,
    /// Any other type, by its Parquet name.
    Other(&'static str),
}

impl std::fmt::Display for ColumnType {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ColumnType::Double => "double (f64)",
            ColumnType::Int64 => "int64",
            ColumnType::Text => "string (UTF-8)",
            ColumnType::Other(name) => name,
        })
    }
}

impl ColumnType {
    fn of(c: &ColumnDescriptor) -> ColumnType {
        let logical = c.logical_type_ref();
        let text = matches!(logical, Some(LogicalType::String))
            || c.converted_type() == ConvertedType::UTF8;
        // An int64 column may carry the annotation "signed 64-bit integer" (pyarrow writes it).
        let plain_int = match logical {
            None => true,
            Some(LogicalType::Integer {
                bit_width,
                is_signed,
            }) => *bit_width == 64 && *is_signed,
            _ => false,
        };
        match c.physical_type() {
            PhysicalType::DOUBLE => ColumnType::Double,
            PhysicalType::INT64 if plain_int => ColumnType::Int64,
            PhysicalType::INT64 => ColumnType::Other("int64 with a logical type (time, decimal)"),
            PhysicalType::BYTE_ARRAY if text => ColumnType::Text,
            PhysicalType::BYTE_ARRAY => ColumnType::Other("binary"),
            PhysicalType::FLOAT => ColumnType::Other("float (f32)"),
            PhysicalType::INT32 => ColumnType::Other("int32"),
            PhysicalType::BOOLEAN => ColumnType::Other("boolean"),
            PhysicalType::INT96 => ColumnType::Other("int96"),
            PhysicalType::FIXED_LEN_BYTE_ARRAY => ColumnType::Other("fixed-length binary"),
        }
    }
}

/// One chunk file's footer, as far as the checks need it.
#[derive(Debug, Clone)]
pub(super) struct FileFooter {
    pub(super) path: PathBuf,
    pub(super) meta: Vec<(String, String)>,
    /// The run as the footer records it, or why it cannot be read (the message names the key).
    run: Result<RunManifest, polywear_study::explore::manifest::ManifestError>,
    pub(super) rows: u64,
    /// (min, max) of `sample_id` from the column statistics.
    pub(super) id_range: Option<(i64, i64)>,
    /// Every column with its type, in file order.
    columns: Vec<(String, ColumnType)>,
}

impl FileFooter {
    /// Reads the footer of `path` (a regular file, see [`polywear_study::safe_read`]).
    pub(super) fn read(path: &Path) -> Result<FileFooter, AnalysisError> {
        use parquet::file::reader::{FileReader, SerializedFileReader};
        let (f, _) = safe_read::open(path, Limit::Chunk).map_err(|e| AnalysisError::Io {
            path: path.to_path_buf(),
            message: e.reason(),
        })?;
        // The parquet crate's metadata decoder can panic on a damaged footer (an unwrap on a
        // missing thrift field) instead of returning an error: such a file is refused as
        // damaged, without the panic's words on stderr.
        let quiet = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let decoded = std::panic::catch_unwind(|| SerializedFileReader::new(f));
        std::panic::set_hook(quiet);
        let r = decoded
            .map_err(|_| AnalysisError::Io {
                path: path.to_path_buf(),
                message: "damaged Parquet footer: its metadata cannot be decoded".into(),
            })?
            .map_err(|e| AnalysisError::io(path, e))?;
        let md = r.metadata();
        let meta: Vec<(String, String)> = md
            .file_metadata()
            .key_value_metadata()
            .map(|kv| {
                kv.iter()
                    .map(|k| (k.key.clone(), k.value.clone().unwrap_or_default()))
                    .collect()
            })
            .unwrap_or_default();
        let schema = md.file_metadata().schema_descr();
        let columns = schema
            .columns()
            .iter()
            .map(|c| (c.path().string(), ColumnType::of(c)))
            .collect();
        let id_col = (0..schema.num_columns())
            .find(|&i| schema.column(i).name() == polywear_core::records::SAMPLE_ID.name);
        let (rows, id_range) = id_statistics(md.row_groups(), id_col);
        Ok(FileFooter {
            path: path.to_path_buf(),
            run: RunManifest::from_key_values(&meta),
            meta,
            rows,
            id_range,
            columns,
        })
    }

    /// Whether the footer is an explore chunk's: it names the drawn values.
    pub(super) fn is_explore(&self) -> bool {
        self.meta
            .iter()
            .any(|(k, _)| k == "drawn_names" || k == "drawn")
    }

    /// The run the footer records, or a refusal naming the file and the key.
    pub(super) fn run(&self) -> Result<&RunManifest, AnalysisError> {
        self.run.as_ref().map_err(|e| AnalysisError::Metadata {
            path: self.path.clone(),
            message: e.to_string(),
        })
    }

    /// The text of metadata key `key`, if present.
    pub(super) fn value(&self, key: &str) -> Option<&str> {
        self.meta
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Refuses a column the analysis reads that is missing or of another type than explore
    /// writes: the drawn values and cycle quantities as doubles, `sample_id` as int64, the
    /// names as text.
    /// Whether the file has a column `name`.
    pub(super) fn has_column(&self, name: &str) -> bool {
        self.columns.iter().any(|(c, _)| c == name)
    }

    pub(super) fn check_columns(
        &self,
        drawn: &[ParamId],
        quantities: &[&str],
    ) -> Result<(), AnalysisError> {
        use polywear_core::records::{RecordColumn, SAMPLE_ID};
        let text = [
            RecordColumn::Variant,
            RecordColumn::Wheel,
            RecordColumn::Class,
        ]
        .map(|c| (c.name(), ColumnType::Text));
        let wanted = text
            .into_iter()
            .chain([(SAMPLE_ID.name, ColumnType::Int64)])
            .chain(drawn.iter().map(|p| (p.name(), ColumnType::Double)))
            .chain(quantities.iter().map(|q| (*q, ColumnType::Double)));
        for (name, expected) in wanted {
            let found = self
                .columns
                .iter()
                .find(|(c, _)| c == name)
                .map(|(_, t)| *t);
            if found != Some(expected) {
                return Err(AnalysisError::ColumnType {
                    path: self.path.clone(),
                    column: name.to_string(),
                    found: found.map_or("missing".to_string(), |t| t.to_string()),
                    expected: expected.to_string(),
                });
            }
        }
        Ok(())
    }
}

/// Rows of a file and the (min, max) of its `sample_id` from the row groups' statistics (None
/// when a non-empty row group has none).
fn id_statistics(
    groups: &[parquet::file::metadata::RowGroupMetaData],
    id_col: Option<usize>,
) -> (u64, Option<(i64, i64)>) {
    use parquet::file::statistics::Statistics;
    let mut id_range: Option<(i64, i64)> = None;
    let mut rows = 0u64;
    let mut stats_complete = true;
    for rg in groups {
        rows += rg.num_rows() as u64;
        let Some(c) = id_col else {
            stats_complete = false;
            continue;
        };
        match rg.column(c).statistics() {
            Some(Statistics::Int64(s)) => match (s.min_opt(), s.max_opt()) {
                (Some(lo), Some(hi)) => {
                    id_range = Some(match id_range {
                        None => (*lo, *hi),
                        Some((a, b)) => (a.min(*lo), b.max(*hi)),
                    })
                }
                _ => stats_complete = rg.num_rows() == 0 && stats_complete,
            },
            _ => stats_complete = false,
        }
    }
    (rows, if stats_complete { id_range } else { None })
}

/// Verifies every chunk file of the explore directory `dir` among `files` against the
/// directory's journal (rows, size and CRC-32, as `explore --resume` does): a chunk that was
/// damaged, replaced or never recorded is refused, naming the file and the command that
/// re-evaluates it. A directory without a journal (a run of a polywear that kept none) is not
/// verified.
pub(super) fn verify_chunks(dir: &Path, files: &[PathBuf]) -> Result<(), AnalysisError> {
    if !dir.join(output_dir::JOURNAL).exists() {
        return Ok(());
    }
    let journal = output_dir::read_journal(dir).map_err(|e| AnalysisError::io(dir, e))?;
    let chunks: Vec<(&PathBuf, u64)> = files
        .iter()
        .filter(|f| f.parent() == Some(dir))
        .filter_map(|f| {
            let name = f.file_name()?.to_str()?;
            Some((f, output_dir::chunk_index(name)?))
        })
        .collect();
    let verify = |k: usize| {
        let (f, c) = chunks[k];
        let entry = journal.get(&c);
        let rows = entry.map_or(0, |e| e.rows);
        output_dir::verify_chunk(f, entry, rows).map(|why| (f.clone(), why))
    };
    let bad = polywear_core::ensemble::solve(
        chunks.len(),
        verify,
        &polywear_core::ensemble::Control::QUIET,
    )
    .all()
    .into_iter()
    .flatten()
    .next();
    match bad {
        None => Ok(()),
        Some((path, why)) => Err(AnalysisError::Damaged {
            path,
            why: match why {
                ChunkMismatch::NotRecorded => {
                    "not recorded in the run's journal (written after the run stopped, or copied in)"
                        .to_string()
                }
                why => why.to_string(),
            },
            dir: dir.to_path_buf(),
        }),
    }
}
