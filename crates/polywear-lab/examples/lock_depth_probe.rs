//! A drive cycle's answer over the tread's life, each speed bin saturated on its own as
//! `cycle` gives it, against the same walk with a lock that
//! widens with the depth (MODEL.md#the-tongue-at-depth): a vibrating bin locks to order n once
//! the polygon's radius reaches the least at which its forced Hopf normal form locks at the
//! bin's detuning ν − n·f₀/f (`WheelGrowth::lock_radius_m`), and a locked bin prints, instead of
//! its saturated linear print:
//! - the free cycle's harmonic |P₁|/P̄ (the default);
//! - the sliding bound m_max (`PW_LOCKED_PRINT=cap`);
//! - |P₁|/P̄ times the normal form's locked amplitude over the free cycle's, at most m_max
//!   (`PW_LOCKED_PRINT=amplitude`);
//! - |P₁|/P̄ times the share of the locked print that deepens the polygon
//!   (`WheelGrowth::locked_print_share`, at most m_max; `PW_LOCKED_PRINT=phase`), or with the
//!   locked amplitude's power harmonic saturated as a sliding power's (`phase_sliding`).
//!
//! Each order is walked in 32 midpoint substeps per interval of worn depth; without the lock the
//! walk is the shipped answer.
//!
//! `PW_LOCKED_PRINT=brute` takes the lock and print of order ⌊ν⌋ at the cycle's first speed (or
//! `PW_TABLE_ORDER`) from brute force instead, on a grid of speeds around V_n and radii (about a
//! minute per wheel; MODEL.md#the-locked-print);
//! `PW_LOCKED_PRINT=orbit` from the forced orbit (`polywear_lab::forced_orbit`, from 30 revolutions
//! settled) on the same grid; `PW_LOCK_SIDE=below` (a diagnostic) locks no speed above V_n.
//! `PW_CAPTURE=1` locks an order at any depth where the tread's drift carries a vibrating speed's
//! ν through it (MODEL.md#the-locked-print). `PW_VERBOSE=1` prints each order's distance and the
//! first speed's lock radii, `PW_TRACE_ORDER=N` order N's radius interval by interval.
//!
//! CYCLE is a drive cycle's CSV, or `cruise:V:SIGMA:LEGS`: cruising at V km/h with a spread of
//! SIGMA km/h driven as the long-term loop drives it, LEGS quantile speeds at equal distances.
//!
//! ```sh
//! cargo run --release -p polywear-lab --example lock_depth_probe -- CYCLE TOE_DEG PHI_S
//! cargo run --release -p polywear-lab --example lock_depth_probe -- data/cycles/wltc_class3b.csv 0.3 1
//! PW_LOCKED_PRINT=phase cargo run --release -p polywear-lab --example lock_depth_probe -- cruise:100:5:5 0.3 1
//! ```
use polywear::classify::budget::Meter;
use polywear::classify::ClassifierOptions;
use polywear::evaluate::{solve_wheel, WearStage};
use polywear::model::{Variant, Wheel};
use polywear::params::Params;
use polywear_core::wear::estimator::{print_log_ratio, SaturatedSteps, SLIDING_MODULATION_MAX};
use polywear_core::wear::{
    FittedConstants, LifeProfile, WearSettings, WheelGrowth, LIFE_PROFILE_INTERVALS,
};
use polywear_study::cycle::DriveCycle;
use std::collections::BTreeMap;

const ORDERS: u32 = 64;

/// A speed's profile, its lock radii (as [`Bin::lock_radius`]), its cycle's |P₁|/P̄ and what
/// the locked amplitude needs.
type Solved = (LifeProfile, Vec<Vec<f64>>, f64, Amplitude);

/// What [`WheelGrowth::locked_amplitude`] needs at a bin: its growth, speed and ν, and f₀/f
/// at each interval's middle.
#[derive(Clone)]
struct Amplitude {
    growth: std::sync::Arc<WheelGrowth>,
    /// PW_LOCKED_PRINT=brute: the wheel's order-19 lock and print, brute force.
    brute: Option<std::sync::Arc<BruteTable>>,
    speed_kmh: f64,
    nu: f64,
    mid_ratios: Vec<f64>,
}

