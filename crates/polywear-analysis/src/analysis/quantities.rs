//! The quantities of the rows that the report shows in engineering units: the severity of a
//! vibration (amplitudes, energy, polygon order), each a column of the record table with the
//! title and unit people read it in.

use polywear_core::records::RecordColumn;

/// A severity quantity: its column (in SI units, as the rows hold it) and how people read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Quantity {
    /// The column (its name and SI unit, as the rows hold it, from the column table).
    pub column: RecordColumn,
    /// What it is, in words, for titles and tables.
    pub title: &'static str,
    /// The engineering unit it is shown in ("" for a pure number).
    pub shown_unit: &'static str,
    /// Shown value = SI value × `scale`.
    pub scale: f64,
}

impl Quantity {
    /// The column's name.
    pub const fn name(&self) -> &'static str {
        self.column.name()
    }

    /// The column's SI unit.
    pub const fn unit(&self) -> &'static str {
        self.column.unit()
    }

    /// "Lateral displacement amplitude \[µm\]", or the title alone for a pure number.
    pub fn label(&self) -> String {
        if self.shown_unit.is_empty() {
            self.title.to_string()
        } else {
            format!("{} [{}]", self.title, self.shown_unit)
        }
    }
}

/// The severity quantities, as `simulate` prints them (µm, mm/s, µJ).
pub(crate) const SEVERITY_QUANTITIES: [Quantity; 4] = [
    Quantity {
        column: RecordColumn::AmpYM,
        title: "Lateral displacement amplitude",
        shown_unit: "µm",
        scale: 1e6,
    },
    Quantity {
        column: RecordColumn::AmpVMps,
        title: "Lateral velocity amplitude",
        shown_unit: "mm/s",
        scale: 1e3,
    },
    Quantity {
        column: RecordColumn::EnergyPerCycleJ,
        title: "Vibration energy per cycle",
        shown_unit: "µJ",
        scale: 1e6,
    },
    Quantity {
        column: RecordColumn::PolygonOrder,
        title: "Polygon order (wear facets)",
        shown_unit: "",
        scale: 1.0,
    },
];

/// The quantity of column `column`.
pub(crate) fn quantity(column: &str) -> Option<&'static Quantity> {
    SEVERITY_QUANTITIES.iter().find(|q| q.name() == column)
}
