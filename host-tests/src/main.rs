//! The `curvicast` command.
fn main() {}
