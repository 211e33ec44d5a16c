//! Difference maps of two frames, as the thesis drew them (figure 17, section
//! 4.11) and the table beside them: where and by how much two renders of a
//! scene differ.
//!
//! It lives in `golden`, beside [`frame`](crate::frame), because it needs no
//! Verilator: it compares two [`Frame`]s, whoever made them. `rtcosim
//! diffmap` (tools/diffmap.rs) gets the frames (from frame files, the golden
//! models, or the verilated RTL) and calls [`DiffMap::write`].
//!
//! # What is measured
//!
//! Per pixel and channel, on the thesis' 0..255 scale, `|a - b| * 255` (a NaN
//! on either side counts as an infinite difference, as in
//! [`Frame::compare`]); and the ULP distance of the two values as f32
//! ([`crate::fp::ulp_distance`], +0 and -0 equal). A channel of the f64
//! reference is first rounded to the nearest f32, so it is 0 ULP from the f32
//! closest to it: a difference below half an f32 ULP shows in the absolute
//! map and the table but not in the ULP map. Frames of the micro-op model and
//! of the RTL are f32 values, so their ULP distances are exact.
//!
//! # What is written
//!
//! - `heat-ulp.png`: per pixel the largest ULP distance of its three
//!   channels, on a log scale with a legend (see [`draw`]);
//! - `heat-abs.png`: per pixel the largest absolute difference, likewise;
//! - `mask-<threshold>.png`, one per threshold: the frame's size, a pixel
//!   black where any channel differs by more than the threshold, else white
//!   (thesis figure 17);
//! - `table.md` and `table.json`: the [`Table`].

pub mod draw;
pub mod font;

use crate::fp::{ulp_distance, UlpDistance};
use crate::frame::{Frame, FrameError};
use draw::{Cell, Legend, Scale};
use image::{GrayImage, Luma, RgbImage};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The thesis' thresholds (0..255 scale): the table near its figure 17.
pub const THESIS_THRESHOLDS: [f64; 3] = [0.00001, 0.0001, 0.5];

/// How many of the largest differences the table lists.
pub const LARGEST: usize = 3;

const CHANNELS: [&str; 3] = ["R", "G", "B"];

/// The legends' titles: the ULP map's and the absolute map's.
const ULP_TITLE: [&str; 2] = ["largest", "ulp"];
const ABS_TITLE: [&str; 2] = ["|a-b|", "x255"];

