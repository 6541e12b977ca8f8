//! Parquet output through the low-level column API (no Arrow): typed columns, one row group per
//! chunk so memory stays bounded, and key–value metadata (study, seed, variant, parameters,
//! program version, units) in the file footer. Files open in polars, pandas/pyarrow and DuckDB.
//!
//! Every file is created through [`crate::safe_write`] (never through a planted link). A Parquet
//! file is written crash-safely: under a hidden temporary name, fsynced, renamed, and the
//! directory fsynced, so after a crash or `kill -9` a file is either whole or absent; a CSV file
//! goes through the same temporary name and rename, without the fsyncs. The CRC-32 of the
//! bytes is computed while writing, for the explore manifest.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use parquet::basic::{Compression, ZstdLevel};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, FloatType, Int64Type};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::parser::parse_message_type;
use parquet::schema::types::ColumnPath;

use crate::safe_write::NewFile;
pub use crate::safe_write::{partial_path, sync_dir, write_durably};

pub use polywear_core::columns::{Column, ColumnData};

/// The Parquet physical type a column is written as.
fn physical(data: &ColumnData) -> &'static str {
    match data {
        ColumnData::F64(_) => "DOUBLE",
        ColumnData::F32(_) => "FLOAT",
        ColumnData::I64(_) => "INT64",
        ColumnData::Str(_) => "BYTE_ARRAY",
    }
}

/// Errors while writing; the message names the file.
#[derive(Debug)]
pub struct WriteError(pub String);

impl std::fmt::Display for WriteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for WriteError {}

/// Size and CRC-32 (IEEE, as zlib and `crc32` tools compute it) of a written file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileDigest {
    /// Size of the file \[bytes\].
    pub bytes: u64,
    /// CRC-32 of its contents.
    pub crc32: u32,
}

impl FileDigest {
    /// Reads `path` and computes its digest (for verifying a file against a manifest); only a
    /// regular file within [`crate::safe_read::Limit::Chunk`] is read.
    pub fn of_file(path: &Path) -> std::io::Result<FileDigest> {
        use std::io::Read;
        let (mut f, _) = crate::safe_read::open(path, crate::safe_read::Limit::Chunk)
            .map_err(std::io::Error::other)?;
        let mut h = crc32fast::Hasher::new();
        let mut buf = vec![0u8; 1 << 16];
        let mut bytes = 0u64;
        loop {
            let n = f.read(&mut buf)?;
            if n == 0 {
                break;
            }
            h.update(&buf[..n]);
            bytes += n as u64;
        }
        Ok(FileDigest {
            bytes,
            crc32: h.finalize(),
        })
    }
}

/// A file that digests what is written through it.
struct DigestingFile {
    file: NewFile,
    hasher: crc32fast::Hasher,
    bytes: u64,
}

