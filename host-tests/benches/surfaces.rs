//! Criterion benchmarks of the ray–surface solvers (filled by the surfaces work).
fn main() {}
