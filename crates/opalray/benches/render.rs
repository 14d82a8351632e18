//! Criterion benchmarks of the render stage (being built).
fn main() {}
