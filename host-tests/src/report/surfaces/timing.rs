//! The surface layer's speed: the median time per ray–surface solve of each kind and mode, as the report measures it.

use super::*;

/// Kernel surfaces of one kind in scalar `T`, for timing.
pub(super) fn time_kind<T: Real, S: Surface<T>>(
    surfaces: &[S],
    rays: &[Ray<T>],
    reps: usize,
) -> f64 {
    let mut per = Vec::with_capacity(reps);
    let n = rays.len().max(1);
    let mut sink = 0usize;
    // warm-up pass
    for (s, r) in surfaces.iter().zip(rays) {
        sink += black_box(s.crossings(black_box(r))).len();
    }
    for _ in 0..reps {
        let t0 = Instant::now();
        for (s, r) in surfaces.iter().zip(rays) {
            sink += black_box(s.crossings(black_box(r))).len();
        }
        per.push(t0.elapsed().as_nanos() as f64 / n as f64);
    }
    black_box(sink);
    per.sort_by(|a, b| a.total_cmp(b));
    per[per.len() / 2]
}

/// The median ns per intersection for one kind and mode over the given cases (rounded to the mode first).
pub fn median_ns(kind: Kind, mode: Precision, cases: &[SurfaceCase], reps: usize) -> f64 {
    fn go<T: Real>(kind: Kind, cases: &[SurfaceCase], reps: usize) -> f64 {
        let rays: Vec<Ray<T>> = cases
            .iter()
            .filter_map(|c| kernel_ray::<T>(c).ok())
            .collect();
        let p = |c: &SurfaceCase| (T::from_f64(c.p[0]), T::from_f64(c.p[1]));
        match kind {
            Kind::Spheroid => {
                let s: Vec<_> = cases
                    .iter()
                    .filter_map(|c| Spheroid::new(p(c).0, p(c).1).ok())
                    .collect();
                time_kind(&s, &rays, reps)
            }
            Kind::Cone => {
                let s: Vec<_> = cases
                    .iter()
                    .filter_map(|c| AxialCone::from_zenith_rad(p(c).0, p(c).1).ok())
                    .collect();
                time_kind(&s, &rays, reps)
            }
            Kind::HalfPlane => {
                let s: Vec<_> = cases
                    .iter()
                    .filter_map(|c| HalfPlane::from_azimuth_rad(p(c).0).ok())
                    .collect();
                time_kind(&s, &rays, reps)
            }
            Kind::PlaneZ => {
                let s: Vec<_> = cases
                    .iter()
                    .filter_map(|c| PlaneZ::new(p(c).0).ok())
                    .collect();
                time_kind(&s, &rays, reps)
            }
        }
    }
    let cs: Vec<SurfaceCase> = cases.iter().map(|c| c.for_mode(mode)).collect();
    match mode {
        Precision::F64 => go::<f64>(kind, &cs, reps),
        Precision::F32 => go::<f32>(kind, &cs, reps),
        Precision::F32Fast => go::<F32Fast>(kind, &cs, reps),
    }
}
