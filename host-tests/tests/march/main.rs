//! Marching: the kernel's traversals against the arbitrary-precision oracle and analytic answers, the engines against
//! each other, named defects, the QEMU smoke cases, the cost model and the kernel's generic API.
//!
//! One test binary per subject (one link instead of one per file); each module is one suite.

#[path = "../support/mod.rs"]
mod support;

mod analytic;
mod cost;
mod defects;
mod engines;
mod kernel_generics;
mod oracle;
mod smoke_cases;
