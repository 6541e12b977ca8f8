//! Reads Parquet files back as text rows, for comparing outputs in tests.

use std::path::Path;

use parquet::file::reader::{FileReader, SerializedFileReader};

/// The chunk files (`*.parquet` not named `_*`) of `dirs`, sorted by file name: the run's own
/// files (`_calibration_band.parquet`) are not rows, as pandas reads it.
pub fn chunk_files(dirs: &[&Path]) -> Vec<std::path::PathBuf> {
    let mut files: Vec<std::path::PathBuf> = dirs
        .iter()
        .flat_map(|d| std::fs::read_dir(d).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| {
            p.extension().is_some_and(|e| e == "parquet")
                && !p.file_name().unwrap().to_string_lossy().starts_with('_')
        })
        .collect();
    files.sort_by_key(|p| p.file_name().unwrap().to_owned());
    files
}

/// Every row of every chunk in `dir`, sorted by file name, as text.
pub fn rows_in_dir(dirs: &[&Path]) -> Vec<String> {
    let mut rows = Vec::new();
    for f in chunk_files(dirs) {
        let reader = SerializedFileReader::new(std::fs::File::open(&f).unwrap()).unwrap();
        for row in reader.get_row_iter(None).unwrap() {
            rows.push(row.unwrap().to_string());
        }
    }
    rows
}

/// Every row of every chunk in `dir`, each as a map from column name to value.
#[allow(dead_code)]
pub fn chunk_rows(dir: &Path) -> Vec<std::collections::HashMap<String, parquet::record::Field>> {
    chunk_files(&[dir]).iter().flat_map(|f| rows(f)).collect()
}

/// Every row of one Parquet file as a map from column name to value.
#[allow(dead_code)]
pub fn rows(file: &Path) -> Vec<std::collections::HashMap<String, parquet::record::Field>> {
    let reader = SerializedFileReader::new(std::fs::File::open(file).unwrap()).unwrap();
    reader
        .get_row_iter(None)
        .unwrap()
        .map(|row| {
            row.unwrap()
                .get_column_iter()
                .map(|(name, field)| (name.clone(), field.clone()))
                .collect()
        })
        .collect()
}

/// The value of key `key` in a Parquet file's footer metadata, if it has one.
pub fn footer_value(file: &Path, key: &str) -> Option<String> {
    let reader = SerializedFileReader::new(std::fs::File::open(file).unwrap()).unwrap();
    let kv = reader
        .metadata()
        .file_metadata()
        .key_value_metadata()?
        .clone();
    kv.into_iter().find(|k| k.key == key).and_then(|k| k.value)
}

/// The JSON value of key `key` in a Parquet file's footer metadata (panics if absent).
pub fn footer_json(file: &Path, key: &str) -> serde_json::Value {
    serde_json::from_str(&footer_value(file, key).unwrap()).unwrap()
}
