//! Numeric tables that users bring: measured operating points (a study's `[operating_points]`)
//! and drive cycles (`polywear cycle`). A CSV file with a header line, or a Parquet file, read
//! completely into plain numbers before any work; every refusal names the file, the row and the
//! column, so a telematics export can be fixed where it is wrong.

use std::path::{Path, PathBuf};

use crate::safe_read::{self, Limit, ReadError};
use polywear_core::wording::{snippet, thousands};

/// A table of finite numbers with named columns.
#[derive(Debug, Clone, PartialEq)]
pub struct NumericTable {
    /// The file the table was read from (named in every error).
    pub path: PathBuf,
    /// Column names, in file order (unique).
    pub columns: Vec<String>,
    /// `rows[i][j]`: data row i (0-based; row i + 1 in messages) of column j.
    pub rows: Vec<Vec<f64>>,
    /// For a CSV file, the line number of each data row (messages say it beside the row).
    lines: Vec<usize>,
    /// The columns read as text ([`NumericTable::read_with_text`]): `(column, cells)`, each
    /// cell as written (`rows[i][column]` holds its number where it is one, NaN otherwise).
    pub text: Vec<(usize, Vec<String>)>,
    /// FNV-1a 64 of the file's bytes, as 16 hex digits, and their count.
    pub hash: String,
    /// The file's size in bytes.
    pub bytes: u64,
}

/// A refusal, naming the file and, where it applies, the row and column (`at`: "FILE, row R
/// (line L), column `NAME`", as [`NumericTable::at`] words it).
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    /// The file cannot be read: absent, not a regular file, or larger than a table may be.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A CSV file that is not UTF-8 text.
    #[error("{}: not UTF-8 text: {source}", path.display())]
    NotUtf8 {
        /// The file.
        path: PathBuf,
        /// Where the text breaks.
        source: std::str::Utf8Error,
    },
    /// The CSV reader failed.
    #[error("{}: {source}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// The reader's error.
        source: csv::Error,
    },
    /// No header line.
    #[error("{}: empty file (expected a header line, then one row per line)", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// A header without data rows.
    #[error("{}: no rows (only the header line)", path.display())]
    NoRows {
        /// The file.
        path: PathBuf,
    },
    /// A quoted field that is never closed.
    #[error("{}, line {line}: a quoted field starts here and is never closed (unterminated `\"`)", path.display())]
    UnterminatedQuote {
        /// The file.
        path: PathBuf,
        /// The line of the opening quote, counted from 1.
        line: usize,
    },
    /// A header cell that cannot be a column name: the file is likely not a table at all.
    #[error("{}: header, column {number}: {} is not a column name (at most 40 characters, no control characters); is this a CSV file with a header line?", path.display(), snippet(name))]
    NotAName {
        /// The file.
        path: PathBuf,
        /// The column, counted from 1.
        number: usize,
        /// The cell (quoted in part only).
        name: String,
    },
    /// A column without a name.
    #[error("{}: header, column {number}: empty column name", path.display())]
    EmptyColumnName {
        /// The file.
        path: PathBuf,
        /// The column, counted from 1.
        number: usize,
    },
    /// A column name given twice.
    #[error("{}: header, column `{name}` appears twice (columns {first} and {second})", path.display())]
    RepeatedColumn {
        /// The file.
        path: PathBuf,
        /// The name.
        name: String,
        /// Its first column, counted from 1.
        first: usize,
        /// Its second column, counted from 1.
        second: usize,
    },
    /// A row whose cell count differs from the header's.
    #[error("{row}: {cells} cells, the header has {columns} columns")]
    CellCount {
        /// File and row.
        row: String,
        /// Cells in the row.
        cells: usize,
        /// Columns in the header.
        columns: usize,
    },
    /// An empty cell.
    #[error("{at}: empty cell")]
    EmptyCell {
        /// File, row and column.
        at: String,
    },
    /// A cell that is not a number.
    #[error("{at}: {} is not a number", snippet(text))]
    NotANumber {
        /// File, row and column.
        at: String,
        /// The cell.
        text: String,
    },
    /// NaN or an infinity.
    #[error("{at}: {value} is not a finite number (NaN and inf are refused)")]
    NotFinite {
        /// File, row and column.
        at: String,
        /// The value.
        value: f64,
    },
    /// A Parquet file that cannot be read as a flat table of numbers.
    #[error("{}: {message}", path.display())]
    Parquet {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A Parquet cell without a value.
    #[error("{at}: missing value")]
    MissingValue {
        /// File, row and column.
        at: String,
    },
    /// A Parquet column of another type than numbers.
    #[error(
        "{at}: {} is not a number (the column must be numeric)",
        snippet(value)
    )]
    NotNumeric {
        /// File, row and column.
        at: String,
        /// The cell as Parquet prints it.
        value: String,
    },
    /// More data rows than the reader accepts (counted before any cell is read).
    #[error("{}: {} rows; accepted at most {} ({what})", path.display(), thousands(*rows as f64), thousands(*max as f64))]
    TooManyRows {
        /// The file.
        path: PathBuf,
        /// Its data rows (for a CSV file, its non-blank lines after the header).
        rows: u64,
        /// The most accepted.
        max: u64,
        /// Why, in the caller's words.
        what: &'static str,
    },
    /// A nested or repeated Parquet column.
    #[error("{row}: nested or repeated columns are not supported")]
    Nested {
        /// File and row.
        row: String,
    },
}

