//! Drawing the maps: the colour ramp, the logarithmic scale and the legend
//! beside a heat map.
//!
//! A heat map is the frame's size plus a legend strip on its right: image
//! pixel (x, y) for x < width is frame pixel (x, y). The legend is a
//! colour bar, one tick per decade with its label, a black swatch for 0 and,
//! when there is one, a magenta swatch for a NaN on one side only. The
//! image is at least [`MIN_HEIGHT`] pixels tall (times the scale) so that
//! the legend fits below small frames; the rows below the frame are white.

use super::font;
use image::{Rgb, RgbImage};

/// Colour of a pixel that does not differ at all.
pub const ZERO: Rgb<u8> = Rgb([0, 0, 0]);
/// Colour of a pixel where one side is NaN and the other is not.
pub const NAN: Rgb<u8> = Rgb([255, 0, 255]);
const PAPER: Rgb<u8> = Rgb([255, 255, 255]);
const INK: Rgb<u8> = Rgb([0, 0, 0]);

/// Legend strip width and the image's least height, at scale 1.
pub const LEGEND_WIDTH: u32 = 64;
pub const MIN_HEIGHT: u32 = 160;

/// A viridis-like ramp: dark violet (smallest) through blue and green to
/// yellow (largest); never black, so 0 stands out.
const RAMP: [[f64; 3]; 5] = [
    [68.0, 1.0, 84.0],
    [59.0, 82.0, 139.0],
    [33.0, 145.0, 140.0],
    [94.0, 201.0, 98.0],
    [253.0, 231.0, 37.0],
];

/// The ramp's colour at `t` in [0, 1] (clamped).
pub fn ramp(t: f64) -> Rgb<u8> {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let pos = t * (RAMP.len() - 1) as f64;
    let i = (pos.floor() as usize).min(RAMP.len() - 2);
    let f = pos - i as f64;
    Rgb(std::array::from_fn(|ch| {
        (RAMP[i][ch] + (RAMP[i + 1][ch] - RAMP[i][ch]) * f).round() as u8
    }))
}

/// One pixel's value in a heat map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Cell {
    /// The two frames agree on every channel.
    Zero,
    /// The largest channel difference (finite, > 0).
    Value(f64),
    /// A channel is NaN on one side only.
    Nan,
}

/// A logarithmic scale from 10^lo to 10^hi (lo < hi).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Scale {
    pub lo: i32,
    pub hi: i32,
}

/// The most decades a scale spans; smaller values share the lowest colour.
const MAX_DECADES: i32 = 12;

impl Scale {
    /// The decades that hold the positive values `min..=max`, from `floor`
    /// at least (10^floor is the smallest possible value, e.g. 1 ULP), at
    /// most [`MAX_DECADES`] below the top. `None` (no positive value) gives
    /// floor..floor + 1.
    pub fn covering(range: Option<(f64, f64)>, floor: i32) -> Scale {
        let Some((min, max)) = range else {
            return Scale {
                lo: floor,
                hi: floor + 1,
            };
        };
        let hi = (max.log10().ceil() as i32).max(floor + 1);
        let lo = (min.log10().floor() as i32).clamp(floor, hi - 1);
        Scale {
            lo: lo.max(hi - MAX_DECADES),
            hi,
        }
    }

    /// Where `v` (> 0) sits on the scale, 0 at 10^lo, 1 at 10^hi.
    pub fn position(&self, v: f64) -> f64 {
        (v.log10() - f64::from(self.lo)) / f64::from(self.hi - self.lo)
    }

    pub fn colour(&self, cell: Cell) -> Rgb<u8> {
        match cell {
            Cell::Zero => ZERO,
            Cell::Nan => NAN,
            Cell::Value(v) => ramp(self.position(v)),
        }
    }
}

/// What the legend of a map says.
pub struct Legend<'a> {
    /// Two short lines above the colour bar (at most 9 characters each).
    pub title: [&'a str; 2],
    pub scale: Scale,
    /// The label of the tick at 10^k.
    pub tick_label: &'a dyn Fn(i32) -> String,
    /// Whether to show the NaN swatch.
    pub nan: bool,
}

/// Font pixel size for an image of frame height `height`: 2 from 400 rows.
pub fn text_scale(height: u32) -> u32 {
    if height >= 400 {
        2
    } else {
        1
    }
}

/// The heat map of `cells` (row-major, `width` x `height`) with its legend.
pub fn heat_map(width: u32, height: u32, cells: &[Cell], legend: &Legend) -> RgbImage {
    debug_assert_eq!(cells.len(), width as usize * height as usize);
    let s = text_scale(height);
    let full_height = height.max(MIN_HEIGHT * s);
    let mut img = RgbImage::from_pixel(width + LEGEND_WIDTH * s, full_height, PAPER);
    for (i, &cell) in cells.iter().enumerate() {
        let (x, y) = ((i % width as usize) as u32, (i / width as usize) as u32);
        img.put_pixel(x, y, legend.scale.colour(cell));
    }
    draw_legend(&mut img, width, legend, s);
    img
}

