//! Stability where methods fail: the geometric edge mask and the
//! perturbation study (docs/accuracy.md, "Stability").
//!
//! A pixel's colour is a continuous function of its primary direction
//! except where the discrete events along its path change: which object
//! each ray hits, and whether light reaches each hit point
//! ([`reference::path_events`]). The [`edge_mask`] marks the pixels where
//! those events differ from a 4-neighbour's: silhouettes, shadow edges and
//! terminators, and their reflections. There, and only there, a tiny change
//! of direction (a rounding error, or the ±1 ULP of [`perturb`]) may move
//! the colour by a visible step; everywhere else it must not. The tests
//! (`golden/tests/stability.rs`) hold the micro-op model to this: every
//! pixel where it differs visibly from the reference, or from itself with a
//! nudged direction, lies in the mask dilated by one pixel.

use crate::frame::Frame;
use crate::micro::Processor;
use crate::reference;
use crate::scene::Scene;
use rayon::prelude::*;

/// The threshold of a visible change: half a step of the 8-bit output, on
/// the 0..255 scale.
pub const VISIBLE: f64 = 0.5;

/// Whether two colours differ by more than [`VISIBLE`] in some channel (on
/// the 0..255 scale, linear, unclamped). A NaN on either side always
/// differs: a NaN is never silently stable.
pub fn differs(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).any(|ch| {
        let d = (a[ch] - b[ch]).abs() * 255.0;
        d.is_nan() || d > VISIBLE
    })
}

/// A set of pixels of a `width` x `height` image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mask {
    pub width: u32,
    pub height: u32,
    /// Row-major, y = 0 at the top.
    pub bits: Vec<bool>,
}

impl Mask {
    fn from_fn(width: u32, height: u32, f: impl Fn(u32, u32) -> bool + Sync) -> Mask {
        let bits = (0..width * height)
            .into_par_iter()
            .map(|i| f(i % width, i / width))
            .collect();
        Mask {
            width,
            height,
            bits,
        }
    }

    /// Whether (x, y) is in the set.
    pub fn get(&self, x: u32, y: u32) -> bool {
        self.bits[(y * self.width + x) as usize]
    }

    /// Pixels in the set.
    pub fn count(&self) -> usize {
        self.bits.iter().filter(|&&b| b).count()
    }

    /// The set's share of the frame (0..=1).
    pub fn share(&self) -> f64 {
        self.count() as f64 / self.bits.len() as f64
    }

    /// The set grown by one pixel in every direction (its 3x3 neighbourhood).
    pub fn dilated(&self) -> Mask {
        let (w, h) = (self.width as i64, self.height as i64);
        Mask::from_fn(self.width, self.height, |x, y| {
            (-1..=1).any(|dy: i64| {
                (-1..=1).any(|dx: i64| {
                    let (nx, ny) = (i64::from(x) + dx, i64::from(y) + dy);
                    (0..w).contains(&nx) && (0..h).contains(&ny) && self.get(nx as u32, ny as u32)
                })
            })
        })
    }

    /// The pixels in the set, in row order.
    pub fn pixels(&self) -> Vec<(u32, u32)> {
        (0..self.bits.len() as u32)
            .filter(|&i| self.bits[i as usize])
            .map(|i| (i % self.width, i / self.width))
            .collect()
    }
}

/// The geometric edges of `scene`, computed by the reference renderer: the
/// pixels whose [`reference::path_events`] differ from those of a
/// 4-neighbour (both pixels of such a pair are marked).
pub fn edge_mask(scene: &Scene) -> Mask {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let events: Vec<_> = (0..w * h)
        .into_par_iter()
        .map(|i| reference::path_events(scene, i % w, i / w))
        .collect();
    let at = |x: u32, y: u32| &events[(y * w + x) as usize];
    Mask::from_fn(w, h, |x, y| {
        let me = at(x, y);
        (x > 0 && at(x - 1, y) != me)
            || (x + 1 < w && at(x + 1, y) != me)
            || (y > 0 && at(x, y - 1) != me)
            || (y + 1 < h && at(x, y + 1) != me)
    })
}

/// Pixels where two frames of one size [`differs`].
pub fn visible_differences(a: &Frame, b: &Frame) -> Mask {
    assert_eq!(
        (a.width, a.height),
        (b.width, b.height),
        "frames of one size"
    );
    Mask::from_fn(a.width, a.height, |x, y| {
        differs(a.pixel(x, y), b.pixel(x, y))
    })
}

/// The pixels of `set` outside `allowed`, in row order.
pub fn outside(set: &Mask, allowed: &Mask) -> Vec<(u32, u32)> {
    set.pixels()
        .into_iter()
        .filter(|&(x, y)| !allowed.get(x, y))
        .collect()
}