struct Bin {
    km: f64,
    profile: LifeProfile,
    /// Per order (index n−1), per interval j (1..=J): the radius [m] at which the bin locks
    /// (inf: never).
    lock_radius: Vec<Vec<f64>>,
    power_harmonic: f64,
    amplitude: Amplitude,
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let path = std::path::Path::new(&a[1]);
    let toe: f64 = a[2].parse().unwrap();
    let phi: f64 = a[3].parse().unwrap();
    let base = Params {
        toe_deg: toe,
        wear_share_straight: phi,
        ..Params::default()
    };
    let variant = Variant::SlidingShare;
    let opts = ClassifierOptions::default();
    let stage = WearStage::for_run(&base, variant, WearSettings::default(), &opts).unwrap();
    let cycle = match a[1].strip_prefix("cruise:") {
        Some(spec) => cruise_cycle(spec),
        None => DriveCycle::read(path).unwrap(),
    };
    let kms = cycle.step_km();
    let c = FittedConstants::of(&base);
    let brute_mode = std::env::var("PW_LOCKED_PRINT").is_ok_and(|v| v == "brute" || v == "orbit");
    for wheel in [Wheel::Follower, Wheel::Driving] {
        let t0 = std::time::Instant::now();
        let brute = brute_mode.then(|| {
            let centre = a[1]
                .strip_prefix("cruise:")
                .map_or(100.0, |s| s.split(':').next().unwrap().parse().unwrap());
            std::sync::Arc::new(BruteTable::new(&base, wheel, centre))
        });
        let mut bins: BTreeMap<i64, Bin> = BTreeMap::new();
        let mut cache: BTreeMap<u64, Option<Solved>> = BTreeMap::new();
        for (i, &km) in kms.iter().enumerate() {
            if cycle.standstill(i) || km <= 0.0 {
                continue;
            }
            let p = cycle.step_params(&base, i);
            let key = p.speed_kmh.to_bits();
            let entry = cache.entry(key).or_insert_with(|| {
                let w = solve_wheel(p, variant, wheel, &opts);
                let g = WheelGrowth::new(&stage.problem(&p, &w), &Meter::new(opts.budget)).ok()?;
                let profile = g.life_profile(ORDERS, LIFE_PROFILE_INTERVALS);
                let ratios = g.worn_frequency_ratios(LIFE_PROFILE_INTERVALS);
                let nu = g.nu();
                let mut lock =
                    vec![vec![f64::INFINITY; LIFE_PROFILE_INTERVALS + 1]; ORDERS as usize];
                if w.verdict.class.vibrates() {
                    for n in 1..=ORDERS {
                        let nf = n as f64;
                        let deltas: Vec<f64> = (1..=LIFE_PROFILE_INTERVALS)
                            .map(|j| nu - nf * 0.5 * (ratios[j - 1] + ratios[j]))
                            .collect();
                        if deltas.iter().all(|d| d.abs() > 4.0) {
                            continue;
                        }
                        // PW_CAPTURE (a trial): where the tread's drift carries ν through n
                        // between two intervals, the order locks at any depth (its print widens
                        // the tongue faster than the drift moves δ).
                        let capture = std::env::var("PW_CAPTURE").is_ok();
                        let crossed = |j: usize| j > 0 && deltas[j - 1] * deltas[j] <= 0.0;
                        // The radius at which the bin's detuning locks (closed form).
                        for (j, d) in deltas.iter().enumerate() {
                            if capture && crossed(j) {
                                lock[n as usize - 1][j + 1] = 0.0;
                                continue;
                            }
                            let offset_kmh = -d * p.speed_kmh / nf;
                            // PW_LOCK_SIDE=below (a diagnostic): no lock above V_n.
                            let below_only =
                                std::env::var("PW_LOCK_SIDE").is_ok_and(|v| v == "below");
                            if below_only && offset_kmh > 0.0 {
                                continue;
                            }
                            if let Some(t) = brute.as_ref().filter(|t| t.order == n) {
                                lock[n as usize - 1][j + 1] = t.lock_radius(offset_kmh);
                            } else if let Some(r) = g.lock_radius_m(n, offset_kmh) {
                                lock[n as usize - 1][j + 1] = r;
                            }
                        }
                    }
                }
                let mid_ratios = (0..=LIFE_PROFILE_INTERVALS)
                    .map(|j| {
                        if j == 0 {
                            1.0
                        } else {
                            0.5 * (ratios[j - 1] + ratios[j])
                        }
                    })
                    .collect();
                let ph = g.cycle_power_harmonic_rel();
                let amplitude = Amplitude {
                    growth: std::sync::Arc::new(g),
                    brute: brute.clone(),
                    speed_kmh: p.speed_kmh,
                    nu,
                    mid_ratios,
                };
                Some((profile, lock, ph, amplitude))
            });
            let Some((profile, lock, ph, amplitude)) = entry else {
                continue;
            };
            let bin = (p.speed_kmh / 0.1).round() as i64;
            let b = bins.entry(bin).or_insert_with(|| Bin {
                km: 0.0,
                profile: LifeProfile::zero(profile.max_order, profile.intervals, profile.usable_m),
                lock_radius: lock.clone(),
                power_harmonic: *ph,
                amplitude: amplitude.clone(),
            });
            b.km += km;
            b.profile.add(profile, km);
        }
        for b in bins.values_mut() {
            let km = b.km;
            b.profile.scale(1.0 / km);
        }
        if std::env::var("PW_VERBOSE").is_ok() {
            if let Some(b) = bins.values().next() {
                let m = &b.amplitude;
                for n in m.nu.floor() as u32..=m.nu.floor() as u32 + 1 {
                    let radii: Vec<String> = (1..=24)
                        .map(|j| format!("{:.1}", b.lock_radius[n as usize - 1][j] * 1e6))
                        .collect();
                    eprintln!("  first bin, order {n}: lock radius [um] by interval: {radii:?}");
                }
            }
        }
        let steps: Vec<(f64, LifeProfile)> =
            bins.values().map(|b| (b.km, b.profile.clone())).collect();
        let shipped = SaturatedSteps::new(steps).answer(&c, &base, SLIDING_MODULATION_MAX);
        println!(
            "{wheel:?}: {} bins, {:.1} s; shipped saturated: {:?}",
            bins.len(),
            t0.elapsed().as_secs_f64(),
            shipped
        );
        for locking in [false, true] {
            let (km, n) = walk(&bins, &c, &base, locking);
            println!("  own walk, lock at depth {locking}: {km:.0} km, order {n}");
        }
    }
}

