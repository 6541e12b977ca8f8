//! One operating point's verdicts in words and as a table, as `simulate` prints them.

use polywear_core::classify::Class;
use polywear_core::records::WheelRecord;
use polywear_core::wording::plain;

/// The verdict of one wheel in words, the first thing `simulate` prints:
/// "rear (follower): vibrates (65.4 mm/s, 38.5 µm, 270 Hz, 19.4-gon)", "front (driving): stable
/// (decays at 7.07 1/s)": the wheel by its axle and role (MODEL.md#the-car-axles-and-drivetrain).
pub(crate) fn verdict_line(r: &WheelRecord) -> String {
    let cycle = || {
        format!(
            "{} mm/s, {} µm, {} Hz, {}-gon",
            plain(r.amp_v_mps * 1e3, 3),
            plain(r.amp_y_m * 1e6, 3),
            plain(r.freq_hz, 3),
            plain(r.polygon_order, 3)
        )
    };
    let verdict = match r.class {
        Class::LimitCycle => format!("vibrates ({})", cycle()),
        Class::Bistable => format!(
            "stable, but vibrates once disturbed hard enough (bistable: {})",
            cycle()
        ),
        Class::Stable => format!("stable (decays at {} 1/s)", plain(-r.eig_re_max, 3)),
        Class::NoTraction => format!("no traction ({})", r.reason),
        Class::Failed => format!("no verdict ({})", r.reason),
        Class::Standstill => format!("standing still ({})", r.reason),
    };
    format!("{}: {verdict}", r.axle.with_role(r.wheel))
}

/// The verdicts and the table of every figure per wheel, as `simulate` prints them.
pub fn verdict_table(records: &[WheelRecord]) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let Some(first) = records.first() else {
        return out;
    };
    for r in records {
        let _ = writeln!(out, "{}", verdict_line(r));
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "operating point: {} km/h, toe {} deg, load {} N, pressure {} kPa, variant {}",
        plain(first.speed_kmh, 6),
        plain(first.toe_deg, 6),
        plain(first.load_n, 6),
        plain(first.pressure_kpa, 6),
        first.variant
    );
    type Cell = fn(&WheelRecord) -> String;
    let rows: [(&str, Cell); 14] = [
        ("class", |r| r.class.to_string()),
        ("slip ratio", |r| plain(r.slip_ratio, 4)),
        ("contact length [mm]", |r| {
            plain(r.contact_length_m * 1e3, 4)
        }),
        ("contact width [mm]", |r| plain(r.contact_width_m * 1e3, 4)),
        ("K_s [N/m]", |r| plain(r.k_s, 5)),
        ("F_m / F_s [N]", |r| {
            format!("{} / {}", plain(r.f_m, 4), plain(r.f_s, 4))
        }),
        ("eig re max [1/s]", |r| plain(r.eig_re_max, 4)),
        ("eig freq [Hz]", |r| plain(r.eig_freq_hz, 5)),
        ("amplitude y [µm]", |r| plain(r.amp_y_m * 1e6, 4)),
        ("amplitude v [mm/s]", |r| plain(r.amp_v_mps * 1e3, 4)),
        ("cycle freq [Hz]", |r| plain(r.freq_hz, 5)),
        ("polygon order", |r| plain(r.polygon_order, 4)),
        ("energy/cycle [µJ]", |r| {
            plain(r.energy_per_cycle_j * 1e6, 4)
        }),
        ("Floquet max |mu|", |r| plain(r.floquet_max, 4)),
    ];
    let _ = write!(out, "{:<20}", "");
    for r in records {
        let _ = write!(out, "{:>22}", r.wheel);
    }
    let _ = writeln!(out);
    for (k, (label, f)) in rows.iter().enumerate() {
        // Padded by characters, not bytes: `µ` takes two bytes.
        let _ = write!(
            out,
            "{label}{}",
            " ".repeat(20usize.saturating_sub(label.chars().count()))
        );
        for r in records {
            // A stable wheel has no cycle: no amplitude, frequency, polygon order, energy or
            // Floquet multiplier.
            let cell = if (8..14).contains(&k) && r.class == Class::Stable {
                "-".to_string()
            } else {
                f(r)
            };
            let _ = write!(out, "{cell:>22}");
        }
        let _ = writeln!(out);
    }
    out
}
