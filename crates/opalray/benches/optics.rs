//! Criterion benchmarks of the optics stage (group "optics"): building the reflectance
//! tables of the default crystal, and one table lookup as the render passes do it.
// criterion's macros generate undocumented items.
#![allow(missing_docs)]

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use opalray::scene::CrystalConfig;
use opalray::{build_optics, WavelengthGrid};

fn optics(c: &mut Criterion) {
    let crystal = CrystalConfig::default();
    let grid = WavelengthGrid::default();
    let mut group = c.benchmark_group("optics");
    group.bench_function("build_optics_default", |b| {
        b.iter(|| build_optics(black_box(&crystal), black_box(&grid)).unwrap())
    });
    let tables = build_optics(&crystal, &grid).unwrap();
    let (mut r, mut t, mut d) = (
        vec![0.0; grid.bins],
        vec![0.0; grid.bins],
        vec![0.0; grid.bins],
    );
    group.bench_function("lookup", |b| {
        b.iter(|| {
            tables.lookup(black_box(0.8137), &mut r, &mut t, &mut d);
            black_box(r[20])
        })
    });
    group.finish();
}

criterion_group!(benches, optics);
criterion_main!(benches);
