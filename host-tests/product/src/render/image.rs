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
    let gradient = gradient(map);
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

/// One image of a [`figure`] and the title written above it.
#[derive(Debug, Clone, Copy)]
pub struct Panel<'a> {
    /// The colour-mapped image.
    pub image: &'a Rgb,
    /// Its title.
    pub title: &'a str,
}

/// The colour scale of a group of panels: the range the colour map spans and what the values are, with units.
#[derive(Debug, Clone, Copy)]
pub struct Scale<'a> {
    /// The values at the bottom and the top of the colour bar.
    pub range: [f64; 2],
    /// The colour map.
    pub map: ColorMap,
    /// What the values are, with their unit (written above the colour bar).
    pub unit: &'a str,
}

/// The smallest panel height of a figure, and the smallest long side: small renders are enlarged (each pixel
/// drawn as a k × k block) until both hold, so that a reader sees the data and can read the labels.
const MIN_PANEL: usize = 256;
const MIN_LONG_SIDE: usize = 512;

/// A figure: groups of panels side by side, each panel with its title above it and each group followed by the
/// colour bar of its scale, with five labelled ticks and the scale's unit. Panels are enlarged by a whole factor
/// until they are at least 256 pixels high and the figure at least 512 pixels wide.
pub fn figure(groups: &[(&[Panel], Scale)]) -> Rgb {
    let h = groups
        .iter()
        .flat_map(|(p, _)| p.iter().map(|p| p.image.height))
        .max()
        .unwrap_or(1)
        .max(1);
    let text = 2; // font scale: 16-pixel glyphs
    let glyph = 8 * text;
    let text_w = |s: &str| s.chars().count() * glyph;
    let (gap, bar, tick_len, tick_gap) = (16, 24, 6, 6);
    let ticks: Vec<Vec<String>> = groups
        .iter()
        .map(|(_, s)| {
            (0..5)
                .map(|i| tick(s.range[0] + (s.range[1] - s.range[0]) * i as f64 / 4.0))
                .collect()
        })
        .collect();
    // Each panel's column: the wider of the enlarged image and its title; each colour bar's: the wider of the bar
    // with its tick labels and the unit.
    let bar_w = |g: usize, unit: &str| {
        let labels = ticks[g].iter().map(|t| text_w(t)).max().unwrap_or(0);
        (bar + tick_len + tick_gap + labels).max(text_w(unit))
    };
    let width_at = |k: usize| -> usize {
        gap + groups
            .iter()
            .enumerate()
            .map(|(g, (panels, scale))| {
                let panels_w: usize = panels
                    .iter()
                    .map(|p| (p.image.width * k).max(text_w(p.title)) + gap)
                    .sum();
                panels_w + bar_w(g, scale.unit) + 2 * gap
            })
            .sum::<usize>()
    };
    let mut k = MIN_PANEL.div_ceil(h).max(1);
    while width_at(k).max(h * k) < MIN_LONG_SIDE {
        k += 1;
    }
    let top = glyph + 2 * gap;
    let (width, height) = (width_at(k), top + h * k + glyph + gap);
    let mut out = Rgb {
        width,
        height,
        data: vec![255; width * height * 3],
    };
    let mut x = gap;
    for (g, (panels, scale)) in groups.iter().enumerate() {
        for p in panels.iter() {
            draw_text(&mut out, x, gap, p.title, text);
            blit_scaled(&mut out, p.image, x, top, k);
            x += (p.image.width * k).max(text_w(p.title)) + gap;
        }
        // The colour bar: top = range[1], bottom = range[0].
        let bar_h = h * k;
        draw_text(&mut out, x, gap, scale.unit, text);
        for row in 0..bar_h {
            let t = 1.0 - row as f64 / (bar_h - 1).max(1) as f64;
            let c = gradient(scale.map).eval_continuous(t);
            for col in 0..bar {
                out.set(x + col, top + row, [c.r, c.g, c.b]);
            }
        }
        for (i, label) in ticks[g].iter().enumerate() {
            let y = top + (bar_h - 1) * (4 - i) / 4;
            for col in bar..bar + tick_len {
                out.set(x + col, y, [0, 0, 0]);
            }
            let ty = y.saturating_sub(glyph / 2).min(height - glyph);
            draw_text(&mut out, x + bar + tick_len + tick_gap, ty, label, text);
        }
        x += bar_w(g, scale.unit) + 2 * gap;
    }
    out
}

/// A tick label: plain decimals (at most 3 significant digits after trimming) in `[0.01, 1e5)`, scientific
/// otherwise.
fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    if (0.01..1e5).contains(&v.abs()) {
        let digits = (2 - v.abs().log10().floor() as i32).clamp(0, 4) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

fn gradient(map: ColorMap) -> colorous::Gradient {
    match map {
        ColorMap::Viridis => colorous::VIRIDIS,
        ColorMap::Inferno => colorous::INFERNO,
        ColorMap::Magma => colorous::MAGMA,
    }
}

impl Rgb {
    /// Sets one pixel (outside the image: nothing).
    fn set(&mut self, x: usize, y: usize, rgb: [u8; 3]) {
        if x < self.width && y < self.height {
            let i = (y * self.width + x) * 3;
            self.data[i..i + 3].copy_from_slice(&rgb);
        }
    }
}

/// Copies `src` into `dst` at `(x, y)`, each pixel drawn as a `k × k` block.
fn blit_scaled(dst: &mut Rgb, src: &Rgb, x: usize, y: usize, k: usize) {
    for row in 0..src.height * k {
        for col in 0..src.width * k {
            let i = ((row / k) * src.width + col / k) * 3;
            dst.set(
                x + col,
                y + row,
                [src.data[i], src.data[i + 1], src.data[i + 2]],
            );
        }
    }
}

/// Writes `text` in black with its top-left corner at `(x, y)`, in the 8 × 8 bitmap font (font8x8: basic Latin,
/// Latin-1 and Greek) enlarged `scale` times; a character the font lacks is drawn as `?`.
fn draw_text(img: &mut Rgb, x: usize, y: usize, text: &str, scale: usize) {
    use font8x8::UnicodeFonts;
    for (n, ch) in text.chars().enumerate() {
        let rows = font8x8::BASIC_FONTS
            .get(ch)
            .or_else(|| font8x8::LATIN_FONTS.get(ch))
            .or_else(|| font8x8::GREEK_FONTS.get(ch))
            .or_else(|| font8x8::BASIC_FONTS.get('?'))
            .unwrap_or([0; 8]);
        for (r, bits) in rows.iter().enumerate() {
            for c in 0..8 {
                if bits & (1 << c) != 0 {
                    for dy in 0..scale {
                        for dx in 0..scale {
                            img.set(x + (n * 8 + c) * scale + dx, y + r * scale + dy, [0, 0, 0]);
                        }
                    }
                }
            }
        }
    }
}
