//! The speed-against-accuracy chart of one scene's sweep, drawn with
//! plotters as SVG and PNG.
//!
//! x: the sweep's [`Axis`]: frames per second of one Virtex-6 LX760 filled
//! with processors of the row's build ([`crate::output::device`]), log scale; or
//! one processor's LUTs or DSP48E1s, linear from 0; y: mean absolute error
//! against the f64 reference on the 0..255 scale, log scale. The mean, not the largest
//! error, because it weighs the whole frame: the largest error is one
//! pixel's, decided by rounding luck at an edge, and jumps between
//! neighbouring configurations. A mean of exactly 0 has no place on a log
//! axis: such points are drawn on the bottom edge as hollow triangles and
//! the legend says so; non-finite means (a NaN colour) are not drawn, and
//! the title counts them.
//!
//! Grey dots are the compact processor's configurations, teal ones the
//! fast processor's, the blue line and dots the Pareto front over both, a
//! green square a front point the RTL confirmed (bit- and cycle-exact on
//! its sampled pixels), a red cross one it did not, the orange triangle
//! the thesis' hardware ([`super::THESIS_DEVICE`]) at its configuration's
//! error (on the frames/s axis only: the area of its processors, built
//! from Xilinx IP cores, is not known).
//!
//! Text: plotters' own text rendering needs its `ttf` feature (font-kit,
//! which needs fontconfig and freetype) or `ab_glyph` with font bytes from
//! somewhere; neither is allowed or guaranteed. So plotters draws the shapes
//! only, and the labels are a list drawn afterwards: into the SVG as text
//! elements (the viewer picks a sans-serif font), into the PNG with golden's
//! built-in bitmap font (embedded-graphics' FONT_6X9 via
//! [`golden::diffmap::font`]). Both files carry
//! the same labels at the same places.

use super::{Axis, Row, SceneSweep, SweepError};
use crate::design::processor::ProcessorKind;
use golden::diffmap::font;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// The chart's size in pixels.
pub const WIDTH: u32 = 960;
pub const HEIGHT: u32 = 640;

const LEFT: u32 = 90;
const RIGHT: u32 = 30;
const TOP: u32 = 70;
const BOTTOM: u32 = 60;

/// PNG text: each font pixel a SCALE x SCALE square; SVG text of the same
/// height.
const SCALE: u32 = 2;
const SVG_TEXT_PX: f64 = 16.0;

const GREY: RGBColor = RGBColor(150, 150, 150);
const FRONT: RGBColor = RGBColor(30, 90, 200);
const CONFIRMED: RGBColor = RGBColor(0, 150, 60);
const FAILED: RGBColor = RGBColor(210, 30, 30);
const THESIS: RGBColor = RGBColor(230, 120, 0);

/// A label: text at a pixel, anchored by its left, centre or right edge
/// and its top.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    pub text: String,
    pub x: i32,
    pub y: i32,
    pub anchor: Anchor,
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