impl NumericTable {
    /// Reads `path`: Parquet when it ends in `.parquet`, CSV otherwise; only a regular file
    /// within [`Limit::Table`] is read.
    pub fn read(path: &Path) -> Result<NumericTable, TableError> {
        Self::read_with_text(path, &|_| false)
    }

    /// [`NumericTable::read`], with the columns whose name `text` accepts kept as text
    /// (identifiers, labels, or columns the caller judges by name first): their cells need not
    /// be numbers, and are kept as written.
    pub fn read_with_text(
        path: &Path,
        text: &dyn Fn(&str) -> bool,
    ) -> Result<NumericTable, TableError> {
        Self::read_at_most(path, text, None)
    }

    /// [`NumericTable::read_with_text`], refusing a file of more than `max.0` data rows before
    /// any cell is read (so a huge file costs a scan, not its cells' memory); `max.1` says why
    /// in the refusal.
    pub fn read_at_most(
        path: &Path,
        text: &dyn Fn(&str) -> bool,
        max: Option<(u64, &'static str)>,
    ) -> Result<NumericTable, TableError> {
        let bytes = safe_read::read_bytes(path, Limit::Table)?;
        let hash = bytes_hash(&bytes);
        let n = bytes.len() as u64;
        let is_parquet = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("parquet"));
        if let Some((max, what)) = max {
            let rows = if is_parquet {
                parquet_rows(path)?
            } else {
                csv_data_lines(&bytes)
            };
            if rows > max {
                return Err(TableError::TooManyRows {
                    path: path.to_path_buf(),
                    rows,
                    max,
                    what,
                });
            }
        }
        let mut t = if is_parquet {
            read_parquet(path, text)?
        } else {
            read_csv(path, &bytes, text)?
        };
        t.hash = hash;
        t.bytes = n;
        Ok(t)
    }

    /// "row 3 (line 4)" for a CSV file, "row 3" for Parquet: data rows counted from 1.
    pub fn row_name(&self, row: usize) -> String {
        match self.lines.get(row) {
            Some(line) => format!("row {} (line {line})", row + 1),
            None => format!("row {}", row + 1),
        }
    }

    /// The start of a message about one cell: `FILE, row R (line L), column `NAME``.
    pub fn at(&self, row: usize, column: usize) -> String {
        format!(
            "{}, {}, column `{}`",
            self.path.display(),
            self.row_name(row),
            self.columns[column]
        )
    }

    /// The index of column `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The cells of column `j` as text, when it was read as text.
    pub fn text_of(&self, j: usize) -> Option<&[String]> {
        self.text
            .iter()
            .find(|(k, _)| *k == j)
            .map(|(_, cells)| cells.as_slice())
    }
}

/// The text columns' indices among `columns`, each with an empty cell list.
fn text_columns(columns: &[String], text: &dyn Fn(&str) -> bool) -> Vec<(usize, Vec<String>)> {
    columns
        .iter()
        .enumerate()
        .filter(|(_, c)| text(c))
        .map(|(j, _)| (j, Vec::new()))
        .collect()
}

/// A Parquet cell's number, where it is one.
fn number_of(field: &parquet::record::Field) -> Option<f64> {
    use parquet::record::Field;
    Some(match field {
        Field::Double(x) => *x,
        Field::Float(x) => f64::from(*x),
        Field::Byte(x) => f64::from(*x),
        Field::Short(x) => f64::from(*x),
        Field::Int(x) => f64::from(*x),
        Field::Long(x) => *x as f64,
        Field::UByte(x) => f64::from(*x),
        Field::UShort(x) => f64::from(*x),
        Field::UInt(x) => f64::from(*x),
        Field::ULong(x) => *x as f64,
        _ => return None,
    })
}

