//! Criterion benchmarks of the structure stage (being built).
fn main() {}
