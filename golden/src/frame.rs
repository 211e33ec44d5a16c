//! Rendered frames: linear RGB per pixel, PNG output, lossless frame files
//! (OpenEXR), and the comparison the accuracy tests and reports use.
//!
//! Pixels are held as f64. The reference renderer computes in f64, and
//! rounding it to f32 would by itself move a channel by up to 2^-25 (about
//! 0.76e-5 on the 0..255 scale), the size of the finest threshold the thesis
//! reports differences at (1e-5). Every f32 result of the micro-op model or
//! the RTL is held exactly, so one type serves all of them.
//!
//! # Frame files
//!
//! [`Frame::save_exr`] writes a frame as an OpenEXR file with three f32
//! channels R, G, B (RLE-compressed, lossless) and [`Frame::load_exr`]
//! reads one back. Frames of the micro-op model and of the RTL are f32
//! values, so their files are exact: every channel reads back with the same
//! bits (NaN, values above 1 and signed zeros included). A frame of the f64
//! reference renderer is rounded to the nearest f32 on the way out, which
//! moves a channel by at most half an f32 ULP: 2^-24 of its value, and for a
//! channel in [0, 1] at most 2^-25 absolute, 2^-25 * 255 ≈ 0.76e-5 on the
//! 0..255 scale, the size of the thesis' finest threshold (1e-5). Differences counted from a file of the *reference* are therefore
//! approximate at 1e-5; the in-process reference frame (f64) is exact.
//!
//! A file is refused, with its path and the reason, unless it is an OpenEXR
//! image of one flat layer whose channels are exactly R, G and B, each f32
//! or f16 (f16 widens to f32 exactly) and not subsampled.

