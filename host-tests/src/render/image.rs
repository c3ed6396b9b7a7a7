//! PNG output of `curvicast render` and the report: values mapped through a perceptual colour map (`colorous`),
//! encoded with the `png` crate; several images of the same size side by side.

use std::path::Path;

/// The colour map of an image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorMap {
    /// Viridis (projections, travel times).
    Viridis,
    /// Inferno (emission–absorption intensities).
    Inferno,
    /// Magma (error maps).
    Magma,
}

/// An RGB image.
#[derive(Debug, Clone, PartialEq)]
pub struct Rgb {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Row-major RGB bytes, row 0 at the top.
    pub data: Vec<u8>,
}

/// The smallest and largest finite value (`[0, 1]` when there is none; widened when they are equal).
pub fn finite_range(values: &[f64]) -> [f64; 2] {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        [0.0, 1.0]
    } else if lo == hi {
        [lo, lo + 1.0]
    } else {
        [lo, hi]
    }
}

/// The smallest finite value and the `q`-quantile of the finite values (`q` in (0, 1]): a colour range that a few
/// extreme pixels (the limb of a thin shell) do not wash out.
pub fn quantile_range(values: &[f64], q: f64) -> [f64; 2] {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return [0.0, 1.0];
    }
    v.sort_by(f64::total_cmp);
    let hi = v[((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize];
    if hi > v[0] {
        [v[0], hi]
    } else {
        finite_range(values)
    }
}

/// Maps `values` (row-major, `width × height`) linearly from `range` onto the colour map; NaN is mid grey.
pub fn colorize(
    values: &[f64],
    width: usize,
    height: usize,
    range: [f64; 2],
    map: ColorMap,
) -> Rgb {
    let gradient = match map {
        ColorMap::Viridis => colorous::VIRIDIS,
        ColorMap::Inferno => colorous::INFERNO,
        ColorMap::Magma => colorous::MAGMA,
    };
    let mut data = Vec::with_capacity(values.len() * 3);
    for &v in values {
        if v.is_finite() {
            let t = ((v - range[0]) / (range[1] - range[0])).clamp(0.0, 1.0);
            let c = gradient.eval_continuous(t);
            data.extend_from_slice(&[c.r, c.g, c.b]);
        } else {
            data.extend_from_slice(&[128, 128, 128]);
        }
    }
    Rgb {
        width,
        height,
        data,
    }
}

/// Images of equal height placed left to right with `gap` white columns between them.
pub fn side_by_side(images: &[&Rgb], gap: usize) -> Rgb {
    let height = images.iter().map(|i| i.height).max().unwrap_or(0);
    let width =
        images.iter().map(|i| i.width).sum::<usize>() + gap * images.len().saturating_sub(1);
    let mut data = vec![255u8; width * height * 3];
    let mut x0 = 0;
    for img in images {
        for row in 0..img.height {
            let src = &img.data[row * img.width * 3..(row + 1) * img.width * 3];
            let dst = (row * width + x0) * 3;
            data[dst..dst + src.len()].copy_from_slice(src);
        }
        x0 += img.width + gap;
    }
    Rgb {
        width,
        height,
        data,
    }
}

/// Writes `img` as an 8-bit RGB PNG.
pub fn write_png(path: &Path, img: &Rgb) -> anyhow::Result<()> {
    let file = std::fs::File::create(path)
        .map_err(|e| anyhow::anyhow!("{}: cannot create: {e}", path.display()))?;
    let mut enc = png::Encoder::new(
        std::io::BufWriter::new(file),
        u32::try_from(img.width)?,
        u32::try_from(img.height)?,
    );
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc
        .write_header()
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    w.write_image_data(&img.data)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    w.finish()
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(())
}
