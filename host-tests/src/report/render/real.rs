//! The report's renders of real data: the ocean globe and PREM, each against the Cartesian baseline, with figures.

use super::*;

/// Renders the ocean and PREM on their own: the globe from space and a grazing view along the horizon
/// (emission–absorption), and PREM's travel-time image.
pub(super) fn real_renders(opts: &Options) -> anyhow::Result<String> {
    let mut md = String::new();
    let (grid, values) = data::ocean()?;
    let tf = Transfer {
        lo: -2.0,
        hi: 30.0,
        opacity: 1.0 / 200.0,
        cutoff: 0.99,
    };
    let side = if opts.quick { 160 } else { 480 };
    // grazing: 300 km above 30°N 136°W, looking east-north-east at the horizon (17.2° below the horizontal from
    // there), toward California
    let (lat, lon) = (30f64.to_radians(), (-136f64).to_radians());
    let up = [lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()];
    let north = [-lat.sin() * lon.cos(), -lat.sin() * lon.sin(), lat.cos()];
    let east = [-lon.sin(), lon.cos(), 0.0];
    let ahead = [0, 1, 2].map(|k| 0.9 * east[k] + 0.45 * north[k]);
    let eye = up.map(|x| x * (EARTH_RADIUS_M + 300e3));
    let dip = (EARTH_RADIUS_M / (EARTH_RADIUS_M + 300e3)).acos();
    let look = [0, 1, 2].map(|k| eye[k] + 3000e3 * (ahead[k] / 1.006 - dip.tan() * up[k]));
    let views = [
        (
            "ocean_globe.png",
            ocean_globe_camera(),
            [side, side],
            "the globe from space (orthographic)",
        ),
        (
            "ocean_grazing.png",
            CameraSpec::Perspective {
                eye,
                look_at: look,
                up,
                fov_deg: 70.0,
            },
            [side * 2, side],
            "a grazing view along the horizon from 300 km above the North Pacific, looking toward California (perspective, 70°)",
        ),
    ];
    for (file, camera, pixels, what) in views {
        let scene = Scene {
            grid: grid.clone().into(),
            values: values.clone(),
            camera: Camera::new(&camera, pixels).map_err(anyhow::Error::msg)?,
            pixels,
            mode: Mode::EmissionAbsorption(tf),
            method: Method::Native,
            precision: Precision::F64,
        };
        let out = render(&scene, &|| {});
        let range = finite_range(&out.values);
        let image = colorize(&out.values, pixels[0], pixels[1], range, ColorMap::Inferno);
        let panels = [Panel {
            image: &image,
            title: "ocean temperature, emission-absorption",
        }];
        let scale = Scale {
            range,
            map: ColorMap::Inferno,
            unit: "intensity",
        };
        write_png(&opts.out_dir.join(file), &figure(&[(&panels, scale)]))?;
        let _ = writeln!(
            md,
            "![ocean temperature, {what}]({file})\n\nOcean temperature, {what}: emission–absorption (−2 °C to 30 °C \
             mapped to 0–1, extinction 1/200 m⁻¹ at full scale: the top few hundred meters show; land is empty, so rays \
             through it reach the far side's deep, cold water from below, early termination at opacity 0.99), {}×{} pixels \
             in {} natively ({:.0} cells per ray).\n",
            pixels[0],
            pixels[1],
            ms(out.seconds),
            out.crossings as f64 / out.rays as f64
        );
    }
    let model = data::prem()?;
    let (g, v) = model.grid(4, 45, 90);
    let r = g.outer_radius();
    let pixels = [side, side];
    let scene = Scene {
        grid: g.into(),
        values: v,
        camera: Camera::new(
            &CameraSpec::Perspective {
                eye: [2.2 * r, -1.4 * r, 0.9 * r],
                look_at: [0.0; 3],
                up: [0.0, 0.0, 1.0],
                fov_deg: 45.0,
            },
            pixels,
        )
        .map_err(anyhow::Error::msg)?,
        pixels,
        mode: Mode::TravelTime,
        method: Method::Native,
        precision: Precision::F64,
    };
    let out = render(&scene, &|| {});
    let range = finite_range(&out.values);
    let image = colorize(&out.values, side, side, range, ColorMap::Viridis);
    let panels = [Panel {
        image: &image,
        title: "PREM, P travel time",
    }];
    let scale = Scale {
        range,
        map: ColorMap::Viridis,
        unit: "s",
    };
    write_png(
        &opts.out_dir.join("prem_travel_time.png"),
        &figure(&[(&panels, scale)]),
    )?;
    let [lo, hi] = finite_range(&out.values);
    let _ = writeln!(
        md,
        "![PREM travel times](prem_travel_time.png)\n\nPREM: straight-ray P travel time through the whole Earth \
         (perspective view; {} cells, each linear piece of the model cut in 4; {lo:.0} s to {hi:.0} s, viridis), \
         {side}×{side} pixels in {} natively.\n",
        cells_label(scene.grid.shape()),
        ms(out.seconds)
    );
    Ok(md)
}
