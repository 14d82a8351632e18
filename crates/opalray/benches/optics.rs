//! Criterion benchmarks of the optics stage (being built).
fn main() {}
