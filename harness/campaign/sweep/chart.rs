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
//! Its labels are drawn by [`crate::output::chart`].

use super::{Axis, Row, SceneSweep, SweepError};
use crate::design::processor::ProcessorKind;
use crate::output::chart::{self, ticks, Anchor, Drawing, Label, LEFT, TOP, WIDTH};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

const RIGHT: u32 = chart::RIGHT;
const BOTTOM: u32 = chart::BOTTOM;

const GREY: RGBColor = RGBColor(150, 150, 150);
const FRONT: RGBColor = RGBColor(30, 90, 200);
const CONFIRMED: RGBColor = RGBColor(0, 150, 60);
const FAILED: RGBColor = RGBColor(210, 30, 30);
const THESIS: RGBColor = RGBColor(230, 120, 0);

/// Writes the chart of `sweep` to `svg` and `png`.
pub fn write(sweep: &SceneSweep, svg: &Path, png: &Path) -> Result<(), SweepError> {
    chart::write(&Chart(sweep), svg, png).map_err(|e| SweepError::Chart {
        path: e.path,
        reason: e.reason,
    })
}

struct Chart<'a>(&'a SceneSweep);

impl Drawing for Chart<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<Vec<Label>, String> {
        draw(root, self.0)
    }
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
    let label = |text: String, at: (i32, i32), anchor| Label::new(text, at, anchor);

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
    labels.push(chart::x_title(x.title()));

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
    labels.extend(chart::legend(root, &legend, TOP as i32 + 12)?);
    Ok(labels)
}
