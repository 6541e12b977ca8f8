//! The analysis from Rust instead of the command line: `RunInfo` → `Analysis` → rendered
//! report (docs/book/src/reference/analyze.md#analyze).
//!
//! Run: `cargo run --release --example analyze_in_rust -- EXPLORE_DIR REPORT_DIR`.

use std::error::Error;

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let (Some(dir), Some(out)) = (args.next(), args.next()) else {
        return Err("usage: analyze_in_rust EXPLORE_DIR REPORT_DIR".into());
    };
    let info = polywear::analysis::inputs::check_inputs(&[dir.into()])?;
    let a = polywear::analysis::run(info, &polywear::analysis::AnalysisOptions::default())?;
    // Both questions are answered the same way (`OutcomeAnswer`): vibration, and the wear
    // answer at 40,000 km when the run has the wear stage.
    for o in &a.vibration.occurrence {
        println!("{} {}: P(vibrates) = {:.3}", o.variant, o.wheel, o.p());
    }
    if let Some(w) = &a.wear {
        let h = w.headline_answer();
        for o in &h.occurrence {
            println!("{} {}: P({}) = {:.3}", o.variant, o.wheel, h.words, o.p());
        }
    }
    let opts = polywear::render::RenderOptions {
        out_dir: out.into(),
        figure_format: polywear::render::FigureFormat::Png,
    };
    polywear::render::write(&a, &opts)?;
    Ok(())
}
