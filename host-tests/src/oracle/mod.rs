//! The oracle: independent, arbitrary-precision reference answers.
//!
//! Rule: nothing in this module calls into the `curvicast` kernel. It re-derives every answer by brute force in
//! high precision with logic of its own, so that a bug cannot hide in both.

pub mod march;
pub mod multires;
pub mod precise;
pub mod surfaces;
pub mod terrain;
