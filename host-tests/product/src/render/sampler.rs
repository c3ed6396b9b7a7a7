//! Samplers of `curvicast render`: what a pixel makes of the cells its ray crosses, one `(value, length)` pair per
//! cell in increasing `t` (Hannasch §6.1 uses the projection sampler, which "multiplies the cell value by the
//! length of the intersection of the ray with the cell", without interpolation; so do the others here).
//!
//! * projection: `Σ value · length` (empty cells, NaN, contribute 0);
//! * travel time: `Σ length / value`, the value being a speed (NaN or ≤ 0 contributes 0);
//! * emission–absorption: front-to-back compositing with the transfer function [`Transfer`].

/// The emission–absorption transfer function.
///
/// A cell's value `v` is mapped to `s = clamp((v − lo) / (hi − lo), 0, 1)` (NaN: empty, `s = 0`). The cell emits
/// with intensity `s` and absorbs with extinction `σ = opacity · s` per unit length, so over a crossing of length
/// `L` its opacity is `α = 1 − exp(−σ L)`. Front to back: `I += T · α · s`, `T *= 1 − α`, starting from `I = 0`,
/// `T = 1`; the march stops early once the accumulated opacity `1 − T` reaches `cutoff`. The pixel's value is `I`,
/// in `[0, 1]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transfer {
    /// The value mapped to `s = 0`.
    pub lo: f64,
    /// The value mapped to `s = 1`.
    pub hi: f64,
    /// Extinction per unit length at `s = 1`.
    pub opacity: f64,
    /// Accumulated opacity at which the march stops (early termination), in (0, 1].
    pub cutoff: f64,
}

/// What a pixel computes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// `Σ value · length`.
    Projection,
    /// `Σ length / value`.
    TravelTime,
    /// Front-to-back emission–absorption.
    EmissionAbsorption(Transfer),
}

impl Mode {
    /// The mode's name in `render.json`.
    pub fn name(&self) -> &'static str {
        match self {
            Mode::Projection => "projection",
            Mode::TravelTime => "travel_time",
            Mode::EmissionAbsorption(_) => "emission_absorption",
        }
    }
}

/// The running state of one pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accumulator {
    mode: Mode,
    sum: f64,
    transmittance: f64,
}

impl Accumulator {
    /// A pixel with nothing crossed yet.
    pub fn new(mode: Mode) -> Accumulator {
        Accumulator {
            mode,
            sum: 0.0,
            transmittance: 1.0,
        }
    }

    /// Adds one crossing of `length` through a cell holding `value`; `false` when the pixel is done (early
    /// termination of emission–absorption).
    #[inline]
    pub fn add(&mut self, value: f64, length: f64) -> bool {
        match self.mode {
            Mode::Projection => {
                // a zero cell adds nothing, even along an infinite crossing (a polar prism seen along z)
                if value.is_finite() && value != 0.0 {
                    self.sum += value * length;
                }
                true
            }
            Mode::TravelTime => {
                if value.is_finite() && value > 0.0 {
                    self.sum += length / value;
                }
                true
            }
            Mode::EmissionAbsorption(tf) => {
                if !value.is_finite() {
                    return true;
                }
                let s = ((value - tf.lo) / (tf.hi - tf.lo)).clamp(0.0, 1.0);
                if s == 0.0 {
                    // neither emits nor absorbs, whatever the length
                    return true;
                }
                let alpha = -(-tf.opacity * s * length).exp_m1();
                self.sum += self.transmittance * alpha * s;
                self.transmittance *= 1.0 - alpha;
                1.0 - self.transmittance < tf.cutoff
            }
        }
    }

    /// The pixel's value.
    pub fn value(&self) -> f64 {
        self.sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn emission_absorption_of_one_thick_cell_is_its_emission_times_opacity() {
        let tf = Transfer {
            lo: 0.0,
            hi: 2.0,
            opacity: 1.0,
            cutoff: 0.99,
        };
        let mut a = Accumulator::new(Mode::EmissionAbsorption(tf));
        assert!(a.add(1.0, 2.0));
        let alpha = 1.0 - (-1.0f64).exp();
        assert!((a.value() - 0.5 * alpha).abs() < 1e-15);
    }

    #[test]
    fn emission_absorption_stops_once_opaque_and_later_cells_are_hidden() {
        let tf = Transfer {
            lo: 0.0,
            hi: 1.0,
            opacity: 10.0,
            cutoff: 0.99,
        };
        let mut a = Accumulator::new(Mode::EmissionAbsorption(tf));
        assert!(!a.add(1.0, 1.0));
        assert!(a.value() > 0.99);
    }

    #[test]
    fn travel_time_skips_empty_and_non_positive_speeds() {
        let mut a = Accumulator::new(Mode::TravelTime);
        a.add(2.0, 4.0);
        a.add(f64::NAN, 1.0);
        a.add(0.0, 1.0);
        a.add(-1.0, 1.0);
        assert_eq!(a.value(), 2.0);
    }

    #[test]
    fn zero_cells_add_nothing_along_an_infinite_crossing() {
        let mut a = Accumulator::new(Mode::Projection);
        a.add(0.0, f64::INFINITY);
        a.add(2.0, 0.5);
        assert_eq!(a.value(), 1.0);
        let tf = Transfer {
            lo: 1.0,
            hi: 2.0,
            opacity: 1.0,
            cutoff: 0.99,
        };
        let mut a = Accumulator::new(Mode::EmissionAbsorption(tf));
        assert!(a.add(0.5, f64::INFINITY));
        assert_eq!(a.value(), 0.0);
        // a visible cell crossed for ever is opaque
        assert!(!a.add(2.0, f64::INFINITY));
        assert_eq!(a.value(), 1.0);
    }

    #[test]
    fn projection_treats_nan_as_empty() {
        let mut a = Accumulator::new(Mode::Projection);
        a.add(3.0, 0.5);
        a.add(f64::NAN, 10.0);
        assert_eq!(a.value(), 1.5);
    }
}
