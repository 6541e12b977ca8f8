//! Parquet output through the low-level column API (no Arrow): typed columns, one row group per
//! chunk so memory stays bounded, and key–value metadata (study, seed, variant, parameters,
//! program version, units) in the file footer. Files open in polars, pandas/pyarrow and DuckDB.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use parquet::basic::{Compression, ZstdLevel};
use parquet::data_type::{ByteArray, ByteArrayType, DoubleType, Int64Type};
use parquet::file::metadata::KeyValue;
use parquet::file::properties::WriterProperties;
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::parser::parse_message_type;

/// The values of one column in one row group.
#[derive(Debug, Clone, PartialEq)]
pub enum ColumnData {
    F64(Vec<f64>),
    I64(Vec<i64>),
    Str(Vec<String>),
}

impl ColumnData {
    pub fn len(&self) -> usize {
        match self {
            ColumnData::F64(v) => v.len(),
            ColumnData::I64(v) => v.len(),
            ColumnData::Str(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn physical(&self) -> &'static str {
        match self {
            ColumnData::F64(_) => "DOUBLE",
            ColumnData::I64(_) => "INT64",
            ColumnData::Str(_) => "BYTE_ARRAY",
        }
    }
}

/// A named column with its unit ("" for none), as written to the schema and the `units` metadata.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    pub name: String,
    pub unit: &'static str,
    pub data: ColumnData,
}

impl Column {
    pub fn f64(name: impl Into<String>, unit: &'static str, data: Vec<f64>) -> Self {
        Column {
            name: name.into(),
            unit,
            data: ColumnData::F64(data),
        }
    }
    pub fn i64(name: impl Into<String>, unit: &'static str, data: Vec<i64>) -> Self {
        Column {
            name: name.into(),
            unit,
            data: ColumnData::I64(data),
        }
    }
    pub fn str(name: impl Into<String>, data: Vec<String>) -> Self {
        Column {
            name: name.into(),
            unit: "",
            data: ColumnData::Str(data),
        }
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

/// Streams row groups into one Parquet file. The file is written under a temporary name and
/// renamed on [`TableWriter::finish`], so a half-written file is never taken for a result.
pub struct TableWriter {
    writer: SerializedFileWriter<File>,
    path: PathBuf,
    tmp_path: PathBuf,
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
                c.data.physical(),
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
        let props = WriterProperties::builder()
            .set_compression(Compression::ZSTD(
                ZstdLevel::try_new(3).expect("valid level"),
            ))
            .set_key_value_metadata(Some(kv))
            .set_created_by(format!("polywear {}", env!("CARGO_PKG_VERSION")))
            .build();
        // A leading underscore hides the unfinished file from pyarrow/pandas directory reads.
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let tmp_path = path.with_file_name(format!("_{name}.partial"));
        let file = File::create(&tmp_path).map_err(|e| err(&e))?;
        let writer =
            SerializedFileWriter::new(file, schema, Arc::new(props)).map_err(|e| err(&e))?;
        Ok(TableWriter {
            writer,
            path: path.to_path_buf(),
            tmp_path,
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

    /// Writes the footer and moves the file to its final name.
    pub fn finish(self) -> Result<(), WriteError> {
        let path = self.path.display().to_string();
        self.writer
            .close()
            .map_err(|e| WriteError(format!("{path}: {e}")))?;
        std::fs::rename(&self.tmp_path, &self.path)
            .map_err(|e| WriteError(format!("{path}: {e}")))?;
        Ok(())
    }
}

/// Writes a whole table as one row group.
pub fn write_table(
    path: &Path,
    columns: &[Column],
    metadata: &[(String, String)],
) -> Result<(), WriteError> {
    let mut w = TableWriter::create(path, columns, metadata)?;
    w.write(columns)?;
    w.finish()
}

/// Writes the same table as CSV (RFC 4180 quoting, `\n` line ends): a field holding a comma, a
/// double quote, a line break or leading/trailing space is quoted, with inner quotes doubled;
/// numbers are written in full precision (`NaN` for a missing value).
pub fn write_csv(path: &Path, columns: &[Column]) -> Result<(), WriteError> {
    use std::io::Write;
    let err = |e: std::io::Error| WriteError(format!("{}: {e}", path.display()));
    let mut f = std::io::BufWriter::new(File::create(path).map_err(err)?);
    let header: Vec<String> = columns.iter().map(|c| csv_field(&c.name)).collect();
    writeln!(f, "{}", header.join(",")).map_err(err)?;
    let n = columns.first().map_or(0, |c| c.data.len());
    for row in 0..n {
        let cells: Vec<String> = columns
            .iter()
            .map(|c| match &c.data {
                ColumnData::F64(v) => format!("{}", v[row]),
                ColumnData::I64(v) => v[row].to_string(),
                ColumnData::Str(v) => csv_field(&v[row]),
            })
            .collect();
        writeln!(f, "{}", cells.join(",")).map_err(err)?;
    }
    f.flush().map_err(err)
}

/// One CSV field, quoted when RFC 4180 requires it (and around leading/trailing spaces).
pub fn csv_field(s: &str) -> String {
    let needs = s.contains([',', '"', '\n', '\r'])
        || s.starts_with(char::is_whitespace)
        || s.ends_with(char::is_whitespace);
    if needs {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod csv_tests {
    use super::*;

    #[test]
    fn csv_fields_are_quoted_as_rfc_4180_says() {
        assert_eq!(csv_field("paper"), "paper");
        assert_eq!(csv_field("a,b"), "\"a,b\"");
        assert_eq!(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(csv_field("two\nlines"), "\"two\nlines\"");
        assert_eq!(csv_field(" padded"), "\" padded\"");
        assert_eq!(csv_field(""), "");
    }
}
