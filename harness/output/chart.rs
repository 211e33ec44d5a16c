//! Charts as SVG and PNG: the frame every chart of rtcosim is drawn in (the
//! sweep's speed against accuracy, the guided fuzzer's coverage against
//! candidates).
//!
//! Text: plotters' own text rendering needs its `ttf` feature (font-kit,
//! which needs fontconfig and freetype) or `ab_glyph` with font bytes from
//! somewhere; neither is allowed or guaranteed. So plotters draws the shapes
//! only, and a chart's labels are a list drawn afterwards: into the SVG as
//! text elements (the viewer picks a sans-serif font), into the PNG with
//! golden's built-in bitmap font (embedded-graphics' FONT_6X9 via
//! [`golden::diffmap::font`]). Both files carry the same labels at the same
//! places.

use golden::diffmap::font;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};

/// A chart's size in pixels.
pub const WIDTH: u32 = 960;
pub const HEIGHT: u32 = 640;

/// The margins around the plot area.
pub const LEFT: u32 = 90;
pub const RIGHT: u32 = 30;
pub const TOP: u32 = 70;
pub const BOTTOM: u32 = 60;

/// PNG text: each font pixel a SCALE x SCALE square; SVG text of the same
/// height.
const SCALE: u32 = 2;
const SVG_TEXT_PX: f64 = 16.0;

/// A label: text at a pixel, anchored by its left, centre or right edge
/// and its top.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    pub text: String,
    pub x: i32,
    pub y: i32,
    pub anchor: Anchor,
}

impl Label {
    pub fn new(text: impl Into<String>, (x, y): (i32, i32), anchor: Anchor) -> Label {
        Label {
            text: text.into(),
            x,
            y,
            anchor,
        }
    }
}

/// Which edge of a label its x is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Left,
    Center,
    Right,
}

impl From<Anchor> for HPos {
    fn from(a: Anchor) -> HPos {
        match a {
            Anchor::Left => HPos::Left,
            Anchor::Center => HPos::Center,
            Anchor::Right => HPos::Right,
        }
    }
}

/// A chart: draws its shapes on any backend and returns its labels.
pub trait Drawing {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>)
        -> Result<Vec<Label>, String>;
}

/// A chart that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct ChartError {
    pub path: PathBuf,
    pub reason: String,
}

/// Writes `chart` to `svg` and `png`.
pub fn write(chart: &impl Drawing, svg: &Path, png: &Path) -> Result<(), ChartError> {
    let err = |path: &Path| {
        let path = path.to_path_buf();
        move |reason: String| ChartError {
            path: path.clone(),
            reason,
        }
    };
    {
        let root = SVGBackend::new(svg, (WIDTH, HEIGHT)).into_drawing_area();
        let labels = chart.draw(&root).map_err(err(svg))?;
        for l in &labels {
            let style = ("sans-serif", SVG_TEXT_PX)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(l.anchor.into(), VPos::Top));
            root.draw(&Text::new(l.text.as_str(), (l.x, l.y), style))
                .map_err(|e| err(svg)(e.to_string()))?;
        }
        root.present().map_err(|e| err(svg)(e.to_string()))?;
    }
    let mut buf = vec![0u8; WIDTH as usize * HEIGHT as usize * 3];
    let labels = {
        let root = BitMapBackend::with_buffer(&mut buf, (WIDTH, HEIGHT)).into_drawing_area();
        let labels = chart.draw(&root).map_err(err(png))?;
        root.present().map_err(|e| err(png)(e.to_string()))?;
        labels
    };
    let mut img = image::RgbImage::from_raw(WIDTH, HEIGHT, buf).expect("3 bytes a pixel");
    for l in &labels {
        let w = font::text_width(&l.text, SCALE) as i32;
        let left = match l.anchor {
            Anchor::Left => l.x,
            Anchor::Center => l.x - w / 2,
            Anchor::Right => l.x - w,
        };
        font::draw_text(&l.text, 0, 0, SCALE, &mut |dx, dy| {
            let (x, y) = (left + dx as i32, l.y + dy as i32);
            if (0..WIDTH as i32).contains(&x) && (0..HEIGHT as i32).contains(&y) {
                img.put_pixel(x as u32, y as u32, image::Rgb([0, 0, 0]));
            }
        });
    }
    img.save_with_format(png, image::ImageFormat::Png)
        .map_err(|e| err(png)(e.to_string()))
}

/// Ticks at 1, 2 or 5 times a power of ten, about six across [lo, hi].
pub fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let raw = (hi - lo) / 6.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// A legend at the plot area's left, its first line at `top`: a colour
/// square and its text per line; returns the texts' labels.
pub fn legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    entries: &[(String, RGBColor)],
    top: i32,
) -> Result<Vec<Label>, String> {
    let lx = LEFT as i32 + 12;
    let mut labels = Vec::new();
    for (i, (text, colour)) in entries.iter().enumerate() {
        let ly = top + 24 * i as i32;
        root.draw(&Rectangle::new(
            [(lx, ly + 2), (lx + 10, ly + 12)],
            colour.filled(),
        ))
        .map_err(|e| e.to_string())?;
        labels.push(Label::new(text.clone(), (lx + 18, ly), Anchor::Left));
    }
    Ok(labels)
}

/// The x axis' title, centred under the plot area.
pub fn x_title(text: impl Into<String>) -> Label {
    Label::new(
        text,
        (
            (LEFT + (WIDTH - LEFT - RIGHT) / 2) as i32,
            (HEIGHT - BOTTOM) as i32 + 32,
        ),
        Anchor::Center,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_inside() {
        assert_eq!(
            ticks(0.0, 600.0),
            vec![0.0, 100.0, 200.0, 300.0, 400.0, 500.0, 600.0]
        );
        let t = ticks(137.0, 391.0);
        assert_eq!(t.first(), Some(&150.0));
        assert_eq!(t.last(), Some(&350.0));
    }
}
