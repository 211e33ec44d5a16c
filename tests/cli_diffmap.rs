//! `rtcosim diffmap`, run as the built binary on tiny frames: models
//! rendered in-process (the RTL co-simulated), hand-made frame files with
//! known differences, and the requests it must refuse with exit 2.

mod common;

use common::{both, rtcosim, text};
use golden::frame::Frame;
use std::path::{Path, PathBuf};

fn scratch(test: &str) -> PathBuf {
    common::scratch("cli_diffmap", test)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

fn json(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("table.json")).expect("table.json written");
    serde_json::from_str(&text).expect("table.json is JSON")
}

fn luma(path: &Path) -> image::GrayImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_luma8()
}

#[test]
fn the_rtl_with_fast_units_against_the_exact_model_writes_every_file() {
    let dir = scratch("rtl");
    let maps = dir.join("maps");
    let out = rtcosim(&[
        "diffmap",
        "rtl",
        "micro",
        "--a-recip",
        "fast",
        "--a-sqrt",
        "fast",
        "--size",
        "16x12",
        "--threads",
        "2",
        "--out",
        s(&maps),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(
            "A: rtl co-simulated against micro (recip fast, sqrt fast): agrees bit for bit"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains("A: rtl (scene reference 16x12, recip fast, sqrt fast)\nB: micro (scene reference 16x12, recip exact, sqrt exact)\n"),
        "{stdout}"
    );
    // 16 x 12 pixels, three colour values each.
    assert!(
        stdout.contains("16x12 pixels, 576 colour values"),
        "{stdout}"
    );
    for name in [
        "heat-ulp.png",
        "heat-abs.png",
        "mask-0.00001.png",
        "mask-0.0001.png",
        "mask-0.5.png",
        "table.md",
        "table.json",
    ] {
        assert!(maps.join(name).is_file(), "{name} missing: {stdout}");
        assert!(stdout.contains(name), "{name} not listed: {stdout}");
    }
    assert_eq!(luma(&maps.join("mask-0.5.png")).dimensions(), (16, 12));
    let heat = image::open(maps.join("heat-ulp.png")).expect("a PNG");
    assert_eq!((heat.width(), heat.height()), (16 + 64, 160));
    let table = json(&maps);
    assert_eq!(table["channels"], 576);
    let rows = table["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 3);
    for row in rows {
        let over = row["over"].as_u64().expect("a count");
        let share = row["share"].as_f64().expect("a share");
        assert!((share - over as f64 / 576.0).abs() < 1e-12, "{row}");
    }
    // The masks count what the table counts: a black pixel has a channel over.
    let black = luma(&maps.join("mask-0.00001.png"))
        .pixels()
        .filter(|p| p.0[0] == 0)
        .count() as u64;
    let over = rows[0]["over"].as_u64().expect("a count");
    assert!(
        black <= over && over <= 3 * black,
        "{black} black, {over} over"
    );
}

#[test]
fn a_model_against_itself_differs_nowhere() {
    let dir = scratch("same");
    let out = rtcosim(&[
        "diffmap",
        "micro",
        "micro",
        "--size",
        "16x12",
        "--block",
        "4",
        "--out",
        s(&dir),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("576 colour values (channels) compared on the 0..255 scale; 0 differ"),
        "{stdout}"
    );
    assert!(stdout.contains("| 0.00001 | 0 | 0.0000% | - |"), "{stdout}");
    assert!(stdout.contains("largest differences: none"), "{stdout}");
    // Heat maps in blocks of 4x4: 4 x 3 beside the legend; masks full size.
    let heat = image::open(dir.join("heat-abs.png")).expect("a PNG");
    assert_eq!((heat.width(), heat.height()), (4 + 64, 160));
    for t in ["0.00001", "0.0001", "0.5"] {
        let mask = luma(&dir.join(format!("mask-{t}.png")));
        assert_eq!(mask.dimensions(), (16, 12));
        assert!(mask.pixels().all(|p| p.0[0] == 255), "{t}");
    }
}

/// 2x2 frames: b differs from a by 0.25/255 in R of (1, 0), by 2/255 in G
/// and B of (0, 1), and by 1e-3/255 in B of (1, 1).
fn hand_made_files(dir: &Path) -> (PathBuf, PathBuf) {
    let a = Frame::from_pixels(2, 2, vec![[0.5; 3]; 4]).expect("4 pixels");
    let mut b = a.clone();
    b.pixels[1][0] += 0.25 / 255.0;
    b.pixels[2][1] += 2.0 / 255.0;
    b.pixels[2][2] -= 2.0 / 255.0;
    b.pixels[3][2] += 1e-3 / 255.0;
    let (pa, pb) = (dir.join("a.exr"), dir.join("b.exr"));
    a.save_exr(&pa).expect("writing a.exr");
    b.save_exr(&pb).expect("writing b.exr");
    (pa, pb)
}

#[test]
fn two_frame_files_are_compared_at_the_given_thresholds() {
    let dir = scratch("files");
    let (a, b) = hand_made_files(&dir);
    let maps = dir.join("maps");
    let out = rtcosim(&[
        "diffmap",
        s(&a),
        s(&b),
        "--thresholds",
        "0.0001,0.1,1",
        "--out",
        s(&maps),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains(&format!("A: file {} (2x2)", a.display())),
        "{stdout}"
    );
    let table = json(&maps);
    // Over 1e-4: 0.25, 2, 2, 1e-3 (4 of 12); over 0.1: 0.25, 2, 2; over 1: 2, 2.
    let over: Vec<u64> = table["rows"]
        .as_array()
        .expect("rows")
        .iter()
        .map(|r| r["over"].as_u64().expect("a count"))
        .collect();
    assert_eq!(over, [4, 3, 2]);
    let mean = table["rows"][2]["mean_over"].as_f64().expect("a mean");
    // f32 storage moves each 2/255 step by under 1e-5 on the 0..255 scale.
    assert!((mean - 2.0).abs() < 1e-4, "{mean}");
    assert_eq!(table["largest"][0]["x"], 0);
    assert_eq!(table["largest"][0]["y"], 1);
    // Black where a channel is over: (1,0) and (0,1) at 0.1, only (0,1) at 1.
    let black = |t: &str| -> Vec<(u32, u32)> {
        luma(&maps.join(format!("mask-{t}.png")))
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] == 0)
            .map(|(x, y, _)| (x, y))
            .collect()
    };
    assert_eq!(black("0.1"), [(1, 0), (0, 1)]);
    assert_eq!(black("1"), [(0, 1)]);
    assert_eq!(black("0.0001"), [(1, 0), (0, 1), (1, 1)]);
}

#[test]
fn bad_requests_exit_2_and_say_what_is_wrong() {
    let dir = scratch("bad");
    let (a, b) = hand_made_files(&dir);
    let bytes = std::fs::read(&a).expect("a.exr");
    let cut = dir.join("cut.exr");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("writing cut.exr");
    let png = dir.join("frame.exr");
    Frame::black(2, 2).save_png(&png).expect("a PNG named .exr");
    let a_file = dir.join("a-file");
    std::fs::write(&a_file, "not a directory").expect("writing a file");
    let out_dir = dir.join("out");
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec![s(&cut), s(&b), "--out", s(&out_dir)],
            format!("{}: damaged or truncated OpenEXR file", cut.display()),
        ),
        (
            vec![s(&png), s(&b), "--out", s(&out_dir)],
            format!("{}: not an OpenEXR file", png.display()),
        ),
        (
            vec![s(&a), "micro", "--size", "8x8", "--out", s(&out_dir)],
            "A is 2x2 and B is 8x8: the frames must have the same size".into(),
        ),
        (
            vec![s(&a), "micro", "--a-recip", "fast", "--out", s(&out_dir)],
            "but A is the frame file".into(),
        ),
        (
            vec![s(&a), s(&b), "--out", s(&a_file)],
            "not a directory".into(),
        ),
        (
            vec![s(&a), s(&b), "--out", "/nonexistent-rtcosim-dir/maps"],
            "no such directory /nonexistent-rtcosim-dir".into(),
        ),
        (
            vec![
                "micro",
                "reference",
                "--scene",
                "no-such-scene",
                "--out",
                s(&out_dir),
            ],
            "no-such-scene: no such scene file".into(),
        ),
    ];
    for (args, message) in cases {
        let out = rtcosim(&[&["diffmap"][..], &args].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", both(&out));
        let stderr = text(&out.stderr);
        assert!(stderr.contains(&message), "{args:?}: {stderr}");
    }
    // Nothing was written for any of them.
    assert!(!out_dir.exists());
}

/// A reference frame written to a file is rounded to f32: against the f64
/// frame rendered in-process it moves no channel by more than 2^-25 (for
/// values up to 1), under the 0.00001 threshold, though many differ.
#[test]
fn a_reference_file_differs_from_the_in_process_reference_by_its_rounding_only() {
    let dir = scratch("reference-file");
    let scene = golden::scene::Scene::builtin("reference")
        .expect("builtin")
        .resized(16, 12, "16x12")
        .expect("a smaller image of a valid scene");
    let frame = golden::reference::render(&scene, &|_| {});
    assert!(
        frame.max_channel() <= 1.0,
        "the bound below is for values up to 1"
    );
    let file = dir.join("reference.exr");
    frame.save_exr(&file).expect("writing the frame file");
    let maps = dir.join("maps");
    let out = rtcosim(&[
        "diffmap",
        s(&file),
        "reference",
        "--size",
        "16x12",
        "--thresholds",
        "0,0.00001",
        "--out",
        s(&maps),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let table = json(&maps);
    // Some channels are not f32 values, so they moved; none by 1e-5.
    assert!(
        table["rows"][0]["over"].as_u64().expect("a count") > 0,
        "{table}"
    );
    assert_eq!(table["rows"][1]["over"], 0, "{table}");
    let largest = table["largest"][0]["value"].as_f64().expect("a difference");
    assert!(largest <= 255.0 * 2f64.powi(-25), "{largest}");
    // Rounded to f32 first, the reference is 0 ULP from its file.
    assert_eq!(table["max_ulps"], 0, "{table}");
}

#[test]
fn render_exr_writes_the_micro_models_frame_bit_for_bit() {
    let dir = scratch("render-exr");
    let (png, exr) = (dir.join("m.png"), dir.join("m.exr"));
    let out = rtcosim(&[
        "render",
        "--model",
        "micro",
        "--size",
        "16x12",
        "--out",
        s(&png),
        "--exr",
        s(&exr),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let scene = golden::scene::Scene::reference()
        .resized(16, 12, "16x12")
        .expect("a smaller image of a valid scene");
    let (expected, _) = golden::micro::render(&scene, &|_| {});
    assert_eq!(Frame::load_exr(&exr).expect("m.exr"), expected);
}
