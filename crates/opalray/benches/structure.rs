//! Criterion benchmarks of the structure stage (paper §2.4): growing the paper's opal
//! (100 × 75 × 25 cells, R = 6, void ratio 0.2; target ≤ 20 ms on two cores) and a grid
//! 64 times larger (400 × 300 × 100; target ≤ 2 s), plus drawing the fig. 9 map.

use criterion::Criterion;
use opalray::grow_structure;
use opalray::scene::StructureConfig;
use opalray::structure::orientation_map;

fn structure(c: &mut Criterion) {
    let paper = StructureConfig::default();
    let large = StructureConfig {
        grid: [400, 300, 100],
        ..StructureConfig::default()
    };
    let mut group = c.benchmark_group("structure");
    group.bench_function("grow_100x75x25", |b| {
        b.iter(|| grow_structure(&paper).unwrap())
    });
    let grown = grow_structure(&paper).unwrap();
    group.bench_function("map_100x75x25_scale6", |b| {
        b.iter(|| orientation_map(&grown, 12, 6).unwrap())
    });
    group.sample_size(10);
    group.bench_function("grow_400x300x100", |b| {
        b.iter(|| grow_structure(&large).unwrap())
    });
    group.finish();
}

fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    structure(&mut criterion);
    criterion.final_summary();
}
