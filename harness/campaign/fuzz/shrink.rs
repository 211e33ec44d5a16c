//! A kept scene shrunk to the smallest image that still reaches what it
//! was kept for.
//!
//! Pixel (px, py) of a W x H image looks along `(px - W/2, H/2 - py,
//! distance)` (rotated): what a pixel does depends on its offset from the
//! image's centre, not on W and H. So a *centred crop* of the image, W' x
//! H' with the parity of W x H, holds exactly the rays of the pixels it
//! covers, each with the same direction, and crops nest. The smallest crop
//! that holds pixel (px, py) is W' = W - 2px (px left of the centre; the
//! pixel becomes column 0) or 2px - W + 2 (right of it; the last column),
//! and the same for rows. For each point the scene was kept for, the pixel
//! of smallest crop that reaches it is chosen; the scene keeps the crop
//! that holds all of those pixels, if golden confirms that the cropped
//! scene still reaches every one of the points (a pixel's coordinates are
//! among the values it writes, so its value classes can differ).

use golden::micro::cover::{Coverage, Point};
use golden::micro::Processor;
use golden::scene::Scene;
use toml::{Table, Value};

/// The side of the smallest centred crop of a `side`-wide image that
/// holds column (or row) `at`, counted from the side where the crop's
/// centre offset grows, `offset2 = 2 * at - side` (twice the offset of the
/// pixel from the centre).
fn crop_side(side: u32, at: u32) -> u32 {
    let offset2 = 2 * i64::from(at) - i64::from(side);
    (if offset2 < 0 { -offset2 } else { offset2 + 2 }) as u32
}

/// The crop (W', H') that holds pixel (px, py) of `scene`. Rows count
/// downwards, so the row offset is `H/2 - py`: the same rule with the sign
/// turned, which `crop_side` of the mirrored row gives.
fn crop_of(scene: &Scene, px: u32, py: u32) -> (u32, u32) {
    let (w, h) = (scene.camera.width, scene.camera.height);
    (crop_side(w, px), crop_side(h, h - 1 - py))
}

/// A scene cropped by [`shrink`].
#[derive(Debug, Clone, PartialEq)]
pub struct Cropped {
    /// The cropped scene file.
    pub text: String,
    /// What it reaches, and its pixels.
    pub coverage: Coverage,
    pub pixels: u64,
    /// The image's (width, height) before and after.
    pub from: (u32, u32),
    pub to: (u32, u32),
}

/// `text` with its image cropped so that it reaches every one of `points`;
/// `None` if no crop smaller than the image does (or the text does not
/// load).
pub fn shrink(text: &str, points: &[Point]) -> Option<Cropped> {
    let scene = Scene::from_toml(text, "kept scene").ok()?;
    let processor = Processor::new(&scene);
    let (w, h) = (scene.camera.width, scene.camera.height);
    // For each point, the smallest crop of a pixel that reaches it.
    let mut best: Vec<Option<(u32, u32)>> = vec![None; points.len()];
    for py in 0..h {
        for px in 0..w {
            let mut c = Coverage::new();
            processor.render_pixel_covered(px, py, &mut c);
            let crop = crop_of(&scene, px, py);
            for (i, &p) in points.iter().enumerate() {
                if c.contains(p) && best[i].is_none_or(|b| crop.0 * crop.1 < b.0 * b.1) {
                    best[i] = Some(crop);
                }
            }
        }
    }
    let crops: Vec<(u32, u32)> = best.into_iter().collect::<Option<_>>()?;
    let (cw, ch) = crops
        .iter()
        .fold((0, 0), |(a, b), &(x, y)| (a.max(x), b.max(y)));
    if u64::from(cw) * u64::from(ch) >= scene.pixel_count() {
        return None;
    }
    let mut table: Table = text.parse().ok()?;
    let camera = table.get_mut("camera")?.as_table_mut()?;
    camera.insert("width".into(), Value::Integer(cw.into()));
    camera.insert("height".into(), Value::Integer(ch.into()));
    let cropped = toml::to_string(&table).ok()?;
    let small = Scene::from_toml(&cropped, "kept scene, cropped").ok()?;
    let coverage = Processor::new(&small).coverage(golden::window::Window::full(&small));
    points
        .iter()
        .all(|&p| coverage.contains(p))
        .then(|| Cropped {
            text: cropped,
            pixels: small.pixel_count(),
            coverage,
            from: (w, h),
            to: (cw, ch),
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_crop_holds_the_pixel_at_the_same_offset_from_the_centre() {
        // The crop keeps the pixel's offset from the centre,
        // px - W/2 = px' - W'/2, with px' its first or last column.
        for side in 1..=40u32 {
            for at in 0..side {
                let crop = crop_side(side, at);
                assert!(crop >= 1 && crop <= side, "side {side}, at {at}: {crop}");
                assert_eq!(crop % 2, side % 2, "side {side}, at {at}");
                let offset2 = 2 * i64::from(at) - i64::from(side);
                let at2 = if offset2 < 0 { 0 } else { i64::from(crop) - 1 };
                assert_eq!(2 * at2 - i64::from(crop), offset2, "side {side}, at {at}");
            }
        }
        assert_eq!(crop_side(16, 8), 2);
        assert_eq!(crop_side(16, 0), 16);
        assert_eq!(crop_side(16, 15), 16);
        assert_eq!(crop_side(15, 7), 1);
    }

    #[test]
    fn a_scene_shrinks_to_the_crop_that_reaches_its_points() {
        let scene = Scene::builtin("reference")
            .expect("builtin")
            .resized(16, 12, "t")
            .expect("resized");
        let text = scene.to_toml();
        // What the centre pixels alone reach, and the far corner's.
        let processor = Processor::new(&scene);
        let mut centre = Coverage::new();
        processor.render_pixel_covered(8, 5, &mut centre);
        let mut all = Coverage::new();
        for (x, y) in golden::window::Window::full(&scene).iter() {
            processor.render_pixel_covered(x, y, &mut all);
        }
        let points: Vec<Point> = centre.points().collect();
        let k = shrink(&text, &points).expect("shrinks");
        let small = Scene::from_toml(&k.text, "t").expect("loads");
        assert!(k.pixels < 192, "{}", k.pixels);
        assert_eq!(k.pixels, small.pixel_count());
        assert_eq!(
            (k.from, k.to),
            ((16, 12), (small.camera.width, small.camera.height))
        );
        assert!(points.iter().all(|&p| k.coverage.contains(p)));
        // The crop's pixels are the middle of the frame's: the same rays,
        // so the same colours.
        let (dx, dy) = (
            (16 - small.camera.width) / 2,
            (12 - small.camera.height) / 2,
        );
        let cropped_processor = Processor::new(&small);
        for (x, y) in golden::window::Window::full(&small).iter() {
            assert_eq!(
                cropped_processor.render_pixel(x, y, |_, _| {}).rgb,
                processor.render_pixel(x + dx, y + dy, |_, _| {}).rgb,
                "({x}, {y})"
            );
        }
        // Every point of the whole frame: the corners reach some, so no
        // crop smaller than the frame holds them all.
        let every: Vec<Point> = all.points().collect();
        assert_eq!(shrink(&text, &every), None);
    }
}