/// Why maps cannot be made or written.
#[derive(Debug, thiserror::Error)]
pub enum DiffMapError {
    #[error(transparent)]
    Frame(#[from] FrameError),
    #[error("{}: cannot write", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: cannot write the PNG", path.display())]
    Png {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
}

/// Two frames' differences, pixel by pixel and channel by channel.
#[derive(Debug, Clone, PartialEq)]
pub struct DiffMap {
    width: u32,
    height: u32,
    /// Row-major: |a - b| * 255 per channel (infinite for a NaN on one side
    /// or both).
    abs: Vec<[f64; 3]>,
    /// Row-major: the ULP distance per channel, both as f32.
    ulps: Vec<[UlpDistance; 3]>,
}

impl DiffMap {
    /// The differences of `a` and `b`, which must have the same size.
    pub fn new(a: &Frame, b: &Frame) -> Result<DiffMap, FrameError> {
        if (a.width, a.height) != (b.width, b.height) {
            return Err(FrameError::SizeMismatch(
                a.width, a.height, b.width, b.height,
            ));
        }
        let abs = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| {
                std::array::from_fn(|ch| {
                    let d = (p[ch] - q[ch]).abs() * 255.0;
                    if d.is_nan() {
                        f64::INFINITY
                    } else {
                        d
                    }
                })
            })
            .collect();
        let ulps = a
            .pixels
            .iter()
            .zip(&b.pixels)
            .map(|(p, q)| std::array::from_fn(|ch| ulp_distance(p[ch] as f32, q[ch] as f32, true)))
            .collect();
        Ok(DiffMap {
            width: a.width,
            height: a.height,
            abs,
            ulps,
        })
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    fn xy(&self, i: usize) -> (u32, u32) {
        let w = self.width as usize;
        ((i % w) as u32, (i / w) as u32)
    }

    /// The largest absolute difference of each pixel, and its channel.
    fn pixel_abs(&self) -> impl Iterator<Item = (f64, usize)> + '_ {
        self.abs.iter().map(|p| {
            (0..3).fold(
                (p[0], 0),
                |best, ch| {
                    if p[ch] > best.0 {
                        (p[ch], ch)
                    } else {
                        best
                    }
                },
            )
        })
    }

    /// The table for `thresholds` (0..255 scale); `a` and `b` say what was
    /// compared.
    pub fn table(&self, a: &str, b: &str, thresholds: &[f64]) -> Table {
        let channels = self.abs.len() as u64 * 3;
        let values = || self.abs.iter().flatten().copied();
        let rows = thresholds
            .iter()
            .map(|&threshold| {
                let (over, sum) = values()
                    .filter(|&d| d > threshold)
                    .fold((0u64, 0.0), |(n, s), d| (n + 1, s + d));
                Row {
                    threshold,
                    over,
                    share: if channels == 0 {
                        0.0
                    } else {
                        over as f64 / channels as f64
                    },
                    mean_over: (over > 0).then(|| sum / over as f64),
                }
            })
            .collect();
        let mut pixels: Vec<(usize, f64, usize)> = self
            .pixel_abs()
            .enumerate()
            .filter(|(_, (d, _))| *d > 0.0)
            .map(|(i, (d, ch))| (i, d, ch))
            .collect();
        // Largest first; ties in row order.
        pixels.sort_by(|p, q| q.1.total_cmp(&p.1).then(p.0.cmp(&q.0)));
        let largest = pixels
            .iter()
            .take(LARGEST)
            .map(|&(i, value, ch)| {
                let (x, y) = self.xy(i);
                Largest {
                    value,
                    x,
                    y,
                    channel: CHANNELS[ch],
                    ulps: ulps_of(self.ulps[i][ch]),
                }
            })
            .collect();
        let mut max_ulps = 0;
        let mut max_ulps_at = None;
        let mut nan_mismatches = 0;
        for (i, p) in self.ulps.iter().enumerate() {
            for (ch, d) in p.iter().enumerate() {
                match *d {
                    UlpDistance::Ulps(u) if u > max_ulps => {
                        max_ulps = u;
                        let (x, y) = self.xy(i);
                        max_ulps_at = Some(Place {
                            x,
                            y,
                            channel: CHANNELS[ch],
                        });
                    }
                    UlpDistance::Ulps(_) => {}
                    UlpDistance::NanMismatch => nan_mismatches += 1,
                }
            }
        }
        Table {
            a: a.to_string(),
            b: b.to_string(),
            width: self.width,
            height: self.height,
            channels,
            differing: values().filter(|&d| d > 0.0).count() as u64,
            rows,
            largest,
            max_ulps,
            max_ulps_at,
            nan_mismatches,
        }
    }

    /// The thesis' mask (figure 17): the frame's size, black where any
    /// channel differs by more than `threshold` (0..255 scale), else white.
    pub fn mask(&self, threshold: f64) -> GrayImage {
        let mut img = GrayImage::new(self.width, self.height);
        for (i, p) in self.abs.iter().enumerate() {
            let (x, y) = self.xy(i);
            let over = p.iter().any(|&d| d > threshold);
            img.put_pixel(x, y, Luma([if over { 0 } else { 255 }]));
        }
        img
    }

    /// Heat map of the largest ULP distance per pixel, with its legend; with
    /// `block` > 1, per block of `block` x `block` pixels (see [`pool`]).
    pub fn ulp_heat_map(&self, block: u32) -> RgbImage {
        let cells: Vec<Cell> = self
            .ulps
            .iter()
            .map(|p| match p.iter().max().copied() {
                Some(UlpDistance::Ulps(0)) | None => Cell::Zero,
                Some(UlpDistance::Ulps(u)) => Cell::Value(f64::from(u)),
                Some(UlpDistance::NanMismatch) => Cell::Nan,
            })
            .collect();
        self.heat_map(&cells, block, ULP_TITLE, 0)
    }

    /// Heat map of the largest absolute difference per pixel (0..255 scale),
    /// with its legend; with `block` > 1, per block (see [`pool`]).
    pub fn abs_heat_map(&self, block: u32) -> RgbImage {
        let cells: Vec<Cell> = self
            .pixel_abs()
            .map(|(d, _)| {
                if d == 0.0 {
                    Cell::Zero
                } else if d.is_finite() {
                    Cell::Value(d)
                } else {
                    Cell::Nan
                }
            })
            .collect();
        // The smallest positive f64 difference is about 1e-322.
        self.heat_map(&cells, block, ABS_TITLE, -330)
    }

    fn heat_map(&self, cells: &[Cell], block: u32, title: [&str; 2], floor: i32) -> RgbImage {
        let (width, height, cells) = pool(self.width, self.height, cells, block);
        let range = cells.iter().fold(None, |r, c| match (r, c) {
            (None, Cell::Value(v)) => Some((*v, *v)),
            (Some((lo, hi)), Cell::Value(v)) => Some((v.min(lo), v.max(hi))),
            (r, _) => r,
        });
        let legend = Legend {
            title,
            scale: Scale::covering(range, floor),
            tick_label: &draw::decade_label,
            nan: cells.contains(&Cell::Nan),
        };
        draw::heat_map(width, height, &cells, &legend)
    }

    /// Writes the heat maps (pooled over `block` x `block` pixels), one
    /// mask per threshold (full size) and the table (as Markdown and JSON)
    /// into `dir`, which must exist; returns the paths written and the table.
    pub fn write(
        &self,
        dir: &Path,
        a: &str,
        b: &str,
        thresholds: &[f64],
        block: u32,
    ) -> Result<(Vec<PathBuf>, Table), DiffMapError> {
        let mut written = Vec::new();
        let mut png = |name: String, img: image::DynamicImage| {
            let path = dir.join(name);
            img.save_with_format(&path, image::ImageFormat::Png)
                .map_err(|source| DiffMapError::Png {
                    path: path.clone(),
                    source,
                })?;
            written.push(path);
            Ok::<_, DiffMapError>(())
        };
        png("heat-ulp.png".into(), self.ulp_heat_map(block).into())?;
        png("heat-abs.png".into(), self.abs_heat_map(block).into())?;
        for &t in thresholds {
            png(mask_name(t), self.mask(t).into())?;
        }
        let table = self.table(a, b, thresholds);
        let json = serde_json::to_string_pretty(&table).expect("a table serializes");
        for (name, text) in [("table.md", table.markdown()), ("table.json", json + "\n")] {
            let path = dir.join(name);
            std::fs::write(&path, text).map_err(|source| DiffMapError::Write {
                path: path.clone(),
                source,
            })?;
            written.push(path);
        }
        Ok((written, table))
    }
}

/// Pools `cells` (row-major, `width` x `height`) over blocks of `block` x
/// `block` pixels (the last ones smaller where the size is not a multiple):
/// each block is its worst cell (a NaN, else the largest value, else zero),
/// so a difference is never hidden. Returns the pooled width, height and
/// cells; `block` 0 or 1 keeps them.
pub fn pool(width: u32, height: u32, cells: &[Cell], block: u32) -> (u32, u32, Vec<Cell>) {
    if block <= 1 {
        return (width, height, cells.to_vec());
    }
    let (w, h) = (width.div_ceil(block), height.div_ceil(block));
    let mut pooled = vec![Cell::Zero; w as usize * h as usize];
    for (i, &cell) in cells.iter().enumerate() {
        let (x, y) = (i as u32 % width, i as u32 / width);
        let p = &mut pooled[((y / block) * w + x / block) as usize];
        *p = match (*p, cell) {
            (Cell::Nan, _) | (_, Cell::Zero) => *p,
            (_, Cell::Nan) | (Cell::Zero, _) => cell,
            (Cell::Value(v), Cell::Value(c)) => Cell::Value(v.max(c)),
        };
    }
    (w, h, pooled)
}

/// The file name of the mask at `threshold`: `mask-0.00001.png`.
pub fn mask_name(threshold: f64) -> String {
    format!("mask-{threshold}.png")
}

fn ulps_of(d: UlpDistance) -> Option<u32> {
    match d {
        UlpDistance::Ulps(u) => Some(u),
        UlpDistance::NanMismatch => None,
    }
}

/// The thesis' table (section 4.11), and more: per threshold, how many
/// colour values (channels) differ by more and their mean difference; the
/// largest differences; the largest ULP distance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// What was compared, side A and side B.
    pub a: String,
    pub b: String,
    pub width: u32,
    pub height: u32,
    /// Colour values compared: 3 per pixel.
    pub channels: u64,
    /// Colour values that differ at all.
    pub differing: u64,
    pub rows: Vec<Row>,
    /// The [`LARGEST`] largest differences, largest first, at most one per
    /// pixel (its largest channel); only nonzero ones.
    pub largest: Vec<Largest>,
    /// The largest ULP distance of any channel (0 if none differs).
    pub max_ulps: u32,
    pub max_ulps_at: Option<Place>,
    /// Channels that are NaN on one side only (not counted in `max_ulps`).
    pub nan_mismatches: u64,
}

