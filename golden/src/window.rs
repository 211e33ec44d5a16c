//! A rectangle of pixels: what `--window`, `--trace-window` and every
//! co-simulation run over.

use std::fmt;
use std::str::FromStr;

/// Columns `x..x + width` and rows `y..y + height` (row 0 at the top).
///
/// Written and parsed as inclusive corners, `X0,Y0,X1,Y1`, or `X,Y` for one
/// pixel ([`FromStr`], [`fmt::Display`]); [`Window::describe`] gives the
/// `WxH at (X, Y)` form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Window {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// Why a window cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WindowError {
    #[error(
        "expected X0,Y0,X1,Y1 (corners inclusive, X0 <= X1, Y0 <= Y1) or X,Y, \
         e.g. 400,300,403,301; got {0:?}"
    )]
    Syntax(String),
    #[error("{0} is an empty window")]
    Empty(Window),
    #[error(
        "{window} is outside the {width}x{height} image (columns 0..={}, rows 0..={})",
        width.saturating_sub(1),
        height.saturating_sub(1)
    )]
    Outside {
        window: Window,
        width: u32,
        height: u32,
    },
}

impl Window {
    pub const fn new(x: u32, y: u32, width: u32, height: u32) -> Window {
        Window {
            x,
            y,
            width,
            height,
        }
    }

    /// One pixel.
    pub const fn pixel(x: u32, y: u32) -> Window {
        Window::new(x, y, 1, 1)
    }

    /// The whole `width` x `height` image.
    pub const fn image(width: u32, height: u32) -> Window {
        Window::new(0, 0, width, height)
    }

    /// The whole image of `scene`.
    pub fn full(scene: &crate::scene::Scene) -> Window {
        Window::image(scene.camera.width, scene.camera.height)
    }

    /// Pixels in the window.
    pub fn pixels(&self) -> u64 {
        u64::from(self.width) * u64::from(self.height)
    }

    /// Rows, top to bottom.
    pub fn rows(&self) -> std::ops::Range<u32> {
        self.y..self.y.saturating_add(self.height)
    }

    /// Columns, left to right.
    pub fn columns(&self) -> std::ops::Range<u32> {
        self.x..self.x.saturating_add(self.width)
    }

    /// Every pixel, row by row, left to right.
    pub fn iter(&self) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.rows()
            .flat_map(move |y| self.columns().map(move |x| (x, y)))
    }

    /// Whether (x, y) is in the window.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        self.columns().contains(&x) && self.rows().contains(&y)
    }

    /// Whether the window is non-empty and inside a `width` x `height` image.
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.width > 0
            && self.height > 0
            && u64::from(self.x) + u64::from(self.width) <= u64::from(width)
            && u64::from(self.y) + u64::from(self.height) <= u64::from(height)
    }

    /// Fails unless the window is non-empty and inside a `width` x
    /// `height` image.
    pub fn check_inside(&self, width: u32, height: u32) -> Result<(), WindowError> {
        if self.pixels() == 0 {
            Err(WindowError::Empty(*self))
        } else if self.fits(width, height) {
            Ok(())
        } else {
            Err(WindowError::Outside {
                window: *self,
                width,
                height,
            })
        }
    }

    /// `WxH at (X, Y)`.
    pub fn describe(&self) -> String {
        format!("{}x{} at ({}, {})", self.width, self.height, self.x, self.y)
    }
}

impl fmt::Display for Window {
    /// Inclusive corners, `X0,Y0,X1,Y1` (an empty window shows its origin
    /// twice).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let last = |start: u32, len: u32| start.saturating_add(len.saturating_sub(1));
        write!(
            f,
            "{},{},{},{}",
            self.x,
            self.y,
            last(self.x, self.width),
            last(self.y, self.height)
        )
    }
}

impl FromStr for Window {
    type Err = WindowError;

    fn from_str(s: &str) -> Result<Window, WindowError> {
        let bad = || WindowError::Syntax(s.to_string());
        let v: Vec<u32> = s
            .split(',')
            .map(|p| p.trim().parse::<u32>().map_err(|_| bad()))
            .collect::<Result<_, _>>()?;
        let (x0, y0, x1, y1) = match v[..] {
            [x, y] => (x, y, x, y),
            [x0, y0, x1, y1] => (x0, y0, x1, y1),
            _ => return Err(bad()),
        };
        if x0 > x1 || y0 > y1 || x1 == u32::MAX || y1 == u32::MAX {
            return Err(bad());
        }
        Ok(Window::new(x0, y0, x1 - x0 + 1, y1 - y0 + 1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_parse_as_inclusive_corners_or_one_pixel() {
        assert_eq!("400,300,403,301".parse(), Ok(Window::new(400, 300, 4, 2)));
        assert_eq!(" 7, 9".parse(), Ok(Window::pixel(7, 9)));
        assert_eq!(
            "0,0,799,599".parse::<Window>().map(|w| w.pixels()),
            Ok(480_000)
        );
        for bad in [
            "",
            "1",
            "1,2,3",
            "1,2,3,4,5",
            "4,0,3,0",
            "0,4,0,3",
            "-1,0",
            "a,b",
            "0,0,4294967295,0",
        ] {
            assert!(bad.parse::<Window>().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn display_round_trips_and_describe_gives_size_and_origin() {
        let w = Window::new(1, 2, 30, 19);
        assert_eq!(w.to_string(), "1,2,30,20");
        assert_eq!(w.to_string().parse(), Ok(w));
        assert_eq!(w.describe(), "30x19 at (1, 2)");
    }

    #[test]
    fn a_window_fits_only_inside_the_image_and_never_empty() {
        let w: Window = "0,0,79,59".parse().expect("valid");
        assert!(w.check_inside(80, 60).is_ok());
        assert!(w.check_inside(79, 60).is_err());
        assert!(w.check_inside(80, 59).is_err());
        assert!(!Window::new(0, 0, 0, 5).fits(80, 60));
        let err = Window::new(30, 0, 11, 1)
            .check_inside(40, 30)
            .expect_err("outside");
        assert_eq!(
            err.to_string(),
            "30,0,40,0 is outside the 40x30 image (columns 0..=39, rows 0..=29)"
        );
    }

    #[test]
    fn pixels_iterate_row_by_row() {
        let w = Window::new(5, 7, 2, 2);
        assert_eq!(
            w.iter().collect::<Vec<_>>(),
            [(5, 7), (6, 7), (5, 8), (6, 8)]
        );
        assert!(w.contains(6, 8) && !w.contains(7, 8) && !w.contains(5, 9));
    }
}
