//! Rendered frames: linear RGB per pixel, PNG output, and the comparison the
//! accuracy tests and reports use.
//!
//! Pixels are held as f64. The reference renderer computes in f64, and
//! rounding it to f32 would by itself move a channel by up to 2^-25 (about
//! 0.76e-5 on the 0..255 scale), the size of the finest threshold the thesis
//! reports differences at (1e-5). Every f32 result of the micro-op model or
//! the RTL is held exactly, so one type serves all of them.

use std::path::{Path, PathBuf};

/// An image, row-major (`pixels[y * width + x]`, y = 0 at the top), linear
/// colour with channels nominally in [0, 1] (values above 1 are kept; they
/// are clamped only when converted to 8 bits).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f64; 3]>,
}

#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    #[error("{}: cannot write the PNG", path.display())]
    Png {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
    #[error("frames differ in size: {0}x{1} and {2}x{3}")]
    SizeMismatch(u32, u32, u32, u32),
    #[error("{width}x{height} needs {expected} pixels, got {got}")]
    PixelCount {
        width: u32,
        height: u32,
        expected: usize,
        got: usize,
    },
}

impl Frame {
    /// An all-black frame.
    pub fn black(width: u32, height: u32) -> Frame {
        Frame {
            width,
            height,
            pixels: vec![[0.0; 3]; width as usize * height as usize],
        }
    }

    /// Wraps row-major pixels, checking that there are `width * height`.
    pub fn from_pixels(
        width: u32,
        height: u32,
        pixels: Vec<[f64; 3]>,
    ) -> Result<Frame, FrameError> {
        let expected = width as usize * height as usize;
        if pixels.len() != expected {
            return Err(FrameError::PixelCount {
                width,
                height,
                expected,
                got: pixels.len(),
            });
        }
        Ok(Frame {
            width,
            height,
            pixels,
        })
    }

    /// The pixel at (x, y); panics outside the frame, like slice indexing.
    pub fn pixel(&self, x: u32, y: u32) -> [f64; 3] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{}",
            self.width,
            self.height
        );
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// The largest channel value in the frame (the thesis' scenes keep it
    /// <= 1, section 3.7); NaN channels are ignored. 0 for an empty frame.
    pub fn max_channel(&self) -> f64 {
        self.pixels
            .iter()
            .flatten()
            .copied()
            .filter(|c| !c.is_nan())
            .fold(0.0, f64::max)
    }

    /// 8-bit sRGB-less RGB bytes, row-major: each channel clamped to [0, 1],
    /// times 255, rounded to nearest (NaN becomes 0).
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels.iter().flatten().map(|&c| to_u8(c)).collect()
    }

    /// Writes the frame as an 8-bit RGB PNG ([`Frame::to_rgb8`]).
    pub fn save_png(&self, path: &Path) -> Result<(), FrameError> {
        image::save_buffer_with_format(
            path,
            &self.to_rgb8(),
            self.width,
            self.height,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|source| FrameError::Png {
            path: path.to_path_buf(),
            source,
        })
    }

    /// Channel-by-channel differences from `other`, on the 0..255 scale.
    pub fn compare(&self, other: &Frame) -> Result<FrameDiff, FrameError> {
        if (self.width, self.height) != (other.width, other.height) {
            return Err(FrameError::SizeMismatch(
                self.width,
                self.height,
                other.width,
                other.height,
            ));
        }
        let mut diffs = Vec::with_capacity(self.pixels.len() * 3);
        let mut max_abs_diff = 0.0f64;
        let mut worst_pixel = None;
        for (i, (a, b)) in self.pixels.iter().zip(&other.pixels).enumerate() {
            for ch in 0..3 {
                let d = (a[ch] - b[ch]).abs() * 255.0;
                // A NaN on either side is as wrong as a colour can be.
                let d = if d.is_nan() { f64::INFINITY } else { d };
                if d > max_abs_diff {
                    max_abs_diff = d;
                    let w = self.width as usize;
                    worst_pixel = Some(((i % w) as u32, (i / w) as u32));
                }
                diffs.push(d);
            }
        }
        diffs.sort_by(f64::total_cmp);
        Ok(FrameDiff {
            max_abs_diff,
            worst_pixel,
            sorted: diffs,
        })
    }
}