/// One line of the thesis' table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// On the 0..255 scale; "over" is strictly greater.
    pub threshold: f64,
    /// Colour values over the threshold.
    pub over: u64,
    /// `over` / all colour values, 0..=1.
    pub share: f64,
    /// Their mean difference (None when none is over; infinite, in JSON
    /// null, when one is NaN on a side).
    pub mean_over: Option<f64>,
}

/// A large difference and where it is.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Largest {
    /// |a - b| * 255 (infinite, in JSON null, for a NaN on one side).
    pub value: f64,
    pub x: u32,
    pub y: u32,
    pub channel: &'static str,
    /// The ULP distance of that channel (None for a NaN on one side).
    pub ulps: Option<u32>,
}

/// A channel of a pixel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Place {
    pub x: u32,
    pub y: u32,
    pub channel: &'static str,
}

/// `x` with about four significant digits, plain where that is short.
pub fn short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    // The decimal exponent after rounding to four digits (0.99999 is 1.000).
    let sci = format!("{x:.3e}");
    let e: i32 = sci
        .rsplit('e')
        .next()
        .and_then(|e| e.parse().ok())
        .expect("{:e} writes an exponent");
    if (-4..6).contains(&e) {
        format!("{x:.*}", (3 - e).max(0) as usize)
    } else {
        sci
    }
}

