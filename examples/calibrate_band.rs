//! Regenerates the shipped calibration band (MODEL.md#the-calibration-band): the scrambled
//! Sobol design over the five calibrated constants' prior ranges, every point evaluated on the
//! shipped level and held to the field facts' targets
//! (`polywear_study::calibration_band::fit`), the accepted points shipped as the calibrated sets.
//!
//! ```sh
//! cargo run --release --example calibrate_band                  # 1024 points, 2000 samples
//! cargo run --release --example calibrate_band -- POINTS SAMPLES [BAND.toml] [DESIGN.csv]
//! cargo run --release --example calibrate_band -- --from-design DESIGN.csv [BAND.toml]
//! ```
//!
//! `--from-design` chooses the sets again from a design table already evaluated (the points'
//! figures as the table records them), without evaluating a point.
//!
//! It writes `data/calibration_band.toml` (the sets, the method, its settings, each constant's
//! prior range and the sentence that says where the accepted region lies) and
//! `data/calibration_design.csv` (every point with its target figures), and prints the time.

use std::time::Instant;

use polywear::params::Params;
use polywear_core::wear::FittedConstants;
use polywear_study::calibration_band::fit::{design_columns, fit, FitOptions};
use polywear_study::field_facts::FieldFacts;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |k: usize, default: u64| {
        args.get(k)
            .map(|a| a.parse::<f64>().expect("a number") as u64)
            .unwrap_or(default)
    };
    let facts = FieldFacts::shipped();
    let mut opts = FitOptions::shipped(&facts);
    if args.first().map(String::as_str) == Some("--from-design") {
        let design = args.get(1).expect("--from-design DESIGN.csv");
        let band_path = args
            .get(2)
            .map_or("data/calibration_band.toml", String::as_str);
        let f = polywear_study::calibration_band::fit::Fit::from_design(&opts, design.as_ref())
            .expect("the design table");
        opts.points = f.points.len() as u64;
        let generated_by = format!(
            "cargo run --release --example calibrate_band -- {} {}",
            opts.points, opts.fleet_samples
        );
        let band = f
            .band(&FittedConstants::of(&Params::default()), &generated_by)
            .expect("the sets");
        std::fs::write(band_path, band.to_toml()).expect("write the sets");
        println!("{}\n{band_path}: {}", band.fit.region, band.fit.shipped);
        println!("nominal: {:?}", band.nominal().constants());
        return;
    }
    opts.points = number(0, opts.points);
    opts.fleet_samples = number(1, opts.fleet_samples);
    let band_path = args
        .get(2)
        .map_or("data/calibration_band.toml", String::as_str);
    let design_path = args
        .get(3)
        .map_or("data/calibration_design.csv", String::as_str);
    let base = Params::default();
    let start = Instant::now();
    let done = std::sync::atomic::AtomicU64::new(0);
    let total = opts.points;
    let f = fit(&base, &facts, &opts, &|k| {
        let n = done.fetch_add(k, std::sync::atomic::Ordering::Relaxed) + k;
        if n % 32 == 0 || n == total {
            eprintln!(
                "{n} of {total} points in {:.0} s",
                start.elapsed().as_secs_f64()
            );
        }
    })
    .expect("fit");
    let secs = start.elapsed().as_secs_f64();
    let generated_by = format!(
        "cargo run --release --example calibrate_band -- {} {}",
        opts.points, opts.fleet_samples
    );
    let band = f
        .band(&FittedConstants::of(&base), &generated_by)
        .expect("the sets");
    std::fs::write(band_path, band.to_toml()).expect("write the sets");
    polywear_study::parquet_out::write_csv(
        std::path::Path::new(design_path),
        &design_columns(&f, &opts.ranges),
    )
    .expect("write the design");
    println!(
        "{} points on {} highway followers and {} fleet wheels in {secs:.0} s ({} threads)",
        f.points.len(),
        f.highway_wheels,
        f.fleet_wheels,
        rayon::current_num_threads()
    );
    println!("{}", band.fit.region);
    println!("{}: {}", band_path, band.fit.shipped);
    let n = band.nominal().constants();
    println!("nominal: {n:?}");
}
