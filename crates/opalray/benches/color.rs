//! Criterion benchmarks of the color stage (being built).
fn main() {}
