//! Fuzz target for `curvicast::tessellate`: arbitrary levels, axes, bounds and buffer lengths.
//!
//! Checks: no panic; an `Ok` writes exactly the const-fn counts, leaves everything past them untouched, and
//! produces finite, well-formed faces; impossible requests get the right typed error (never `Internal`); the
//! a-priori level meets its bound and the level below does not (spheres; ellipsoids up to level 4).

#![no_main]

use arbitrary::Arbitrary;
use curvicast::V3;
use curvicast::real::Real;
use curvicast::tessellate::TessellateError;
use curvicast::tessellate::bevel::{self, Face};
use curvicast::tessellate::chaikin;
use curvicast::tessellate::lod::{self, Bound, Shape};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    level: u8,
    axes: [f64; 3],
    vertex_len: u16,
    face_len: u16,
    single: bool,
    bound_kind: u8,
    bound_a: f64,
    bound_b: f64,
    sphere: bool,
    curve_level: u8,
    curve: [f64; 5],
    point_len: u16,
}

/// Buffers are capped so that one input stays fast (level 4 at most is built).
const CAP: usize = 2048;

fn bevel_case<T: Real>(level: u32, axes: [T; 3], vlen: usize, flen: usize) {
    let sentinel = V3::new(T::from_i32(7), T::from_i32(7), T::from_i32(7));
    let mut v = vec![sentinel; vlen];
    let mut f = vec![Face::<T>::EMPTY; flen];
    let res = bevel::bevel_ellipsoid(level, axes, &mut v, &mut f);
    let nv = bevel::vertex_count(level);
    let nf = bevel::face_count(level);
    match res {
        Ok(c) => {
            assert!(level <= bevel::MAX_LEVEL);
            assert_eq!(
                (c.vertices, c.faces, c.edges),
                (nv, nf, bevel::edge_count(level))
            );
            assert!(vlen >= nv && flen >= nf);
            assert!(
                v[nv..].iter().all(|p| *p == sentinel),
                "wrote past the vertex count"
            );
            assert!(
                f[nf..].iter().all(|x| *x == Face::EMPTY),
                "wrote past the face count"
            );
            assert!(v[..nv].iter().all(|p| p.is_finite()));
            for face in &f[..nf] {
                assert!(face.len == 4 || face.len == 6);
                assert!(face.vertex_indices().iter().all(|&i| (i as usize) < nv));
                assert!(face.center.is_finite() && face.normal.is_finite());
            }
        }
        Err(TessellateError::LevelTooDeep { .. }) => assert!(level > bevel::MAX_LEVEL),
        Err(TessellateError::BufferTooSmall { needed, got, .. }) => {
            assert!(got < needed && (needed == nv || needed == nf))
        }
        Err(TessellateError::InvalidShape) => {}
        Err(e) => panic!("unexpected error {e:?}"),
    }
}

fuzz_target!(|inp: Input| {
    let level = u32::from(inp.level);
    let vlen = usize::from(inp.vertex_len).min(CAP);
    let flen = usize::from(inp.face_len).min(CAP);
    if inp.single {
        bevel_case::<f32>(level, inp.axes.map(|a| a as f32), vlen, flen);
    } else {
        bevel_case::<f64>(level, inp.axes, vlen, flen);
    }

    // A priori level of detail.
    let shape = if inp.sphere {
        Shape::Sphere(inp.axes[0])
    } else {
        Shape::Ellipsoid(inp.axes)
    };
    let bound = match inp.bound_kind % 3 {
        0 => Bound::MinDihedral(inp.bound_a),
        1 => Bound::MaxDeviation(inp.bound_a),
        _ => Bound::ScreenSpace {
            distance: inp.bound_a,
            pixel_angle: inp.bound_b,
        },
    };
    match lod::min_level(shape, bound) {
        Ok(k) => {
            assert!(k <= bevel::MAX_LEVEL);
            // For spheres, re-check minimality with the same comparison on the worst case.
            let worst = |k: u32| lod::worst_case::<f64>(k).unwrap();
            if let (Shape::Sphere(r), Bound::MaxDeviation(e)) = (shape, bound) {
                assert!(worst(k).max_deviation <= e / r);
                if k > 0 {
                    assert!(worst(k - 1).max_deviation > e / r);
                }
            }
            if let (Shape::Sphere(_), Bound::MinDihedral(phi)) = (shape, bound) {
                let limit = core::f64::consts::PI - phi;
                assert!(worst(k).max_normal_angle <= limit);
                if k > 0 {
                    assert!(worst(k - 1).max_normal_angle > limit);
                }
            }
            // For ellipsoids at small levels, against the unpruned walk's exact worst case (a relative 1e-6 of
            // slack for bounds within rounding of a level's worst value).
            if let (Shape::Ellipsoid(axes), true) = (shape, k <= 4) {
                let exact = |k: u32| lod::ellipsoid_worst_case(axes, k).unwrap();
                match bound {
                    Bound::MaxDeviation(e) => {
                        assert!(exact(k).max_deviation <= e * (1.0 + 1e-6));
                        if k > 0 {
                            assert!(exact(k - 1).max_deviation > e * (1.0 - 1e-6));
                        }
                    }
                    Bound::MinDihedral(phi) => {
                        let limit = core::f64::consts::PI - phi;
                        assert!(exact(k).max_normal_angle <= limit * (1.0 + 1e-6));
                        if k > 0 {
                            assert!(exact(k - 1).max_normal_angle > limit * (1.0 - 1e-6));
                        }
                    }
                    Bound::ScreenSpace { .. } => {}
                }
            }
        }
        Err(TessellateError::InvalidShape)
        | Err(TessellateError::AxisRatioTooLarge)
        | Err(TessellateError::InvalidBound)
        | Err(TessellateError::Unreachable) => {}
        Err(e) => panic!("unexpected error {e:?}"),
    }

    // Rational Chaikin curves.
    let clevel = u32::from(inp.curve_level);
    let plen = usize::from(inp.point_len).min(CAP);
    let sentinel = [9.0_f64, 9.0];
    let mut pts = vec![sentinel; plen];
    let [cx, cy, a, b, s] = inp.curve;
    match chaikin::sheared_ellipse([cx, cy], a, b, s, clevel, &mut pts) {
        Ok(n) => {
            assert_eq!(n, chaikin::square_len(clevel));
            assert!(pts[n..].iter().all(|p| *p == sentinel));
        }
        Err(TessellateError::LevelTooDeep { .. }) => assert!(clevel > chaikin::MAX_LEVEL),
        Err(TessellateError::BufferTooSmall { needed, got, .. }) => {
            assert!(got < needed && needed == chaikin::square_len(clevel))
        }
        Err(TessellateError::InvalidShape) | Err(TessellateError::InvalidControlPolygon) => {}
        Err(e) => panic!("unexpected error {e:?}"),
    }
});
