//! A one-parameter sweep in words (`polywear bifurcation`): the windows of vibration of each
//! wheel and its Hopf points with their criticality.

use polywear_core::model::Wheel;
use polywear_core::records::WheelRecord;
use polywear_core::wording::plain;
use polywear_study::bifurcation::Sweep;
use polywear_study::chart::criticality;

/// The windows of vibration in words, and each wheel's Hopf points.
pub fn sweep_lines(sw: &Sweep, (from, to): (f64, f64), steps: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let s = sw.param.spec();
    let variant = sw.variant;
    let (records, hopf) = (&sw.records, &sw.hopf);
    lines.push(format!(
        "sweep of {} from {} to {} {} ({} values, variant {variant}) at {}",
        s.name,
        plain(from, 6),
        plain(to, 6),
        s.unit,
        steps,
        sw.held_fixed()
    ));
    for wheel in Wheel::BOTH {
        for line in sw.windows_in_words(wheel) {
            lines.push(line.to_string());
        }
    }
    for wheel in Wheel::BOTH {
        let rows: Vec<&WheelRecord> = records.iter().filter(|r| r.wheel == wheel).collect();
        let vib = rows.iter().filter(|r| r.class.vibrates()).count();
        lines.push(format!(
            "{wheel:>9}: {vib} of {} values vibrate",
            rows.len()
        ));
        for h in hopf.iter().filter(|h| h.wheel == wheel) {
            lines.push(format!(
                "           Hopf point at {} = {:.6} {} ({} as it increases); l1 = {:.4e}, {}",
                s.name,
                h.value,
                s.unit,
                if h.destabilizing {
                    "loses stability"
                } else {
                    "regains stability"
                },
                h.l1,
                criticality(h.l1)
            ));
        }
    }
    lines
}