use std::fs::File;
use std::io::BufWriter;
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
    #[error("{}: cannot write the EXR frame file", path.display())]
    ExrWrite {
        path: PathBuf,
        #[source]
        source: image::ImageError,
    },
    #[error("{}: cannot read the frame file", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}: not an OpenEXR file (it does not start with the EXR magic number 76 2f 31 01)", path.display())]
    NotExr { path: PathBuf },
    #[error("{}: wrong channel layout for a frame file: {problem}; expected one flat layer with the channels R, G, B (f32 or f16), as `save_exr` writes", path.display())]
    ExrLayout { path: PathBuf, problem: String },
    #[error("{}: damaged or truncated OpenEXR file: {reason}", path.display())]
    ExrRead { path: PathBuf, reason: String },
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

    /// Pixels with a channel over 1: [`Frame::to_rgb8`] clips them to 255,
    /// so distinct colours come out the same (saturated). NaN is not over 1.
    pub fn saturated_pixels(&self) -> u64 {
        self.pixels
            .iter()
            .filter(|p| p.iter().any(|&c| c > 1.0))
            .count() as u64
    }

    /// The warning `render` and `cosim` print when the frame has saturated
    /// pixels ([`Frame::saturated_pixels`]), naming the cure; `None` when
    /// every channel is at most 1.
    pub fn saturation_warning(&self) -> Option<String> {
        let n = self.saturated_pixels();
        (n > 0).then(|| {
            format!(
                "warning: {n} of {} pixels have a channel over 1 (up to {}), clipped to 255 in 8 bits; [render] exposure maps colours into [0, 1) (docs/scenes.md)",
                self.pixels.len(),
                self.max_channel()
            )
        })
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

    /// Writes the frame as an OpenEXR file of f32 channels R, G, B (see
    /// [Frame files](self#frame-files)): exact for f32 values; f64 values
    /// are rounded to the nearest f32.
    pub fn save_exr(&self, path: &Path) -> Result<(), FrameError> {
        let write_err = |source| FrameError::ExrWrite {
            path: path.to_path_buf(),
            source,
        };
        let file = File::create(path).map_err(|e| write_err(image::ImageError::IoError(e)))?;
        let samples: Vec<f32> = self.pixels.iter().flatten().map(|&c| c as f32).collect();
        let bytes: Vec<u8> = samples.iter().flat_map(|c| c.to_ne_bytes()).collect();
        let mut out = BufWriter::new(file);
        image::ImageEncoder::write_image(
            image::codecs::openexr::OpenExrEncoder::new(&mut out),
            &bytes,
            self.width,
            self.height,
            image::ExtendedColorType::Rgb32F,
        )
        .map_err(write_err)?;
        std::io::Write::flush(&mut out).map_err(|e| write_err(image::ImageError::IoError(e)))
    }

    /// Reads a frame file written by [`Frame::save_exr`] (or any OpenEXR
    /// image of one flat R, G, B layer). Every error names the file and
    /// says what is wrong with it.
    pub fn load_exr(path: &Path) -> Result<Frame, FrameError> {
        let io_err = |source| FrameError::Io {
            path: path.to_path_buf(),
            source,
        };
        let read_err = |reason: String| FrameError::ExrRead {
            path: path.to_path_buf(),
            reason,
        };
        // Read once: the checks and the decoder see the same bytes.
        let file = std::fs::read(path).map_err(io_err)?;
        if !file.starts_with(&EXR_MAGIC) {
            return Err(FrameError::NotExr {
                path: path.to_path_buf(),
            });
        }
        let meta = exr::meta::MetaData::read_from_buffered(file.as_slice(), false)
            .map_err(|e| read_err(e.to_string()))?;
        check_exr_layout(&meta).map_err(|problem| FrameError::ExrLayout {
            path: path.to_path_buf(),
            problem,
        })?;
        let decoder = image::codecs::openexr::OpenExrDecoder::with_alpha_preference(
            std::io::Cursor::new(file.as_slice()),
            Some(false),
        )
        .map_err(|e| read_err(e.to_string()))?;
        let (width, height) = image::ImageDecoder::dimensions(&decoder);
        let len = image::ImageDecoder::total_bytes(&decoder);
        let mut bytes = vec![0u8; usize::try_from(len).map_err(|e| read_err(e.to_string()))?];
        image::ImageDecoder::read_image(decoder, &mut bytes)
            .map_err(|e| read_err(e.to_string()))?;
        let pixels = bytes
            .chunks_exact(12)
            .map(|p| {
                std::array::from_fn(|ch| {
                    let b = &p[4 * ch..4 * ch + 4];
                    f64::from(f32::from_ne_bytes([b[0], b[1], b[2], b[3]]))
                })
            })
            .collect();
        Frame::from_pixels(width, height, pixels).map_err(|e| read_err(e.to_string()))
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

/// The first four bytes of every OpenEXR file.
const EXR_MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];

/// Whether `meta` describes a frame file: one flat layer, channels exactly
/// R, G, B, each f32 or f16, not subsampled; else what is wrong.
fn check_exr_layout(meta: &exr::meta::MetaData) -> Result<(), String> {
    use exr::meta::attribute::SampleType;
    let [header] = meta.headers.as_slice() else {
        return Err(format!("{} layers", meta.headers.len()));
    };
    if header.deep {
        return Err("a deep-data layer".into());
    }
    let size = header.shared_attributes.display_window.size;
    let side = 1..=crate::scene::MAX_IMAGE_SIDE as usize;
    if !side.contains(&size.0) || !side.contains(&size.1) {
        return Err(format!(
            "an image of {}x{} pixels (a frame has 1..={} a side)",
            size.0,
            size.1,
            side.end()
        ));
    }
    let channels = &header.channels.list;
    let names: Vec<String> = channels.iter().map(|c| c.name.to_string()).collect();
    let mut sorted = names.clone();
    sorted.sort();
    if sorted != ["B", "G", "R"] {
        return Err(format!("channels {}", names.join(", ")));
    }
    for c in channels {
        if c.sample_type == SampleType::U32 {
            return Err(format!("channel {} holds u32 samples", c.name));
        }
        if c.sampling != exr::math::Vec2(1, 1) {
            return Err(format!(
                "channel {} is subsampled {}x{}",
                c.name, c.sampling.0, c.sampling.1
            ));
        }
    }
    Ok(())
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

    /// The mean channel difference (0..255 scale); infinite if any is. 0
    /// for empty frames.
    pub fn mean(&self) -> f64 {
        if self.sorted.is_empty() {
            return 0.0;
        }
        self.sorted.iter().sum::<f64>() / self.sorted.len() as f64
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

    /// A fresh scratch directory for one test.
    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("golden-frame-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch directory");
        dir
    }

    #[test]
    fn exr_round_trips_f32_values_bit_for_bit() -> Result<(), Box<dyn std::error::Error>> {
        let dir = scratch("exr-round-trip");
        let path = dir.join("f.exr");
        let values: [f32; 12] = [
            0.0,
            -0.0,
            1.0,
            1.5,
            255.0,
            3.4e38,
            f32::from_bits(1),           // the smallest subnormal
            f32::from_bits(0x3F80_0001), // 1 + 1 ulp
            0.1,
            1e-30,
            f32::INFINITY,
            f32::NAN,
        ];
        // 3 x 2 pixels, channels in order; a 4 x 2 frame covers them twice.
        let pixels: Vec<[f64; 3]> = values
            .chunks(3)
            .chain(values.chunks(3).rev())
            .map(|c| [f64::from(c[0]), f64::from(c[1]), f64::from(c[2])])
            .collect();
        let f = Frame::from_pixels(4, 2, pixels)?;
        f.save_exr(&path)?;
        let back = Frame::load_exr(&path)?;
        assert_eq!((back.width, back.height), (4, 2));
        let bits =
            |f: &Frame| -> Vec<u64> { f.pixels.iter().flatten().map(|c| c.to_bits()).collect() };
        assert_eq!(bits(&back), bits(&f));
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn exr_rounds_f64_to_the_nearest_f32_within_2_to_the_minus_25(
    ) -> Result<(), Box<dyn std::error::Error>> {
        let dir = scratch("exr-f64");
        let path = dir.join("f.exr");
        let values = [0.1, 1.0 / 3.0, 0.999_999_99, 2.0 / 255.0, 1e-3 + 1e-12, 0.7];
        let f = Frame::from_pixels(
            2,
            1,
            vec![
                [values[0], values[1], values[2]],
                [values[3], values[4], values[5]],
            ],
        )?;
        f.save_exr(&path)?;
        let back = Frame::load_exr(&path)?;
        for (v, r) in f.pixels.iter().flatten().zip(back.pixels.iter().flatten()) {
            // Round to nearest: at most half an f32 ulp, 2^-24 relative;
            // below 1 an ulp is at most 2^-24, so at most 2^-25 absolute,
            // 0.76e-5 on the 0..255 scale.
            assert!((v - r).abs() <= v.abs() * 2f64.powi(-24), "{v} -> {r}");
            assert!((v - r).abs() <= 2f64.powi(-25), "{v} -> {r}");
            assert!((v - r).abs() * 255.0 <= 0.76e-5, "{v} -> {r}");
            assert_eq!(*r, f64::from(*v as f32));
        }
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn a_file_that_is_not_an_exr_is_refused_by_name() -> Result<(), Box<dyn std::error::Error>> {
        let dir = scratch("exr-foreign");
        let png = dir.join("really-a.png");
        Frame::black(2, 2).save_png(&png)?;
        let empty = dir.join("empty.exr");
        std::fs::write(&empty, b"")?;
        let text = dir.join("text.exr");
        std::fs::write(&text, b"R,G,B\n0,0,0\n")?;
        for path in [&png, &empty, &text] {
            let err = Frame::load_exr(path).expect_err("not an EXR");
            assert!(matches!(err, FrameError::NotExr { .. }), "{err:?}");
            let msg = err.to_string();
            assert!(
                msg.contains(&path.display().to_string()) && msg.contains("not an OpenEXR file"),
                "{msg}"
            );
        }
        let missing = dir.join("missing.exr");
        let msg = Frame::load_exr(&missing).expect_err("no file").to_string();
        assert!(
            msg.contains("missing.exr") && msg.contains("cannot read"),
            "{msg}"
        );
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn a_truncated_exr_is_refused_by_name_at_any_length() -> Result<(), Box<dyn std::error::Error>>
    {
        let dir = scratch("exr-truncated");
        let whole = dir.join("whole.exr");
        let pixels = (0..64 * 48)
            .map(|i| [f64::from(i as f32) / 3072.0, 0.25, 0.5])
            .collect();
        Frame::from_pixels(64, 48, pixels)?.save_exr(&whole)?;
        let bytes = std::fs::read(&whole)?;
        let cut = dir.join("cut.exr");
        // Cuts in the header, in the offset table, in the pixel data.
        for len in [4, 20, 100, bytes.len() / 2, bytes.len() - 1] {
            std::fs::write(&cut, &bytes[..len])?;
            let err = Frame::load_exr(&cut).expect_err("truncated");
            assert!(matches!(err, FrameError::ExrRead { .. }), "{len}: {err:?}");
            let msg = err.to_string();
            assert!(
                msg.contains("cut.exr") && msg.contains("truncated"),
                "{len}: {msg}"
            );
        }
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn an_exr_with_other_channels_is_refused_with_its_layout(
    ) -> Result<(), Box<dyn std::error::Error>> {
        let dir = scratch("exr-layout");
        let path = dir.join("rgba.exr");
        let rgba = image::Rgba32FImage::from_pixel(2, 2, image::Rgba([0.5, 0.5, 0.5, 1.0]));
        image::DynamicImage::from(rgba).save_with_format(&path, image::ImageFormat::OpenExr)?;
        let err = Frame::load_exr(&path).expect_err("an alpha channel");
        let msg = err.to_string();
        assert!(matches!(err, FrameError::ExrLayout { .. }), "{err:?}");
        assert!(
            msg.contains("rgba.exr")
                && msg.contains("wrong channel layout")
                && msg.contains("channels A, B, G, R"),
            "{msg}"
        );
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn an_exr_larger_than_any_frame_is_refused_before_it_is_decoded(
    ) -> Result<(), Box<dyn std::error::Error>> {
        let dir = scratch("exr-huge");
        let path = dir.join("wide.exr");
        Frame::black(crate::scene::MAX_IMAGE_SIDE + 1, 1).save_exr(&path)?;
        let msg = Frame::load_exr(&path).expect_err("too wide").to_string();
        assert!(
            msg.contains("wide.exr") && msg.contains("4097x1 pixels"),
            "{msg}"
        );
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn save_exr_names_the_path_it_cannot_write() {
        let err = Frame::black(1, 1)
            .save_exr(Path::new("/nonexistent-dir-for-golden-tests/x.exr"))
            .expect_err("no such directory");
        assert!(
            err.to_string()
                .contains("/nonexistent-dir-for-golden-tests/x.exr"),
            "{err}"
        );
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