/// Each order's u = D/2R⁰ over the depth grid, 32 midpoint substeps per interval:
/// du/ds = Σ a_k (b_k u + [locked ? L_k : min(r_k u, cap_k)]).
fn walk(bins: &BTreeMap<i64, Bin>, c: &FittedConstants, p: &Params, locking: bool) -> (f64, u32) {
    let total: f64 = bins.values().map(|b| b.km).sum();
    let like = &bins.values().next().unwrap().profile;
    let mut mean = LifeProfile::zero(like.max_order, like.intervals, like.usable_m);
    for b in bins.values() {
        mean.add(&b.profile, b.km / total);
    }
    let wear = mean.tread_wear_m_per_m(c);
    let target = print_log_ratio(p);
    let visible = target.exp();
    let seed_m = 2.0 * p.seed_runout_um * 1e-6;
    let r0 = p.seed_runout_um * 1e-6;
    let phi = c.wear_share_straight;
    let intervals = like.intervals;
    let dw = like.usable_m / intervals as f64;
    let ds = dw / wear;
    let sub = 32;
    let mut best: (f64, u32) = (f64::INFINITY, 0);
    for n in 1..=like.max_order {
        let k = n as usize - 1;
        let mut u = 1.0f64;
        'walk: for j in 1..=intervals {
            let by_amplitude = std::env::var("PW_LOCKED_PRINT").is_ok_and(|v| v == "amplitude");
            let by_phase = std::env::var("PW_LOCKED_PRINT").is_ok_and(|v| v.starts_with("phase"));
            let sliding = std::env::var("PW_LOCKED_PRINT").is_ok_and(|v| v == "phase_sliding");
            let terms: Vec<(f64, f64, f64, f64, f64, f64, &Bin)> = bins
                .values()
                .map(|b| {
                    let pr = &b.profile;
                    let other = (1.0 - phi)
                        * (pr.other_per_share.0 + c.wear_rate_driven_factor * pr.other_per_share.1);
                    let base = phi * pr.base_per_share[k] - other;
                    let rate =
                        (phi * (pr.integral(n, j) - pr.integral(n, j - 1)) - other * dw) / dw;
                    let cap = phi * pr.full_print_per_share[k] * SLIDING_MODULATION_MAX / seed_m;
                    // PW_LOCKED_PRINT=cap: a locked step prints the sliding bound (m_max), else
                    // the free cycle's |P₁|/P̄.
                    let modulation = if std::env::var("PW_LOCKED_PRINT").is_ok_and(|v| v == "cap") {
                        SLIDING_MODULATION_MAX
                    } else {
                        b.power_harmonic
                    };
                    let locked = phi * pr.full_print_per_share[k] * modulation / seed_m;
                    (
                        b.km / total,
                        base,
                        rate - base,
                        cap,
                        locked,
                        b.lock_radius[k][j],
                        b,
                    )
                })
                .collect();
            let f = |u: f64| -> f64 {
                terms
                    .iter()
                    .map(|&(a, base, r, cap, locked, lock_r, b)| {
                        let print = if locking && u * r0 >= lock_r {
                            let m = &b.amplitude;
                            let offset =
                                -(m.nu - n as f64 * m.mid_ratios[j]) * m.speed_kmh / n as f64;
                            if let Some(t) = m.brute.as_ref().filter(|t| t.order == n) {
                                // The table's share is of its own centre's free print.
                                locked / b.power_harmonic * t.free * t.share(offset, u * r0)
                            } else if by_phase {
                                // PW_LOCKED_PRINT=phase: the free print times the share of the
                                // locked print that deepens the polygon (its amplitude and
                                // phase, WheelGrowth::locked_print_share).
                                // A captured order (lock radius 0) is locked at δ = 0 itself.
                                let offset = if lock_r == 0.0 { 0.0 } else { offset };
                                match m.growth.locked_print_share(n, u * r0, offset) {
                                    Some(share) if sliding => {
                                        // PW_LOCKED_PRINT=phase_sliding: the locked amplitude's
                                        // power harmonic saturated as a sliding power's is.
                                        let grow = m.growth.locked_amplitude(n, u * r0, offset);
                                        let a = grow.unwrap_or(1.0) * b.power_harmonic;
                                        locked * share * sliding_harmonic(a) / a
                                    }
                                    Some(share) => (locked * share).min(cap),
                                    None => (r * u).min(cap),
                                }
                            } else if by_amplitude {
                                // PW_LOCKED_PRINT=amplitude: the free print times the locked
                                // cycle's amplitude over the free one's, at most the bound.
                                let grow = m.growth.locked_amplitude(n, u * r0, offset);
                                (locked * grow.unwrap_or(1.0)).min(cap)
                            } else {
                                locked
                            }
                        } else {
                            (r * u).min(cap)
                        };
                        a * (base * u + print)
                    })
                    .sum()
            };
            let h = ds / sub as f64;
            for s in 0..sub {
                let mid = u + 0.5 * h * f(u);
                let next = u + h * f(mid);
                if next >= visible {
                    let at =
                        ((j - 1) as f64 * ds + (s as f64 + (visible - u) / (next - u)) * h) / 1e3;
                    if std::env::var("PW_VERBOSE").is_ok() {
                        eprintln!("    order {n}: visible at {at:.0} km");
                    }
                    if at < best.0 {
                        best = (at, n);
                    }
                    break 'walk;
                }
                u = next.max(1e-300);
            }
            if std::env::var("PW_TRACE_ORDER").is_ok_and(|v| v == n.to_string()) && j <= 24 {
                eprintln!("    order {n}, interval {j}: R = {:.3} um", u * r0 * 1e6);
            }
        }
    }
    best
}

