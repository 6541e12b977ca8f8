//! The model against `reference/points.csv` (an independent implementation; MODEL.md,
//! "Reference values"): statics to 1e-9 relative, the leading eigenvalue to 1e-6, class,
//! amplitudes and frequency to 1%.

use polywear::classify::{classify_point, ClassifierOptions};
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear::records::WheelRecord;

struct Row {
    fields: Vec<(String, String)>,
}

impl Row {
    fn get(&self, k: &str) -> &str {
        &self.fields.iter().find(|(n, _)| n == k).unwrap().1
    }
    fn num(&self, k: &str) -> f64 {
        self.get(k).parse().unwrap()
    }
}

fn reference_rows() -> Vec<Row> {
    let text = include_str!("data/points.csv");
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| Row {
            fields: header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect(),
        })
        .collect()
}

fn record_for(row: &Row) -> WheelRecord {
    let p = Params {
        speed_kmh: row.num("speed_kmh"),
        toe_deg: row.num("toe_deg"),
        load_n: row.num("load_n"),
        pressure_kpa: row.num("pressure_kpa"),
        ..Params::default()
    };
    let wheel: Wheel = row.get("wheel").parse().unwrap();
    let variant: Variant = row.get("variant").parse().unwrap();
    let (model, verdict) = classify_point(&p, wheel, variant, &ClassifierOptions::default());
    WheelRecord::new(&p, wheel, variant, &model, &verdict)
}

fn field(r: &WheelRecord, k: &str) -> f64 {
    let v = serde_json::to_value(r).unwrap();
    v[k].as_f64().unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        a.abs()
    } else {
        ((a - b) / b).abs()
    }
}

#[test]
fn reference_file_is_complete() {
    let rows = reference_rows();
    assert_eq!(rows.len(), 16);
    assert!(rows.iter().any(|r| r.get("class") == "limit_cycle"));
    assert!(rows.iter().any(|r| r.get("class") == "stable"));
}

#[test]
fn static_quantities_match_to_1e9() {
    for row in reference_rows() {
        let rec = record_for(&row);
        for k in [
            "deflection_m",
            "contact_length_m",
            "contact_width_m",
            "k_s",
            "tread_mass_kg",
            "slip_ratio",
            "q",
            "f_m",
            "f_s",
            "z0_m",
            "y0_m",
        ] {
            let (got, want) = (field(&rec, k), row.num(k));
            assert!(
                rel(got, want) < 1e-9,
                "{k} at {} {} V={}: got {got}, want {want}",
                row.get("wheel"),
                row.get("variant"),
                row.get("speed_kmh")
            );
        }
    }
}

#[test]
fn leading_eigenvalue_matches_to_1e6() {
    for row in reference_rows() {
        let rec = record_for(&row);
        for k in ["eig_re_max", "eig_freq_hz"] {
            let (got, want) = (field(&rec, k), row.num(k));
            assert!(rel(got, want) < 1e-6, "{k}: got {got}, want {want}");
        }
    }
}

#[test]
fn class_amplitude_and_frequency_match_to_one_percent() {
    for row in reference_rows() {
        let rec = record_for(&row);
        assert_eq!(rec.class, row.get("class"), "class at {:?}", row.fields);
        for k in ["amp_y_m", "amp_v_mps", "freq_hz", "polygon_order"] {
            let (got, want) = (field(&rec, k), row.num(k));
            assert!(
                rel(got, want) < 0.01,
                "{k}: got {got}, want {want} at {:?}",
                row.fields
            );
        }
    }
}