/// `d` with lane `lane` moved one ULP up (`up`) or down: to the next
/// f32 in that direction (from ±0 to ±2^-149; infinities and NaN stay).
pub fn nudge(mut d: [f32; 3], lane: usize, up: bool) -> [f32; 3] {
    let x = d[lane];
    d[lane] = if x == 0.0 {
        let tiny = f32::from_bits(1);
        if up {
            tiny
        } else {
            -tiny
        }
    } else if x.is_finite() {
        // Up from a positive number and down from a negative one move away
        // from zero: the magnitude's bits grow by one.
        let bits = x.to_bits();
        f32::from_bits(if up == (x > 0.0) { bits + 1 } else { bits - 1 })
    } else {
        x
    };
    d
}

/// What [`perturb`] found.
#[derive(Debug, Clone)]
pub struct Perturbation {
    /// Pixels whose colour changes visibly when the primary direction moves
    /// by one ULP in some lane, either way (six runs of each pixel).
    pub unstable: Mask,
    /// The reference's edge mask, dilated by one pixel.
    pub edges: Mask,
    /// Per pixel, the largest change of a channel over the six runs, on the
    /// 0..255 scale (infinite where a NaN appears).
    pub change: Vec<f64>,
}

impl Perturbation {
    /// Unstable pixels outside the dilated edge mask: what must be empty.
    pub fn unexplained(&self) -> Vec<(u32, u32)> {
        outside(&self.unstable, &self.edges)
    }

    /// The largest [`Perturbation::change`] of a pixel off the edges (0 if
    /// every pixel is on them).
    pub fn largest_change_off_edges(&self) -> f64 {
        self.change
            .iter()
            .zip(&self.edges.bits)
            .filter(|(_, &edge)| !edge)
            .fold(0.0, |m, (&c, _)| m.max(c))
    }

    /// The flip map: black where stable off the edges, dark grey on the
    /// (dilated) edges, white where unstable on an edge, red where unstable
    /// off them.
    pub fn flip_map(&self) -> image::RgbImage {
        image::RgbImage::from_fn(self.unstable.width, self.unstable.height, |x, y| {
            image::Rgb(match (self.unstable.get(x, y), self.edges.get(x, y)) {
                (false, false) => [0, 0, 0],
                (false, true) => [70, 70, 70],
                (true, true) => [255, 255, 255],
                (true, false) => [255, 0, 0],
            })
        })
    }
}

/// The perturbation study of the micro-op model on `scene`: every pixel
/// rendered with its primary direction as computed, then with each lane
/// moved by +1 and by -1 ULP (the f32 lanes the hardware holds); a pixel
/// is unstable if any of the six differs visibly from the first. Rows in
/// parallel; `progress` gets the pixels done, once per row.
pub fn perturb(scene: &Scene, progress: &(dyn Fn(u64) + Sync)) -> Perturbation {
    let proc = Processor::new(scene);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let widen = |c: [f32; 3]| c.map(f64::from);
    let change: Vec<f64> = (0..h)
        .into_par_iter()
        .flat_map_iter(|y| {
            let row: Vec<f64> = (0..w)
                .map(|x| {
                    let base = widen(proc.render_pixel(x, y, |_, _| {}).rgb);
                    let mut largest = 0.0f64;
                    for lane in 0..3 {
                        for up in [true, false] {
                            let c = widen(proc.render_pixel_nudged(x, y, |d| nudge(d, lane, up)));
                            for ch in 0..3 {
                                let d = (c[ch] - base[ch]).abs() * 255.0;
                                largest = largest.max(if d.is_nan() { f64::INFINITY } else { d });
                            }
                        }
                    }
                    largest
                })
                .collect();
            progress(u64::from(w));
            row
        })
        .collect();
    Perturbation {
        unstable: Mask {
            width: w,
            height: h,
            bits: change.iter().map(|&c| c > VISIBLE).collect(),
        },
        edges: edge_mask(scene).dilated(),
        change,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nudge_moves_one_ulp_either_way_through_zero() {
        let bits = |d: [f32; 3]| d.map(f32::to_bits);
        assert_eq!(bits(nudge([1.0, -1.0, 0.0], 0, true))[0], 0x3F80_0001);
        assert_eq!(bits(nudge([1.0, -1.0, 0.0], 0, false))[0], 0x3F7F_FFFF);
        assert_eq!(bits(nudge([1.0, -1.0, 0.0], 1, true))[1], 0xBF7F_FFFF);
        assert_eq!(bits(nudge([1.0, -1.0, 0.0], 1, false))[1], 0xBF80_0001);
        assert_eq!(bits(nudge([1.0, -1.0, 0.0], 2, true))[2], 0x0000_0001);
        assert_eq!(bits(nudge([1.0, -1.0, -0.0], 2, false))[2], 0x8000_0001);
        // The other lanes stay.
        assert_eq!(
            bits(nudge([1.0, -1.0, 0.0], 2, true))[..2],
            [0x3F80_0000, 0xBF80_0000]
        );
    }
}