fn fill(img: &mut RgbImage, x: u32, y: u32, w: u32, h: u32, colour: Rgb<u8>) {
    for yy in y..(y + h).min(img.height()) {
        for xx in x..(x + w).min(img.width()) {
            img.put_pixel(xx, yy, colour);
        }
    }
}

fn text(img: &mut RgbImage, s: &str, x: u32, y: u32, scale: u32) {
    font::draw_text(s, x, y, scale, &mut |px, py| {
        if px < img.width() && py < img.height() {
            img.put_pixel(px, py, INK);
        }
    });
}

/// Draws the legend into the strip of `img` right of column `left`.
fn draw_legend(img: &mut RgbImage, left: u32, legend: &Legend, s: u32) {
    let margin = 4 * s;
    let line = (font::GLYPH_HEIGHT + 2) * s;
    let x = left + margin;
    for (i, t) in legend.title.iter().enumerate() {
        text(img, t, x, margin + i as u32 * line, s);
    }
    let bar_width = 12 * s;
    let swatch = 10 * s;
    let swatches = if legend.nan { 2 } else { 1 };
    // Half a line of room above the top label and below the bottom one.
    let bar_top = margin + 2 * line + line / 2;
    let bar_bottom = img.height() - margin - swatches * (swatch + margin) - line / 2;
    let bar_height = bar_bottom - bar_top;
    for dy in 0..=bar_height {
        let t = f64::from(dy) / f64::from(bar_height.max(1));
        fill(img, x, bar_bottom - dy, bar_width, 1, ramp(t));
    }
    // Label every decade, or every n-th when they would overlap.
    let Scale { lo, hi } = legend.scale;
    let decades = (hi - lo) as u32;
    let step = (line * decades).div_ceil(bar_height.max(1)).max(1) as i32;
    let label_x = x + bar_width + 6 * s;
    for k in (lo..=hi).filter(|k| (k - lo) % step == 0 || *k == hi) {
        let y = bar_bottom - (bar_height * (k - lo) as u32) / decades.max(1);
        fill(img, x + bar_width, y, 4 * s, s, INK);
        let label_y = y.saturating_sub(font::GLYPH_HEIGHT * s / 2);
        text(img, &(legend.tick_label)(k), label_x, label_y, s);
    }
    let mut y = bar_bottom + line / 2 + margin;
    let mut entry = |img: &mut RgbImage, colour, label: &str| {
        fill(img, x, y, bar_width, swatch, colour);
        // The black swatch on white paper needs no frame; the label does.
        text(
            img,
            label,
            label_x,
            y + (swatch - font::GLYPH_HEIGHT * s) / 2,
            s,
        );
        y += swatch + margin;
    };
    entry(img, ZERO, "0");
    if legend.nan {
        entry(img, NAN, "NaN");
    }
}

/// Tick label of 10^k as a plain number where short ("0.001" to "1000"),
/// else "1e<k>".
pub fn decade_label(k: i32) -> String {
    match k {
        -3..=-1 => format!("0.{}1", "0".repeat((-k - 1) as usize)),
        0..=3 => format!("1{}", "0".repeat(k as usize)),
        _ => format!("1e{k}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_runs_from_violet_to_yellow_and_never_hits_black() {
        assert_eq!(ramp(0.0), Rgb([68, 1, 84]));
        assert_eq!(ramp(1.0), Rgb([253, 231, 37]));
        assert_eq!(ramp(2.0), ramp(1.0));
        // Halfway between the 2nd and 3rd control points (t = 0.375).
        assert_eq!(ramp(0.375), Rgb([46, 114, 140]));
        for i in 0..=100 {
            assert_ne!(ramp(f64::from(i) / 100.0), ZERO);
        }
    }

    #[test]
    fn scales_cover_the_values_in_whole_decades() {
        // 3e-6 .. 18 lies in 1e-6 .. 1e2.
        assert_eq!(
            Scale::covering(Some((3e-6, 18.0)), -45),
            Scale { lo: -6, hi: 2 }
        );
        // One ULP at most: 1 .. 10.
        assert_eq!(Scale::covering(Some((1.0, 1.0)), 0), Scale { lo: 0, hi: 1 });
        assert_eq!(Scale::covering(None, 0), Scale { lo: 0, hi: 1 });
        // Twelve decades at most, counted down from the top.
        assert_eq!(
            Scale::covering(Some((1e-30, 5.0)), -45),
            Scale { lo: -11, hi: 1 }
        );
        let s = Scale { lo: -6, hi: 2 };
        assert!((s.position(1e-2) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn decade_labels_are_short() {
        assert_eq!(decade_label(-3), "0.001");
        assert_eq!(decade_label(-1), "0.1");
        assert_eq!(decade_label(0), "1");
        assert_eq!(decade_label(2), "100");
        assert_eq!(decade_label(-5), "1e-5");
        assert_eq!(decade_label(7), "1e7");
        for k in -45..=45 {
            let label = decade_label(k);
            assert!(label.len() <= 5, "{label}");
            assert!(label.chars().all(font::has_glyph), "{label}");
        }
    }
}