/// A CSV file's non-blank lines after the first: its data rows, or more where a quoted field
/// holds a line break (an upper bound is what a row limit needs).
fn csv_data_lines(bytes: &[u8]) -> u64 {
    let lines = bytes
        .split(|b| *b == b'\n')
        .filter(|l| l.iter().any(|b| !b.is_ascii_whitespace()))
        .count() as u64;
    lines.saturating_sub(1)
}

/// A Parquet file's row count, from its footer.
fn parquet_rows(path: &Path) -> Result<u64, TableError> {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    let (f, _) = safe_read::open(path, Limit::Table)?;
    let reader = SerializedFileReader::new(f).map_err(|err| TableError::Parquet {
        path: path.to_path_buf(),
        message: err.to_string(),
    })?;
    Ok(reader.metadata().file_metadata().num_rows().max(0) as u64)
}

/// A text cell's number, where it is a finite one (NaN otherwise).
fn number_in(cell: &str) -> f64 {
    cell.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .unwrap_or(f64::NAN)
}

/// 64-bit FNV-1a of bytes, as 16 hex digits: a fingerprint that tells a changed file, not a
/// cryptographic hash.
pub fn bytes_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// A header cell or a data cell without its quotes and surrounding blanks.
fn cell(s: &str) -> &str {
    let s = s.trim();
    s.strip_prefix('"')
        .and_then(|x| x.strip_suffix('"'))
        .map_or(s, str::trim)
}

/// Whether a header cell can be a column name: a parameter's name, or a weight column's as
/// people write it (`hours`, `Stunden (h)`), at most 40 characters without control characters.
/// The first line of a file that is no table (a password file's entry, a binary) is not, and is
/// then never quoted in full.
fn is_column_name(name: &str) -> bool {
    name.chars().count() <= 40 && !name.chars().any(char::is_control)
}

/// Checks the header: no empty, no repeated name, and each a name.
fn check_header(path: &Path, columns: &[String]) -> Result<(), TableError> {
    for (j, name) in columns.iter().enumerate() {
        if !name.is_empty() && !is_column_name(name) {
            return Err(TableError::NotAName {
                path: path.to_path_buf(),
                number: j + 1,
                name: name.clone(),
            });
        }
        if name.is_empty() {
            return Err(TableError::EmptyColumnName {
                path: path.to_path_buf(),
                number: j + 1,
            });
        }
        if let Some(k) = columns[..j].iter().position(|c| c == name) {
            return Err(TableError::RepeatedColumn {
                path: path.to_path_buf(),
                name: name.clone(),
                first: k + 1,
                second: j + 1,
            });
        }
    }
    Ok(())
}

/// The records of a CSV text with the line each starts on, blank lines left out; the fields
/// are split by the `csv` crate (RFC 4180: quoted fields may hold commas, quotes and line
/// breaks), each then trimmed and stripped of surrounding quotes.
pub(crate) fn csv_records(
    path: &Path,
    text: &str,
) -> Result<Vec<(usize, Vec<String>)>, TableError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some(line) = unterminated_quote(text) {
        return Err(TableError::UnterminatedQuote {
            path: path.to_path_buf(),
            line,
        });
    }
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut out = Vec::new();
    // Line breaks before byte `counted`, counted once for the whole file.
    let (mut counted, mut newlines) = (0usize, 0usize);
    for record in reader.records() {
        let record = record.map_err(|source| TableError::Csv {
            path: path.to_path_buf(),
            source,
        })?;
        if record.len() == 1 && record[0].trim().is_empty() {
            continue;
        }
        // The line the record's first field is on: the reader's own line count leaves out the
        // blank lines it skips, so it is counted from the record's byte offset.
        let start = record.position().map_or(0, |p| p.byte() as usize);
        let first = start
            + text.as_bytes()[start.min(text.len())..]
                .iter()
                .take_while(|b| matches!(b, b'\r' | b'\n'))
                .count();
        let first = first.min(text.len());
        newlines += text.as_bytes()[counted..first]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        counted = first;
        let line = 1 + newlines;
        out.push((line, record.iter().map(|c| cell(c).to_string()).collect()));
    }
    Ok(out)
}