fn to_u8(c: f64) -> u8 {
    if c.is_nan() {
        0
    } else {
        (c.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// How two frames differ, channel by channel, on the 0..255 scale (the
/// scale of the thesis' accuracy figures).
#[derive(Debug, Clone, PartialEq)]
pub struct FrameDiff {
    /// The largest |a - b| * 255 over all channels (infinite if a channel is
    /// NaN in either frame); 0 for identical frames.
    pub max_abs_diff: f64,
    /// Where `max_abs_diff` occurs (x, y); `None` if the frames are equal.
    pub worst_pixel: Option<(u32, u32)>,
    /// Every channel's difference, ascending.
    sorted: Vec<f64>,
}

impl FrameDiff {
    /// Number of channel values compared (3 per pixel).
    pub fn channels(&self) -> usize {
        self.sorted.len()
    }

    /// Share (0..=1) of channel values that differ by more than `threshold`
    /// (0..255 scale). 0 for empty frames.
    pub fn share_over(&self, threshold: f64) -> f64 {
        if self.sorted.is_empty() {
            return 0.0;
        }
        let at_most = self.sorted.partition_point(|&d| d <= threshold);
        (self.sorted.len() - at_most) as f64 / self.sorted.len() as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn to_rgb8_clamps_scales_and_rounds_to_nearest() {
        let f = Frame::from_pixels(
            2,
            1,
            vec![[-0.5, 0.5, 1.5], [f64::NAN, 1.0 / 255.0 * 0.49, 0.999]],
        )
        .expect("2 pixels");
        // 0.5 * 255 = 127.5 rounds away from zero; 0.999 * 255 = 254.745.
        assert_eq!(f.to_rgb8(), vec![0, 128, 255, 0, 0, 255]);
    }

    #[test]
    fn compare_counts_channels_over_a_threshold_on_the_255_scale() {
        let a = Frame::from_pixels(2, 1, vec![[0.0; 3], [0.0; 3]]).expect("2 pixels");
        let b = Frame::from_pixels(2, 1, vec![[0.0, 1.0 / 255.0, 0.0], [0.0, 0.0, 0.5 / 255.0]])
            .expect("2 pixels");
        let d = a.compare(&b).expect("same size");
        assert!((d.max_abs_diff - 1.0).abs() < 1e-12);
        assert_eq!(d.worst_pixel, Some((0, 0)));
        assert_eq!(d.channels(), 6);
        assert!((d.share_over(0.25) - 2.0 / 6.0).abs() < 1e-12);
        assert!((d.share_over(0.75) - 1.0 / 6.0).abs() < 1e-12);
        assert_eq!(d.share_over(1.0), 0.0);
    }

    #[test]
    fn compare_treats_nan_as_infinitely_wrong() {
        let a = Frame::from_pixels(1, 1, vec![[f64::NAN, 0.0, 0.0]]).expect("1 pixel");
        let d = a.compare(&Frame::black(1, 1)).expect("same size");
        assert_eq!(d.max_abs_diff, f64::INFINITY);
        assert_eq!(d.share_over(1e9), 1.0 / 3.0);
    }

    #[test]
    fn compare_refuses_frames_of_different_sizes() {
        let err = Frame::black(2, 1).compare(&Frame::black(1, 2));
        assert!(matches!(err, Err(FrameError::SizeMismatch(2, 1, 1, 2))));
    }

    #[test]
    fn from_pixels_refuses_a_wrong_count() {
        assert!(matches!(
            Frame::from_pixels(2, 2, vec![[0.0; 3]; 3]),
            Err(FrameError::PixelCount {
                expected: 4,
                got: 3,
                ..
            })
        ));
    }

    #[test]
    fn save_png_writes_a_readable_png() -> Result<(), Box<dyn std::error::Error>> {
        let dir = std::env::temp_dir().join(format!("golden-frame-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let path = dir.join("t.png");
        let f = Frame::from_pixels(2, 1, vec![[1.0, 0.0, 0.0], [0.0, 0.5, 1.0]])?;
        f.save_png(&path)?;
        let img = image::open(&path)?.to_rgb8();
        assert_eq!(img.as_raw(), &f.to_rgb8());
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn save_png_names_the_path_it_cannot_write() {
        let path = Path::new("/nonexistent-dir-for-golden-tests/x.png");
        let err = Frame::black(1, 1)
            .save_png(path)
            .expect_err("no such directory");
        assert!(
            err.to_string()
                .contains("/nonexistent-dir-for-golden-tests/x.png"),
            "{err}"
        );
    }
}