impl Table {
    /// The table as Markdown (what `table.md` holds and `rtcosim diffmap`
    /// prints).
    pub fn markdown(&self) -> String {
        let mut s = format!(
            "A: {}\nB: {}\n{}x{} pixels, {} colour values (channels) compared on the 0..255 scale; {} differ\n\n",
            self.a, self.b, self.width, self.height, self.channels, self.differing
        );
        s += "| threshold | colour values over it | share | average difference of those |\n";
        s += "|---|---|---|---|\n";
        for r in &self.rows {
            s += &format!(
                "| {} | {} | {:.4}% | {} |\n",
                r.threshold,
                r.over,
                100.0 * r.share,
                r.mean_over.map_or("-".into(), short)
            );
        }
        s += "\nlargest differences: ";
        if self.largest.is_empty() {
            s += "none";
        }
        let largest: Vec<String> = self
            .largest
            .iter()
            .map(|l| {
                let ulps = l
                    .ulps
                    .map_or("NaN vs number".into(), |u| format!("{u} ulp"));
                format!(
                    "{} at ({}, {}) {} ({ulps})",
                    short(l.value),
                    l.x,
                    l.y,
                    l.channel
                )
            })
            .collect();
        s += &largest.join(", ");
        s += &format!("\nlargest ULP distance: {}", self.max_ulps);
        if let Some(p) = &self.max_ulps_at {
            s += &format!(" at ({}, {}) {}", p.x, p.y, p.channel);
        }
        if self.nan_mismatches > 0 {
            s += &format!(
                "\nNaN on one side only: {} colour values",
                self.nan_mismatches
            );
        }
        s + "\n"
    }
}

#[cfg(test)]
mod tests;