/// The line of a quote that opens a field and is never closed, read as RFC 4180 and the `csv`
/// crate read it: a quote opens a field only at its start, `""` inside is a quote, and a quote
/// elsewhere in an unquoted field is text. The reader itself takes such a field to the end of
/// the file, which would be reported as a row with too few cells.
fn unterminated_quote(text: &str) -> Option<usize> {
    let (mut line, mut opened_on) = (1usize, 0usize);
    let (mut at_field_start, mut quoted) = (true, false);
    let mut bytes = text.bytes().peekable();
    while let Some(b) = bytes.next() {
        if quoted {
            if b == b'"' {
                if bytes.peek() == Some(&b'"') {
                    bytes.next();
                } else {
                    quoted = false;
                }
            }
        } else if b == b'"' && at_field_start {
            quoted = true;
            opened_on = line;
        }
        at_field_start = !quoted && matches!(b, b',' | b'\n' | b'\r');
        if b == b'\n' {
            line += 1;
        }
    }
    quoted.then_some(opened_on)
}

fn read_csv(
    path: &Path,
    bytes: &[u8],
    text_names: &dyn Fn(&str) -> bool,
) -> Result<NumericTable, TableError> {
    let text = std::str::from_utf8(bytes).map_err(|source| TableError::NotUtf8 {
        path: path.to_path_buf(),
        source,
    })?;
    let mut lines = csv_records(path, text)?.into_iter();
    let Some((_, columns)) = lines.next() else {
        return Err(TableError::Empty {
            path: path.to_path_buf(),
        });
    };
    check_header(path, &columns)?;
    let mut t = NumericTable {
        path: path.to_path_buf(),
        text: text_columns(&columns, text_names),
        columns,
        rows: Vec::new(),
        lines: Vec::new(),
        hash: String::new(),
        bytes: 0,
    };
    for (line, cells) in lines {
        let row = t.rows.len();
        t.lines.push(line);
        if cells.len() != t.columns.len() {
            return Err(TableError::CellCount {
                row: format!("{}, {}", path.display(), t.row_name(row)),
                cells: cells.len(),
                columns: t.columns.len(),
            });
        }
        let mut values = Vec::with_capacity(cells.len());
        for (j, c) in cells.iter().enumerate() {
            if let Some((_, kept)) = t.text.iter_mut().find(|(k, _)| *k == j) {
                kept.push(c.clone());
                values.push(number_in(c));
                continue;
            }
            let x: f64 = c.parse().map_err(|_| {
                if c.is_empty() {
                    TableError::EmptyCell { at: t.at(row, j) }
                } else {
                    TableError::NotANumber {
                        at: t.at(row, j),
                        text: c.clone(),
                    }
                }
            })?;
            if !x.is_finite() {
                return Err(TableError::NotFinite {
                    at: t.at(row, j),
                    value: x,
                });
            }
            values.push(x);
        }
        t.rows.push(values);
    }
    if t.rows.is_empty() {
        return Err(TableError::NoRows {
            path: path.to_path_buf(),
        });
    }
    Ok(t)
}