/// Writes the chart of `sweep` to `svg` and `png`.
pub fn write(sweep: &SceneSweep, svg: &Path, png: &Path) -> Result<(), SweepError> {
    let err = |path: &Path| {
        let path = path.to_path_buf();
        move |reason: String| SweepError::Chart {
            path: path.clone(),
            reason,
        }
    };
    {
        let root = SVGBackend::new(svg, (WIDTH, HEIGHT)).into_drawing_area();
        let labels = draw(&root, sweep).map_err(err(svg))?;
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
        let labels = draw(&root, sweep).map_err(err(png))?;
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

/// The front as steps, `points` best on the axis first: from each point
/// at its error across to the next point's x, then down to that point's
/// error (a front point's error is what can be had until the next point).
fn staircase(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut path = Vec::new();
    for (i, &(x, y)) in points.iter().enumerate() {
        if i > 0 {
            path.push((x, points[i - 1].1));
        }
        path.push((x, y));
    }
    path
}

/// Finite, comparable error of a row (None: not drawn).
fn error(r: &Row) -> Option<f64> {
    r.mean_abs_error.is_finite().then_some(r.mean_abs_error)
}

/// The y range, whole decades around the positive errors.
fn decades(rows: &[Row]) -> (i32, i32) {
    let positive: Vec<f64> = rows.iter().filter_map(error).filter(|&e| e > 0.0).collect();
    let lo = positive.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = positive.iter().copied().fold(0.0, f64::max);
    if positive.is_empty() {
        return (-6, 0);
    }
    let (lo, hi) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (lo, hi.max(lo + 1))
}

/// The x range, whole decades around the positive device frames/s.
fn fps_decades(rows: &[Row], thesis: Option<f64>) -> (i32, i32) {
    let fps: Vec<f64> = rows
        .iter()
        .map(|r| r.device_fps)
        .chain(thesis)
        .filter(|f| f.is_finite() && *f > 0.0)
        .collect();
    if fps.is_empty() {
        return (-1, 2);
    }
    let lo = fps.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = fps.iter().copied().fold(0.0, f64::max);
    let (lo, hi) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (lo, hi.max(lo + 1))
}

/// Ticks at 1, 2 or 5 times a power of ten, about six across [lo, hi].
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
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

/// The chart's x: where a value of the sweep's [`Axis`] is plotted
/// (device frames/s as its log10, so that one linear coordinate serves
/// both scales), the range, the ticks (position, label) and the title.
struct XScale {
    axis: Axis,
    lo: f64,
    hi: f64,
    ticks: Vec<(f64, String)>,
}

impl XScale {
    fn new(axis: Axis, rows: &[Row], thesis_fps: Option<f64>) -> XScale {
        match axis {
            Axis::DeviceFps => {
                let (f0, f1) = fps_decades(rows, thesis_fps);
                XScale {
                    axis,
                    lo: f64::from(f0),
                    hi: f64::from(f1),
                    ticks: (f0..=f1)
                        .map(|d| (f64::from(d), format!("{}", 10f64.powi(d))))
                        .collect(),
                }
            }
            Axis::Luts | Axis::Dsp => {
                let most = rows.iter().map(|r| axis.value(r)).fold(1.0, f64::max);
                let hi = most * 1.1;
                XScale {
                    axis,
                    lo: 0.0,
                    hi,
                    ticks: ticks(0.0, hi)
                        .into_iter()
                        .map(|t| (t, format!("{t}")))
                        .collect(),
                }
            }
        }
    }

    /// Where `value` is plotted, clamped into the range.
    fn at(&self, value: f64) -> f64 {
        let x = match self.axis {
            Axis::DeviceFps => value.log10(),
            Axis::Luts | Axis::Dsp => value,
        };
        x.clamp(self.lo, self.hi)
    }

    fn title(&self) -> String {
        let device = crate::output::device::Device::LX760.name;
        match self.axis {
            Axis::DeviceFps => {
                format!("frames/s of one {device} full of the row's processors (log)")
            }
            Axis::Luts => "slice LUTs of one processor of the row's build (Virtex-6)".into(),
            Axis::Dsp => "DSP48E1 slices of one processor of the row's build (Virtex-6)".into(),
        }
    }
}

/// Draws the shapes of the chart of `sweep` on `root` and returns its
/// labels (drawn by the caller, see the module doc).
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    sweep: &SceneSweep,
) -> Result<Vec<Label>, String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let rows = &sweep.rows;
    let (d0, d1) = decades(rows);
    let (y0, y1) = (10f64.powi(d0), 10f64.powi(d1));
    // The thesis' hardware is placed on the frames/s axis only.
    let thesis_row = sweep
        .thesis()
        .filter(|t| error(t).is_some() && sweep.axis == Axis::DeviceFps);
    let thesis_fps = thesis_row.map(|t| super::THESIS_DEVICE.frames_per_second(t.width * t.height));
    let x = XScale::new(sweep.axis, rows, thesis_fps);
    let (c0, c1) = (x.lo, x.hi);
    let mut chart = ChartBuilder::on(root)
        .margin_top(TOP)
        .margin_left(LEFT)
        .margin_right(RIGHT)
        .margin_bottom(BOTTOM)
        .build_cartesian_2d(c0..c1, (y0..y1).log_scale())
        .map_err(e)?;
    let y_of = |r: &Row| error(r).map(|v| v.max(y0)).unwrap_or(y0);
    let at = |r: &Row| (x.at(sweep.axis.value(r)), y_of(r));
    let mut labels = Vec::new();
    let label = |text: String, (x, y): (i32, i32), anchor| Label { text, x, y, anchor };

    // Grid, frame and tick labels.
    let light = ShapeStyle::from(&RGBColor(225, 225, 225)).stroke_width(1);
    for (at_x, text) in &x.ticks {
        chart
            .draw_series([PathElement::new(vec![(*at_x, y0), (*at_x, y1)], light)])
            .map_err(e)?;
        let (px, py) = chart.backend_coord(&(*at_x, y0));
        labels.push(label(text.clone(), (px, py + 8), Anchor::Center));
    }
    for d in d0..=d1 {
        let y = 10f64.powi(d);
        chart
            .draw_series([PathElement::new(vec![(c0, y), (c1, y)], light)])
            .map_err(e)?;
        let (px, py) = chart.backend_coord(&(c0, y));
        labels.push(label(format!("1e{d}"), (px - 8, py - 7), Anchor::Right));
    }
    chart
        .draw_series([Rectangle::new([(c0, y0), (c1, y1)], BLACK.stroke_width(1))])
        .map_err(e)?;

    // Every configuration; errors of exactly 0 as hollow triangles on the
    // bottom edge.
    let zero = rows.iter().filter(|r| r.mean_abs_error == 0.0).count();
    let colour = |r: &Row| {
        let (red, green, blue) = r.processor.row().colour;
        RGBColor(red, green, blue)
    };
    chart
        .draw_series(
            rows.iter()
                .filter(|r| error(r).is_some_and(|v| v > 0.0))
                .map(|r| Circle::new(at(r), 3, colour(r).filled())),
        )
        .map_err(e)?;
    chart
        .draw_series(
            rows.iter()
                .filter(|r| r.mean_abs_error == 0.0)
                .map(|r| TriangleMarker::new(at(r), 5, colour(r).stroke_width(1))),
        )
        .map_err(e)?;

    // The front, best on the axis first.
    let mut front: Vec<&Row> = rows
        .iter()
        .filter(|r| r.pareto && error(r).is_some())
        .collect();
    front.sort_by(|a, b| sweep.axis.gain(b).total_cmp(&sweep.axis.gain(a)));
    chart
        .draw_series(LineSeries::new(
            staircase(&front.iter().map(|r| at(r)).collect::<Vec<_>>()),
            FRONT.stroke_width(2),
        ))
        .map_err(e)?;
    chart
        .draw_series(front.iter().map(|r| Circle::new(at(r), 4, FRONT.filled())))
        .map_err(e)?;
    let confirmed = |want: bool| front.iter().filter(move |r| r.rtl_confirmed == Some(want));
    chart
        .draw_series(confirmed(true).map(|r| {
            EmptyElement::at(at(r)) + Rectangle::new([(-7, -7), (7, 7)], CONFIRMED.stroke_width(2))
        }))
        .map_err(e)?;
    chart
        .draw_series(confirmed(false).map(|r| Cross::new(at(r), 8, FAILED.stroke_width(3))))
        .map_err(e)?;

    // The thesis' hardware, at its configuration's error.
    if let (Some(t), Some(fps)) = (thesis_row, thesis_fps) {
        let point = (x.at(fps), y_of(t));
        chart
            .draw_series([TriangleMarker::new(point, 9, THESIS.filled())])
            .map_err(e)?;
        let (px, py) = chart.backend_coord(&point);
        // Beside the marker, on the side with room.
        let (x, anchor) = if px > (WIDTH / 2) as i32 {
            (px - 12, Anchor::Right)
        } else {
            (px + 12, Anchor::Left)
        };
        labels.push(label(
            "thesis: 2 processors, 28.86 MHz".into(),
            (x, py - 24),
            anchor,
        ));
    }

    // Titles.
    let (w, h) = (sweep.scene.camera.width, sweep.scene.camera.height);
    let skipped = sweep.skipped.len();
    let nonfinite = rows.iter().filter(|r| error(r).is_none()).count();
    let mut title = format!(
        "{} {w}x{h}: {} configurations, {skipped} refused by the scene",
        sweep.name,
        rows.len()
    );
    if nonfinite > 0 {
        title += &format!(", {nonfinite} with non-finite error not drawn");
    }
    labels.push(label(title, (LEFT as i32, 10), Anchor::Left));
    labels.push(label(
        "mean |error| vs f64 reference (0..255, log)".into(),
        (LEFT as i32, TOP as i32 - 26),
        Anchor::Left,
    ));
    labels.push(label(
        x.title(),
        (
            (LEFT + (WIDTH - LEFT - RIGHT) / 2) as i32,
            (HEIGHT - BOTTOM) as i32 + 32,
        ),
        Anchor::Center,
    ));

    // Legend, top left (the slow, inaccurate corner, which the front
    // leaves empty): a marker and its text per line.
    let mut legend: Vec<(String, RGBColor)> = ProcessorKind::ALL
        .iter()
        .map(|k| {
            let (red, green, blue) = k.row().colour;
            (format!("{k} processor"), RGBColor(red, green, blue))
        })
        .collect();
    legend.push(("Pareto front".into(), FRONT));
    legend.push(("RTL-confirmed (bit+cycle)".into(), CONFIRMED));
    if front.iter().any(|r| r.rtl_confirmed == Some(false)) {
        legend.push(("RTL check failed".into(), FAILED));
    }
    if thesis_row.is_some() {
        legend.push(("thesis' hardware".into(), THESIS));
    }
    if zero > 0 {
        legend.push((format!("error exactly 0 ({zero}): bottom edge"), GREY));
    }
    let lx = LEFT as i32 + 12;
    for (i, (text, colour)) in legend.iter().enumerate() {
        let ly = TOP as i32 + 12 + 24 * i as i32;
        root.draw(&Rectangle::new(
            [(lx, ly + 2), (lx + 10, ly + 12)],
            colour.filled(),
        ))
        .map_err(e)?;
        labels.push(label(text.to_string(), (lx + 18, ly), Anchor::Left));
    }
    Ok(labels)
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