impl Write for DigestingFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.file.write(buf)?;
        self.hasher.update(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

/// The zstd level of every file. Higher levels shrink the explore chunks by well under 1% (level
/// 9: 0.3%) for several times the compression time (docs/book/src/maintainers/benchmarks.md#output-size).
pub(crate) const ZSTD_LEVEL: i32 = 3;

/// Whether a column is dictionary-encoded: names (wheel, variant, class, method, reason) and
/// integers (few distinct values per file) are; floating-point values are written plain. Most
/// floats of a row are distinct to the last bit, so a dictionary holds each value once more
/// beside its index; where a value repeats (a sample's inputs on both wheels' rows), zstd finds
/// the repeat in the plain bytes as well (docs/book/src/maintainers/benchmarks.md#output-size). Byte-stream-split
/// encoding measured larger still: it cuts the repeated 8-byte values apart.
fn dictionary_encoded(data: &ColumnData) -> bool {
    !matches!(data, ColumnData::F64(_) | ColumnData::F32(_))
}

/// Streams row groups into one Parquet file. The file is written under a temporary name and
/// renamed on [`TableWriter::finish`] after an fsync, so a half-written file is never taken for
/// a result.
pub(crate) struct TableWriter {
    writer: SerializedFileWriter<DigestingFile>,
    path: PathBuf,
}

impl TableWriter {
    /// Creates the file with the schema of `template` (names, types, units) and `metadata`.
    pub fn create(
        path: &Path,
        template: &[Column],
        metadata: &[(String, String)],
    ) -> Result<Self, WriteError> {
        let err = |e: &dyn std::fmt::Display| WriteError(format!("{}: {e}", path.display()));
        let mut fields = String::new();
        for c in template {
            let logical = if matches!(c.data, ColumnData::Str(_)) {
                " (UTF8)"
            } else {
                ""
            };
            fields.push_str(&format!(
                "REQUIRED {} {}{logical}; ",
                physical(&c.data),
                c.name
            ));
        }
        let schema_text = format!("message polywear {{ {fields}}}");
        let schema = Arc::new(parse_message_type(&schema_text).map_err(|e| err(&e))?);
        let units: serde_json::Map<String, serde_json::Value> = template
            .iter()
            .filter(|c| !c.unit.is_empty())
            .map(|c| (c.name.clone(), serde_json::Value::from(c.unit)))
            .collect();
        let mut kv: Vec<KeyValue> = metadata
            .iter()
            .map(|(k, v)| KeyValue::new(k.clone(), v.clone()))
            .collect();
        kv.push(KeyValue::new(
            "units".to_string(),
            serde_json::Value::Object(units).to_string(),
        ));
        // Columns kept under an old name for one version: {"old": "new", ...}.
        let deprecated =
            polywear_core::records::deprecated_columns(template.iter().map(|c| c.name.as_str()));
        if !deprecated.is_empty() {
            let map: serde_json::Map<String, serde_json::Value> = deprecated
                .into_iter()
                .map(|(old, new)| (old, serde_json::Value::from(new)))
                .collect();
            kv.push(KeyValue::new(
                "deprecated".to_string(),
                serde_json::Value::Object(map).to_string(),
            ));
        }
        let mut props = WriterProperties::builder()
            .set_compression(Compression::ZSTD(
                ZstdLevel::try_new(ZSTD_LEVEL).expect("valid level"),
            ))
            .set_dictionary_enabled(false)
            .set_key_value_metadata(Some(kv))
            .set_created_by(format!("polywear {}", crate::provenance::POLYWEAR_VERSION));
        for c in template.iter().filter(|c| dictionary_encoded(&c.data)) {
            props = props.set_column_dictionary_enabled(ColumnPath::from(c.name.as_str()), true);
        }
        let props = props.build();
        let file = DigestingFile {
            file: NewFile::create(path).map_err(|e| err(&e))?,
            hasher: crc32fast::Hasher::new(),
            bytes: 0,
        };
        let writer =
            SerializedFileWriter::new(file, schema, Arc::new(props)).map_err(|e| err(&e))?;
        Ok(TableWriter {
            writer,
            path: path.to_path_buf(),
        })
    }

    /// Appends one row group; columns must match the template in order and type.
    pub fn write(&mut self, columns: &[Column]) -> Result<(), WriteError> {
        let path = self.path.display().to_string();
        let err = |e: &dyn std::fmt::Display| WriteError(format!("{path}: {e}"));
        let mut rg = self.writer.next_row_group().map_err(|e| err(&e))?;
        let mut i = 0;
        while let Some(mut col) = rg.next_column().map_err(|e| err(&e))? {
            let c = columns
                .get(i)
                .ok_or_else(|| err(&"fewer columns than the schema"))?;
            match &c.data {
                ColumnData::F64(v) => col.typed::<DoubleType>().write_batch(v, None, None),
                ColumnData::F32(v) => col.typed::<FloatType>().write_batch(v, None, None),
                ColumnData::I64(v) => col.typed::<Int64Type>().write_batch(v, None, None),
                ColumnData::Str(v) => {
                    let b: Vec<ByteArray> = v.iter().map(|s| ByteArray::from(s.as_str())).collect();
                    col.typed::<ByteArrayType>().write_batch(&b, None, None)
                }
            }
            .map_err(|e| err(&format!("column {}: {e}", c.name)))?;
            col.close().map_err(|e| err(&e))?;
            i += 1;
        }
        rg.close().map_err(|e| err(&e))?;
        Ok(())
    }

    /// Writes the footer, fsyncs the file, moves it to its final name and fsyncs the directory.
    pub fn finish(self) -> Result<FileDigest, WriteError> {
        let path = self.path.display().to_string();
        let err = |e: &dyn std::fmt::Display| WriteError(format!("{path}: {e}"));
        let mut inner = self.writer.into_inner().map_err(|e| err(&e))?;
        inner.flush().map_err(|e| err(&e))?;
        let digest = FileDigest {
            bytes: inner.bytes,
            crc32: inner.hasher.finalize(),
        };
        inner.file.commit_durably().map_err(|e| err(&e))?;
        Ok(digest)
    }
}

/// Writes a whole table as one row group.
pub fn write_table(
    path: &Path,
    columns: &[Column],
    metadata: &[(String, String)],
) -> Result<(), WriteError> {
    write_table_digest(path, columns, metadata).map(|_| ())
}

/// Writes a whole table as one row group and returns the written file's size and CRC-32.
pub(crate) fn write_table_digest(
    path: &Path,
    columns: &[Column],
    metadata: &[(String, String)],
) -> Result<FileDigest, WriteError> {
    let mut w = TableWriter::create(path, columns, metadata)?;
    w.write(columns)?;
    w.finish()
}

/// Writes the same table as CSV through the `csv` crate (RFC 4180 quoting, `\n` line ends): a
/// field holding a comma, a double quote or a line break is quoted, with inner quotes doubled;
/// numbers are written in full precision ([`polywear_core::wording::data_number`]: the shortest
/// digits that read back exactly, `1e300` rather than 301 digits, `NaN` for a missing value).
pub fn write_csv(path: &Path, columns: &[Column]) -> Result<(), WriteError> {
    let err = |e: &dyn std::fmt::Display| WriteError(format!("{}: {e}", path.display()));
    let file = NewFile::create(path).map_err(|e| err(&e))?;
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(std::io::BufWriter::new(file));
    w.write_record(columns.iter().map(|c| c.name.as_str()))
        .map_err(|e| err(&e))?;
    let n = columns.first().map_or(0, |c| c.data.len());
    for row in 0..n {
        let cells = columns.iter().map(|c| match &c.data {
            ColumnData::F64(v) => polywear_core::wording::data_number(v[row]),
            ColumnData::F32(v) => polywear_core::wording::data_number(f64::from(v[row])),
            ColumnData::I64(v) => v[row].to_string(),
            ColumnData::Str(v) => v[row].clone(),
        });
        w.write_record(cells).map_err(|e| err(&e))?;
    }
    let file = w
        .into_inner()
        .map_err(|e| err(&e.to_string()))?
        .into_inner()
        .map_err(|e| err(&e.error().to_string()))?;
    file.commit().map_err(|e| err(&e))
}

#[cfg(test)]
mod csv_tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_as_rfc_4180_says() {
        let path = std::env::temp_dir().join(format!("polywear-csv-{}.csv", std::process::id()));
        let texts = ["paper", "a,b", "say \"hi\"", "two\nlines", ""];
        let columns = [
            Column::str("text", texts.iter().map(|s| s.to_string()).collect()),
            Column::f64("x", "-", vec![0.1, 1e-7, f64::NAN, -2.0, 1e21]),
        ];
        write_csv(&path, &columns).unwrap();
        let written = std::fs::read_to_string(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(
            written,
            "text,x\npaper,0.1\n\"a,b\",1e-7\n\"say \"\"hi\"\"\",NaN\n\"two\nlines\",-2\n,1e21\n"
        );
    }
}