fn read_parquet(
    path: &Path,
    text_names: &dyn Fn(&str) -> bool,
) -> Result<NumericTable, TableError> {
    use parquet::file::reader::{FileReader, SerializedFileReader};
    use parquet::record::Field;
    let e = |m: &dyn std::fmt::Display| TableError::Parquet {
        path: path.to_path_buf(),
        message: m.to_string(),
    };
    let (f, _) = safe_read::open(path, Limit::Table)?;
    let reader = SerializedFileReader::new(f).map_err(|err| e(&err))?;
    let schema = reader.metadata().file_metadata().schema_descr();
    let columns: Vec<String> = schema.columns().iter().map(|c| c.path().string()).collect();
    if columns.is_empty() {
        return Err(e(&"empty file (no columns)"));
    }
    check_header(path, &columns)?;
    let mut t = NumericTable {
        path: path.to_path_buf(),
        text: text_columns(&columns, text_names),
        columns,
        rows: Vec::new(),
        lines: Vec::new(),
        hash: String::new(),
        bytes: 0,
    };
    for row in reader.get_row_iter(None).map_err(|err| e(&err))? {
        let row = row.map_err(|err| e(&err))?;
        let i = t.rows.len();
        let mut values = Vec::with_capacity(t.columns.len());
        for (j, (_, field)) in row.get_column_iter().enumerate() {
            if let Some((_, kept)) = t.text.iter_mut().find(|(k, _)| *k == j) {
                let cell = match field {
                    Field::Str(s) => s.clone(),
                    Field::Null => String::new(),
                    other => other.to_string(),
                };
                // A number keeps its exact value, not its text's.
                let x = number_of(field).filter(|x| x.is_finite());
                values.push(x.unwrap_or_else(|| number_in(&cell)));
                kept.push(cell);
                continue;
            }
            let x = match (number_of(field), field) {
                (Some(x), _) => x,
                (None, Field::Null) => return Err(TableError::MissingValue { at: t.at(i, j) }),
                (None, other) => {
                    return Err(TableError::NotNumeric {
                        at: t.at(i, j),
                        value: other.to_string(),
                    })
                }
            };
            if !x.is_finite() {
                return Err(TableError::NotFinite {
                    at: t.at(i, j),
                    value: x,
                });
            }
            values.push(x);
        }
        if values.len() != t.columns.len() {
            return Err(TableError::Nested {
                row: format!("{}, {}", path.display(), t.row_name(i)),
            });
        }
        t.rows.push(values);
    }
    if t.rows.is_empty() {
        return Err(e(&"no rows"));
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(name: &str, text: &str) -> Result<NumericTable, TableError> {
        let dir = std::env::temp_dir().join(format!("polywear-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        NumericTable::read(&p)
    }

    #[test]
    fn csv_reads_numbers_and_names_bad_cells() {
        let t = table("ok.csv", "\u{feff}a, \"b\"\r\n1,2\r\n\r\n3.5,-4e1\r\n").unwrap();
        assert_eq!(t.columns, vec!["a", "b"]);
        assert_eq!(t.rows, vec![vec![1.0, 2.0], vec![3.5, -40.0]]);
        assert_eq!(t.row_name(1), "row 2 (line 4)");
        // RFC 4180: a quoted field holds commas, doubled quotes and line breaks.
        let t = table("q.csv", "x,\"a,b\"\n\n\"1\",2\n\"3\n\",4\n5,6\n").unwrap();
        assert_eq!(t.columns, vec!["x", "a,b"]);
        assert_eq!(t.rows.len(), 3);
        assert_eq!(t.row_name(2), "row 3 (line 6)");
        let err = |name: &str, text: &str| table(name, text).unwrap_err().to_string();
        assert!(err("e1.csv", "").contains("empty file"));
        assert!(err("e2.csv", "a,b\n").contains("no rows"));
        let m = err("e3.csv", "a,b\n1,2\n1,NaN\n");
        assert!(
            m.contains("row 2 (line 3), column `b`") && m.contains("NaN"),
            "{m}"
        );
        let m = err("e4.csv", "a,b\n1,inf\n");
        assert!(m.contains("column `b`") && m.contains("finite"), "{m}");
        assert!(err("e5.csv", "a,a\n1,2\n").contains("`a` appears twice"));
        assert!(err("e6.csv", "a,b\n1\n").contains("1 cells"));
        assert!(err("e7.csv", "a,b\n1,x\n").contains("`x` is not a number"));
        let m = err("e8.csv", "a,b\n1,\"2\n3,4\n");
        assert!(m.contains("line 2") && m.contains("never closed"), "{m}");
        // A quote inside an unquoted field is text; doubled quotes inside a quoted one too.
        let m = err("e9.csv", "a,b\n1,2\"x\n\"3\"\"\",4\n");
        assert!(
            m.contains("is not a number") && !m.contains("closed"),
            "{m}"
        );
        let m = err(
            "e10.csv",
            "root:$6$saltsaltsaltsalt$hashhashhashhashhashhashhashhash:19000:0:99999:7:::\nbin:x:1\n",
        );
        assert!(
            m.contains("not a column name") && !m.contains("hash"),
            "{m}"
        );
    }

    #[test]
    fn text_columns_keep_their_cells_and_their_numbers() {
        let dir = std::env::temp_dir().join(format!("polywear-text-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.csv");
        std::fs::write(&p, "id,a,h\nVAN-1,1,2.5\n\"CAR, 3\",2,\n").unwrap();
        let t = NumericTable::read_with_text(&p, &|c| c != "a").unwrap();
        assert_eq!(t.text_of(0).unwrap(), ["VAN-1", "CAR, 3"]);
        assert_eq!(t.text_of(2).unwrap(), ["2.5", ""]);
        assert!(t.text_of(1).is_none());
        assert_eq!((t.rows[0][1], t.rows[0][2]), (1.0, 2.5));
        assert!(t.rows[1][0].is_nan() && t.rows[1][2].is_nan());
        // Read as numbers, the same file is refused at its first text cell.
        let e = NumericTable::read(&p).unwrap_err().to_string();
        assert!(
            e.contains("row 1 (line 2), column `id`: `VAN-1` is not a number"),
            "{e}"
        );
    }
}
