//! The text of the heat maps' legends and of the sweep's PNG chart
//! (rtcosim::sweep::chart): embedded-graphics' built-in 6x9 monospace
//! bitmap font (`mono_font::ascii::FONT_6X9`, printable ASCII), drawn
//! through a callback so any image type can take it. Built in, so drawing
//! a label needs no font file and no system library.

use embedded_graphics::mono_font::ascii::FONT_6X9;
use embedded_graphics::mono_font::{MonoFont, MonoTextStyle};
use embedded_graphics::pixelcolor::BinaryColor;
use embedded_graphics::prelude::*;
use embedded_graphics::text::{Baseline, Text};
use std::convert::Infallible;

/// The font.
const FONT: MonoFont<'static> = FONT_6X9;

/// Height of a line of text at scale 1, in pixels.
pub const GLYPH_HEIGHT: u32 = FONT.character_size.height;

/// Horizontal distance from one character to the next at scale 1.
pub const ADVANCE: u32 = FONT.character_size.width + FONT.character_spacing;

/// Whether the font has a glyph of its own for `c` (it draws any other
/// character as its replacement glyph, `?`).
pub fn has_glyph(c: char) -> bool {
    let index = |c| FONT.glyph_mapping.index(c);
    c == '?' || index(c) != index('?')
}

/// Width in pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: u32) -> u32 {
    text.chars().count() as u32 * ADVANCE * scale
}

/// Calls `ink(x, y)` for every inked pixel of `text` with its top-left
/// corner at (x, y), each font pixel a `scale` x `scale` square.
pub fn draw_text(text: &str, x: u32, y: u32, scale: u32, ink: &mut impl FnMut(u32, u32)) {
    let mut target = Ink {
        ink,
        x,
        y,
        scale: scale.max(1),
    };
    let style = MonoTextStyle::new(&FONT, BinaryColor::On);
    Text::with_baseline(text, Point::zero(), style, Baseline::Top)
        .draw(&mut target)
        .unwrap_or_else(|never| match never {});
}

/// A draw target that scales each lit pixel and hands it to a callback.
struct Ink<'a, F> {
    ink: &'a mut F,
    x: u32,
    y: u32,
    scale: u32,
}

impl<F> OriginDimensions for Ink<'_, F> {
    fn size(&self) -> Size {
        // Large enough for any label: text is only ever drawn from (0, 0).
        Size::new(u32::MAX / 2, u32::MAX / 2)
    }
}

impl<F: FnMut(u32, u32)> DrawTarget for Ink<'_, F> {
    type Color = BinaryColor;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<BinaryColor>>,
    {
        let s = self.scale;
        for Pixel(p, colour) in pixels {
            let (Ok(px), Ok(py)) = (u32::try_from(p.x), u32::try_from(p.y)) else {
                continue;
            };
            if colour.is_on() {
                for dy in 0..s {
                    for dx in 0..s {
                        (self.ink)(self.x + px * s + dx, self.y + py * s + dy);
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn printable_ascii_has_glyphs_and_other_characters_do_not() {
        assert!((' '..='~').all(has_glyph));
        assert!(!has_glyph('é') && !has_glyph('\u{2264}'));
    }

    #[test]
    fn text_is_drawn_inside_its_box_and_scales() {
        let mut ink = Vec::new();
        draw_text("1e-5", 10, 20, 1, &mut |x, y| ink.push((x, y)));
        assert!(!ink.is_empty());
        let w = text_width("1e-5", 1);
        assert_eq!(w, 4 * ADVANCE);
        assert!(ink
            .iter()
            .all(|&(x, y)| (10..10 + w).contains(&x) && (20..20 + GLYPH_HEIGHT).contains(&y)));
        // A space inks nothing; each font pixel becomes scale^2 pixels.
        let mut space = 0;
        draw_text(" ", 0, 0, 3, &mut |_, _| space += 1);
        assert_eq!(space, 0);
        let mut big = 0;
        draw_text("1e-5", 0, 0, 2, &mut |_, _| big += 1);
        assert_eq!(big, 4 * ink.len());
    }

    #[test]
    fn different_characters_ink_different_pixels() {
        let pixels = |c: &str| {
            let mut v = Vec::new();
            draw_text(c, 0, 0, 1, &mut |x, y| v.push((x, y)));
            v
        };
        assert_ne!(pixels("1"), pixels("7"));
        assert_ne!(pixels("e"), pixels("c"));
    }
}
