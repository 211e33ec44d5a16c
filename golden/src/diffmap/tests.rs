use super::*;
use image::Rgb;

/// A 3x2 pair: `a` is 0.5 everywhere; `b` differs, on the 0..255 scale, by
///
/// ```text
/// (0,0) nothing             (1,0) R 2e-5            (2,0) G 3e-4
/// (0,1) R 5e-6, B 1.0       (1,1) R 0.6, G 0.7, B 2e-4   (2,1) nothing
/// ```
fn pair() -> (Frame, Frame) {
    let a = Frame::from_pixels(3, 2, vec![[0.5; 3]; 6]).expect("6 pixels");
    let d = |r: f64, g: f64, b: f64| [0.5 + r / 255.0, 0.5 + g / 255.0, 0.5 + b / 255.0];
    let b = Frame::from_pixels(
        3,
        2,
        vec![
            d(0.0, 0.0, 0.0),
            d(2e-5, 0.0, 0.0),
            d(0.0, 3e-4, 0.0),
            d(5e-6, 0.0, 1.0),
            d(0.6, 0.7, 2e-4),
            d(0.0, 0.0, 0.0),
        ],
    )
    .expect("6 pixels");
    (a, b)
}

fn close(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-9 * y.abs().max(1e-12)
}

#[test]
fn the_thesis_thresholds_count_the_hand_made_pair() {
    let (a, b) = pair();
    let map = DiffMap::new(&a, &b).expect("same size");
    let t = map.table("a", "b", &THESIS_THRESHOLDS);
    assert_eq!((t.width, t.height, t.channels), (3, 2, 18));
    // Every difference but the 5e-6 is over 1e-5: six of eighteen.
    assert_eq!(t.rows[0].over, 6);
    assert!(close(t.rows[0].share, 6.0 / 18.0));
    let mean = (2e-5 + 3e-4 + 1.0 + 0.6 + 0.7 + 2e-4) / 6.0;
    assert!(close(t.rows[0].mean_over.expect("some over"), mean));
    // Over 1e-4: 3e-4, 1.0, 0.6, 0.7, 2e-4.
    assert_eq!(t.rows[1].over, 5);
    assert!(close(t.rows[1].mean_over.expect("some over"), 2.3005 / 5.0));
    // Over 0.5: 1.0, 0.6, 0.7.
    assert_eq!(t.rows[2].over, 3);
    assert!(close(t.rows[2].share, 3.0 / 18.0));
    assert!(close(t.rows[2].mean_over.expect("some over"), 2.3 / 3.0));
    assert_eq!(t.differing, 7);
    // Largest per pixel: B of (0,1), G of (1,1), G of (2,0).
    let largest: Vec<_> = t.largest.iter().map(|l| (l.x, l.y, l.channel)).collect();
    assert_eq!(largest, [(0, 1, "B"), (1, 1, "G"), (2, 0, "G")]);
    assert!(close(t.largest[0].value, 1.0));
    assert!(close(t.largest[1].value, 0.7));
    assert!(close(t.largest[2].value, 3e-4));
}

#[test]
fn a_threshold_nothing_exceeds_has_no_average() {
    let (a, b) = pair();
    let t = DiffMap::new(&a, &b)
        .expect("same size")
        .table("a", "b", &[1.0, 2.0]);
    assert_eq!((t.rows[0].over, t.rows[0].mean_over), (0, None));
    assert_eq!(t.rows[1].share, 0.0);
    let same = DiffMap::new(&a, &a)
        .expect("same size")
        .table("a", "a", &[0.0]);
    assert_eq!((same.differing, same.rows[0].over), (0, 0));
    assert!(same.largest.is_empty());
    assert_eq!((same.max_ulps, &same.max_ulps_at), (0, &None));
    assert!(same.markdown().contains("largest differences: none"));
}

#[test]
fn masks_are_black_where_a_channel_is_over_the_threshold() {
    let (a, b) = pair();
    let map = DiffMap::new(&a, &b).expect("same size");
    let black = |t: f64| -> Vec<(u32, u32)> {
        let m = map.mask(t);
        assert_eq!(m.dimensions(), (3, 2));
        assert!(m.pixels().all(|p| p.0[0] == 0 || p.0[0] == 255));
        m.enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] == 0)
            .map(|(x, y, _)| (x, y))
            .collect()
    };
    assert_eq!(black(1e-5), [(1, 0), (2, 0), (0, 1), (1, 1)]);
    assert_eq!(black(1e-4), [(2, 0), (0, 1), (1, 1)]);
    assert_eq!(black(0.5), [(0, 1), (1, 1)]);
    assert_eq!(black(1.0), []);
}