/// 2⟨P cos θ⟩/⟨P⟩ for P ∝ |1 + a cos θ| (MODEL.md#the-forced-response-saturates): a below 1,
/// at most 1.0528.
fn sliding_harmonic(a: f64) -> f64 {
    let m = 2048;
    let (mut first, mut mean) = (0.0, 0.0);
    for i in 0..m {
        let t = std::f64::consts::TAU * (i as f64 + 0.5) / m as f64;
        let p = (1.0 + a * t.cos()).abs();
        first += p * t.cos();
        mean += p;
    }
    2.0 * first / mean
}

/// The cycle of `V:SIGMA:LEGS` (see the header): each leg one row of 100 m.
fn cruise_cycle(spec: &str) -> DriveCycle {
    let f: Vec<f64> = spec.split(':').map(|x| x.parse().unwrap()).collect();
    let legs = polywear_core::wear::response::legs::cruise_legs(f[0], f[1], f[2] as usize);
    let mut csv = String::from("time_s,speed_kmh\n");
    let mut t = 0.0;
    for leg in &legs {
        csv += &format!("{t},{}\n", leg.speed_kmh);
        t += 100.0 / (leg.speed_kmh / 3.6);
    }
    csv += &format!("{t},0\n");
    let path = std::env::temp_dir().join(format!("lock_depth_probe_{}.csv", std::process::id()));
    std::fs::write(&path, csv).unwrap();
    let cycle = DriveCycle::read(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    cycle
}

/// Brute force's lock and locked print of order n = ⌊ν⌋ on a grid of speed offsets from V_n and
/// radii (the model rebuilt at each speed, 300 revolutions settled, 40 read; the print's share
/// as `crates/polywear-lab/examples/locked_print.rs` reads it, over the free cycle's |P₁|/P̄ at V_19).
struct BruteTable {
    /// The order: ⌊ν⌋ at the cycle's centre speed, the one the loop grows.
    order: u32,
    offsets_kmh: Vec<f64>,
    radii_m: Vec<f64>,
    /// `[offset][radius]`: locked to 19, and the share.
    cells: Vec<Vec<(bool, f64)>>,
    /// The free cycle's |P₁|/P̄ at V_n, which the shares are of.
    free: f64,
}

impl BruteTable {
    fn new(base: &Params, wheel: Wheel, near_kmh: f64) -> Self {
        use polywear::long_term::lock::{is_locked, rotation_number};
        use polywear::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
        use polywear::model::WheelModel;
        use polywear_core::numeric::Complex64;
        use polywear_core::wear::Feedback;
        use polywear_lab::forced_orbit;
        use rayon::prelude::*;
        let by_orbit = std::env::var("PW_LOCKED_PRINT").is_ok_and(|v| v == "orbit");
        let variant = Variant::SlidingShare;
        let opts = ClassifierOptions::default();
        let settings = WearSettings::default();
        let at = |speed_kmh: f64| Params { speed_kmh, ..*base };
        let growth_at = |p: &Params| {
            let stage = WearStage::for_run(p, variant, settings, &opts).unwrap();
            let w = solve_wheel(*p, variant, wheel, &opts);
            let g = WheelGrowth::new(&stage.problem(p, &w), &Meter::new(opts.budget)).unwrap();
            (w, g)
        };
        let (_, g) = growth_at(&at(near_kmh));
        let order =
            std::env::var("PW_TABLE_ORDER").map_or(g.nu().floor() as u32, |n| n.parse().unwrap());
        let nf = order as f64;
        let p0 = at(near_kmh * g.nu() / nf);
        let (w0, g0) = growth_at(&p0);
        let centre = p0.speed_kmh * g0.nu() / nf;
        let free = g0.cycle_power_harmonic_rel();
        let v0 = &w0.verdict;
        let m0 = w0.model.as_ref().unwrap();
        let start = [v0.section_z_m, m0.ode.equilibrium()[1], v0.section_v_mps];
        let offsets_kmh: Vec<f64> = (-32..=32).map(|i| 0.5 * i as f64).collect();
        let radii_m: Vec<f64> = (0..9).map(|i| 0.5e-6 * 2f64.powi(i)).collect();
        let grid: Vec<(usize, usize)> = (0..offsets_kmh.len())
            .flat_map(|i| (0..radii_m.len()).map(move |k| (i, k)))
            .collect();
        let values: Vec<(bool, f64)> = grid
            .par_iter()
            .map(|&(i, k)| {
                let p = at(centre + offsets_kmh[i]);
                let model = WheelModel::build(&p, wheel, variant).unwrap();
                let fb = Feedback::new(&p, &model, settings.zone);
                let mut h = vec![Complex64::new(0.0, 0.0); order as usize];
                h[order as usize - 1] = Complex64::new(radii_m[k], 0.0);
                let rotation_hz = WheelModel::rotation_hz(&p);
                let table = EpsilonTable::new(&fb, &h, 2048);
                let request = WindowRequest {
                    ode: &model.ode,
                    epsilon: &table,
                    rotation_hz,
                    start,
                    skip_revs: 300,
                    revs: 40,
                    samples_per_rev: 256,
                    rtol: 1e-8,
                    period_s: 1.0 / (g0.nu() * rotation_hz),
                    max_steps: 50_000_000,
                };
                let share = |print: Complex64| fb.in_phase_print(nf, print) / free;
                if by_orbit {
                    // The forced orbit by Newton from 30 revolutions settled.
                    let Ok(settled) = integrate_window(&WindowRequest {
                        skip_revs: 0,
                        revs: 30,
                        samples_per_rev: 16,
                        ..request
                    }) else {
                        return (false, 0.0);
                    };
                    let omega = std::f64::consts::TAU * nf * rotation_hz;
                    let forcing = fb.forcing_per_radius(nf) * radii_m[k];
                    return match forced_orbit::solve(&model.ode, forcing, omega, settled.end, 1e-10)
                    {
                        Ok(o) => (o.locks(), share(o.print)),
                        Err(_) => (false, 0.0),
                    };
                }
                let Ok(win) = integrate_window(&request) else {
                    return (false, 0.0);
                };
                let rho = rotation_number(&win.crossings_s, 1.0 / rotation_hz);
                (
                    is_locked(rho) && rho.round() as u32 == order,
                    share(win.print(order)),
                )
            })
            .collect();
        let cells = values
            .chunks(radii_m.len())
            .map(<[(bool, f64)]>::to_vec)
            .collect();
        eprintln!("lock table for {wheel:?}, order {order} around V_n = {centre:.3} km/h");
        BruteTable {
            order,
            free,
            offsets_kmh,
            radii_m,
            cells,
        }
    }

    fn nearest(&self, offset_kmh: f64) -> usize {
        let i = ((offset_kmh - self.offsets_kmh[0]) / 0.5).round();
        i.clamp(0.0, (self.offsets_kmh.len() - 1) as f64) as usize
    }

    /// The least tabled radius locked at the nearest offset (inf: none).
    fn lock_radius(&self, offset_kmh: f64) -> f64 {
        let row = &self.cells[self.nearest(offset_kmh)];
        row.iter()
            .position(|c| c.0)
            .map_or(f64::INFINITY, |k| self.radii_m[k])
    }

    /// The share at the nearest offset, linear in ln R between locked radii.
    fn share(&self, offset_kmh: f64, radius_m: f64) -> f64 {
        let row = &self.cells[self.nearest(offset_kmh)];
        let k = self.radii_m.partition_point(|&r| r <= radius_m).max(1) - 1;
        let next = (k + 1).min(self.radii_m.len() - 1);
        if next == k || !row[next].0 || !row[k].0 {
            return row[k].1;
        }
        let t = ((radius_m / self.radii_m[k]).ln() / (self.radii_m[next] / self.radii_m[k]).ln())
            .clamp(0.0, 1.0);
        row[k].1 + t * (row[next].1 - row[k].1)
    }
}
