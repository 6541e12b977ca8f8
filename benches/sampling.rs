//! Cost of the random streams: explore draws ~10 values per sample at ~5,000 samples/s,
//! so positioning the generator and drawing one value must stay well under a microsecond.
//! A hand-written counter hash (SplitMix64 finalizer), the cheapest addressable generator, is
//! timed beside it for the ratio. Run: `cargo bench --bench sampling`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rand::Rng;

use polywear::study::{Study, DEFAULT_STUDY};
use polywear_core::sampling::design::{Coordinates, Design};
use polywear_core::sampling::distribution::Distribution;
use polywear_core::sampling::Streams;

/// A SplitMix64-style counter hash, kept here only as the baseline of the ratio.
fn splitmix_bits(seed: u64, index: u64, stream: u64) -> u64 {
    let mut z = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_mul(0xD1B5_4A32_D192_ED03))
        .wrapping_add(stream.wrapping_mul(0x8CB9_2BA7_2F3D_8DD7))
        .wrapping_add(0x2545_F491_4F6C_DD1D);
    for _ in 0..2 {
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
    }
    z
}

fn bench_draw(c: &mut Criterion) {
    let streams = Streams::new(2014);
    let mut g = c.benchmark_group("one_draw");
    let mut i = 0u64;
    g.bench_function("chacha12_position_and_draw", |b| {
        b.iter(|| {
            i += 1;
            streams.at(black_box(i), black_box(3)).next_u64()
        })
    });
    g.bench_function("chacha12_key_position_and_draw", |b| {
        b.iter(|| {
            i += 1;
            polywear_core::sampling::bits(black_box(2014), black_box(i), black_box(3))
        })
    });
    g.bench_function("splitmix_hash_v0.1", |b| {
        b.iter(|| {
            i += 1;
            splitmix_bits(black_box(2014), black_box(i), black_box(3))
        })
    });
    let mut rng = streams.at(0, 0);
    g.bench_function("chacha12_sequential_next_u64", |b| {
        b.iter(|| rng.next_u64())
    });
    g.finish();

    let tn = Distribution::TruncatedNormal {
        mean: 240.0,
        sd: 20.0,
        min: 180.0,
        max: 320.0,
    };
    let mut g = c.benchmark_group("one_value");
    g.bench_function("truncated_normal_quantile", |b| {
        b.iter(|| tn.quantile(black_box(0.3)))
    });
    g.bench_function("truncated_normal_far_tail_quantile", |b| {
        let far = Distribution::TruncatedNormal {
            mean: 240.0,
            sd: 8.0,
            min: 312.0,
            max: 400.0,
        };
        b.iter(|| far.quantile(black_box(0.3)))
    });
    let normal = Distribution::Normal {
        mean: 4000.0,
        sd: 500.0,
    };
    g.bench_function("normal_draw_rand_distr", |b| {
        b.iter(|| {
            i += 1;
            normal.draw(&mut streams.at(black_box(i), 0))
        })
    });
    g.finish();
}

fn bench_sample(c: &mut Criterion) {
    // A whole sample of the default study (8 drawn axes), per design.
    let study = Study::parse(DEFAULT_STUDY).unwrap();
    let mut g = c.benchmark_group("sample_default_study");
    for design in [Design::Random, Design::LatinHypercube, Design::Sobol] {
        let coords = Coordinates::new(design, 2014, 1_000_000, study.drawn.len());
        let mut i = 0u64;
        g.bench_function(design.as_str(), |b| {
            b.iter(|| {
                i = (i + 1) % 1_000_000;
                study
                    .drawn
                    .iter()
                    .enumerate()
                    .map(|(dim, d)| coords.value(black_box(i), dim, &d.dist))
                    .sum::<f64>()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench_draw, bench_sample);
criterion_main!(benches);