#[test]
fn ulps_are_counted_on_f32_values_and_the_f64_side_is_rounded_first() {
    let one = 1.0f32;
    let three_up = f32::from_bits(one.to_bits() + 3);
    // 0.1 in f64 is not an f32: rounded to the nearest f32 it is 0 ulp
    // from 0.1f32, though 1.5e-9 apart (0.38e-6 on the 0..255 scale).
    let a = Frame::from_pixels(2, 1, vec![[1.0, 0.1, -0.0], [0.25, 0.25, 0.25]]).expect("2 pixels");
    let b = Frame::from_pixels(
        2,
        1,
        vec![
            [f64::from(three_up), f64::from(0.1f32), 0.0],
            [0.25, 0.25, 0.25],
        ],
    )
    .expect("2 pixels");
    let map = DiffMap::new(&a, &b).expect("same size");
    let t = map.table("a", "b", &[0.0]);
    assert_eq!(t.max_ulps, 3);
    assert_eq!(
        t.max_ulps_at,
        Some(Place {
            x: 0,
            y: 0,
            channel: "R"
        })
    );
    // R (3 ulp of 1.0) and G (0.1 against 0.1f32) differ; -0 and +0 do not.
    assert_eq!(t.differing, 2);
    let g = (0.1f64 - f64::from(0.1f32)).abs() * 255.0;
    assert!(g > 0.0 && g < 1e-6);
    assert_eq!(t.largest[0].ulps, Some(3));
}

#[test]
fn heat_maps_have_the_frame_beside_a_legend() {
    let (a, b) = pair();
    let map = DiffMap::new(&a, &b).expect("same size");
    for img in [map.ulp_heat_map(1), map.abs_heat_map(1)] {
        // 3 + the legend strip wide, at least the legend's height tall.
        assert_eq!(img.dimensions(), (3 + draw::LEGEND_WIDTH, draw::MIN_HEIGHT));
        // Pixels that do not differ are black; the others are not.
        assert_eq!(*img.get_pixel(0, 0), draw::ZERO);
        assert_eq!(*img.get_pixel(2, 1), draw::ZERO);
        for (x, y) in [(1, 0), (2, 0), (0, 1), (1, 1)] {
            assert_ne!(*img.get_pixel(x, y), draw::ZERO, "({x}, {y})");
        }
        // The legend holds the whole ramp and some black text.
        let legend: Vec<Rgb<u8>> = img
            .enumerate_pixels()
            .filter(|(x, _, _)| *x >= 3)
            .map(|(_, _, p)| *p)
            .collect();
        assert!(legend.contains(&draw::ramp(0.0)) && legend.contains(&draw::ramp(1.0)));
        assert!(legend.contains(&draw::ZERO));
        assert!(!legend.contains(&draw::NAN));
    }
    // The ramp's green rises from end to end, so larger differences are
    // greener: (0,1) 1.0 > (1,1) 0.7 > (2,0) 3e-4 > (1,0) 2e-5.
    let img = map.abs_heat_map(1);
    let green = |x, y| img.get_pixel(x, y).0[1];
    assert!(green(0, 1) > green(1, 1), "{img:?}");
    assert!(green(1, 1) > green(2, 0) && green(2, 0) > green(1, 0));
}

#[test]
fn a_nan_on_one_side_is_its_own_colour_and_an_infinite_difference() {
    let a = Frame::from_pixels(2, 1, vec![[f64::NAN, 0.0, 0.0], [0.0; 3]]).expect("2 px");
    let b = Frame::black(2, 1);
    let map = DiffMap::new(&a, &b).expect("same size");
    assert_eq!(*map.ulp_heat_map(1).get_pixel(0, 0), draw::NAN);
    assert_eq!(*map.abs_heat_map(1).get_pixel(0, 0), draw::NAN);
    let t = map.table("a", "b", &[0.5]);
    assert_eq!(t.nan_mismatches, 1);
    assert_eq!(t.rows[0].over, 1);
    assert_eq!(t.largest[0].value, f64::INFINITY);
    assert_eq!(t.largest[0].ulps, None);
    let json = serde_json::to_value(&t).expect("serializes");
    assert!(json["largest"][0]["value"].is_null());
}

#[test]
fn the_font_has_every_character_of_the_titles() {
    for title in ULP_TITLE.iter().chain(&ABS_TITLE).chain(&["0", "NaN"]) {
        assert!(title.chars().all(font::has_glyph), "{title}");
        assert!(
            font::text_width(title, 1) <= draw::LEGEND_WIDTH - 8,
            "{title}"
        );
    }
}

#[test]
fn big_frames_get_a_bigger_legend() {
    let a = Frame::black(500, 400);
    let img = DiffMap::new(&a, &a).expect("same size").ulp_heat_map(1);
    assert_eq!(img.dimensions(), (500 + 2 * draw::LEGEND_WIDTH, 400));
}

#[test]
fn frames_of_other_sizes_are_refused() {
    let err = DiffMap::new(&Frame::black(3, 2), &Frame::black(2, 3)).expect_err("sizes differ");
    assert_eq!(err.to_string(), "frames differ in size: 3x2 and 2x3");
}

#[test]
fn write_puts_maps_masks_and_tables_into_the_directory() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::temp_dir().join(format!("golden-diffmap-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let (a, b) = pair();
    let map = DiffMap::new(&a, &b)?;
    let (written, table) = map.write(&dir, "side a", "side b", &THESIS_THRESHOLDS, 1)?;
    let names: Vec<String> = written
        .iter()
        .map(|p| {
            p.file_name()
                .expect("a name")
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    assert_eq!(
        names,
        [
            "heat-ulp.png",
            "heat-abs.png",
            "mask-0.00001.png",
            "mask-0.0001.png",
            "mask-0.5.png",
            "table.md",
            "table.json"
        ]
    );
    let mask = image::open(dir.join("mask-0.5.png"))?.to_luma8();
    assert_eq!(mask.dimensions(), (3, 2));
    assert_eq!(mask.get_pixel(0, 1).0, [0]);
    assert_eq!(mask.get_pixel(0, 0).0, [255]);
    let heat = image::open(dir.join("heat-abs.png"))?;
    assert_eq!((heat.width(), heat.height()), (3 + 64, 160));
    let md = std::fs::read_to_string(dir.join("table.md"))?;
    assert_eq!(md, table.markdown());
    assert!(md.contains("A: side a\nB: side b\n"), "{md}");
    assert!(md.contains("| 0.00001 | 6 | 33.3333% |"), "{md}");
    assert!(md.contains("| 0.5 | 3 | 16.6667% | 0.7667 |"), "{md}");
    assert!(md.contains("1.000 at (0, 1) B"), "{md}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("table.json"))?)?;
    assert_eq!(json["rows"][1]["over"], 5);
    assert_eq!(json["rows"][1]["threshold"], 0.0001);
    assert_eq!(json["largest"][0]["channel"], "B");
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}

#[test]
fn write_names_the_file_it_cannot_write() {
    let (a, b) = pair();
    let map = DiffMap::new(&a, &b).expect("same size");
    let err = map
        .write(
            Path::new("/nonexistent-golden-diffmap"),
            "a",
            "b",
            &[0.5],
            1,
        )
        .expect_err("no such directory");
    assert!(
        err.to_string()
            .contains("/nonexistent-golden-diffmap/heat-ulp.png"),
        "{err}"
    );
}

#[test]
fn short_numbers_keep_four_significant_digits() {
    assert_eq!(short(0.00148), "0.001480");
    assert_eq!(short(2.56894), "2.569");
    assert_eq!(short(18.0), "18.00");
    assert_eq!(short(1.5e-7), "1.500e-7");
    assert_eq!(short(0.0), "0");
    assert_eq!(short(0.999_999_9), "1.000");
    assert_eq!(short(9.99996e-5), "0.0001000");
    assert_eq!(short(9.99996e-6), "1.000e-5");
}

#[test]
fn pooling_keeps_the_worst_cell_of_each_block() {
    use draw::Cell::{Nan, Value, Zero};
    // 5 x 3 cells in blocks of 2: 3 x 2 blocks, the last column and row
    // narrower.
    #[rustfmt::skip]
    let cells = [
        Zero,       Value(1.0), Zero, Zero, Value(7.0),
        Value(3.0), Zero,       Nan,  Zero, Zero,
        Zero,       Zero,       Zero, Zero, Value(0.5),
    ];
    let (w, h, pooled) = pool(5, 3, &cells, 2);
    assert_eq!((w, h), (3, 2));
    assert_eq!(
        pooled,
        [Value(3.0), Nan, Value(7.0), Zero, Zero, Value(0.5)]
    );
    assert_eq!(pool(5, 3, &cells, 1), (5, 3, cells.to_vec()));
    // A pooled heat map is the pooled size beside the legend.
    let (a, b) = pair();
    let img = DiffMap::new(&a, &b).expect("same size").abs_heat_map(2);
    assert_eq!(img.dimensions(), (2 + draw::LEGEND_WIDTH, draw::MIN_HEIGHT));
    // Blocks: {(0,0),(1,0),(0,1),(1,1)} and {(2,0),(2,1)} both differ.
    assert_ne!(*img.get_pixel(0, 0), draw::ZERO);
    assert_ne!(*img.get_pixel(1, 0), draw::ZERO);
}
