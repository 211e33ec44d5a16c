//! `rtcosim fuzz --first`, run as the built binary: the campaign runs the
//! scenes `first..first + count` of its seed and no others. Which scenes
//! those are is read back from what the binary writes (the failing scenes
//! of a campaign with an injected fault, every accepted one) and held to
//! the generator's scene of each index, each one loaded by golden's
//! validator here to know whether it is accepted. Bad values are refused
//! with exit 2.

mod common;

use common::{arg, assert_refused, both, rtcosim, scratch, text};
use golden::scene::Scene;
use rtcosim::campaign::fuzz::generate;

const SEED: u64 = 3;
const FIRST: u64 = 5;
const COUNT: u64 = 4;

/// The scenes of `indices` that golden's validator accepts.
fn accepted(indices: std::ops::Range<u64>) -> Vec<u64> {
    indices
        .filter(|&i| {
            let g = generate::scene(SEED, i);
            Scene::from_toml(&g.toml, "fuzz scene").is_ok()
        })
        .collect()
}

/// The number after `key` (up to the next space) on the report line that
/// starts with `line`.
fn count_after(stdout: &str, line: &str, key: &str) -> u64 {
    let l = stdout
        .lines()
        .find(|l| l.starts_with(line))
        .unwrap_or_else(|| panic!("no line {line:?} in\n{stdout}"));
    let at = l.find(key).unwrap_or_else(|| panic!("no {key:?} in {l:?}")) + key.len();
    l[at..]
        .split(' ')
        .next()
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no number after {key:?} in {l:?}"))
}

/// A campaign from index 5: with the fault, every accepted scene of 5..9
/// fails and is written as its index's scene, and no scene of another
/// index is; without it, the same scenes pass and are counted alike.
#[test]
fn first_starts_the_campaign_at_that_scene_index() {
    let want = accepted(FIRST..FIRST + COUNT);
    // The seed and range are picked so that both fates occur (a range
    // whose scenes were all refused would prove nothing).
    assert!(
        !want.is_empty() && want.len() < COUNT as usize,
        "accepted {want:?}: pick another range"
    );
    // Scenes before the range would be different files.
    assert_ne!(
        generate::scene(SEED, 0).toml,
        generate::scene(SEED, FIRST).toml
    );
    let dir = scratch("cli_fuzz", "first");
    let failures = dir.join("failures");
    let (seed, first, count) = (SEED.to_string(), FIRST.to_string(), COUNT.to_string());
    let run = |extra: &[&str]| {
        let mut args = vec![
            "fuzz",
            "--seed",
            &seed,
            "--first",
            &first,
            "--count",
            &count,
            "--threads",
            "2",
            "--failures",
            arg(&failures),
        ];
        args.extend(extra);
        rtcosim(&args)
    };

    let out = run(&["--fault", "PRI_HALF:0x400"]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout.starts_with(&format!(
            "rtcosim fuzz: {COUNT} scenes from index {FIRST}, seed {SEED}, 2 threads, "
        )),
        "{stdout}"
    );
    let mut written: Vec<String> = std::fs::read_dir(&failures)
        .unwrap_or_else(|e| panic!("{}: {e}\n{}", failures.display(), both(&out)))
        .map(|e| {
            e.expect("listing")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    written.sort();
    let mut names: Vec<String> = want
        .iter()
        .map(|i| format!("seed-{SEED}-scene-{i}.toml"))
        .collect();
    names.sort();
    assert_eq!(written, names, "{stdout}");
    for &i in &want {
        let file = failures.join(format!("seed-{SEED}-scene-{i}.toml"));
        let on_disk = std::fs::read_to_string(&file).expect("a failing scene");
        assert_eq!(on_disk, generate::scene(SEED, i).toml, "scene {i}");
        assert!(
            stdout.contains(&format!("FAILED: seed {SEED} scene {i} (written to ")),
            "{i}: {stdout}"
        );
    }
    assert_eq!(stdout.matches("FAILED: ").count(), want.len(), "{stdout}");
    assert_eq!(count_after(&stdout, "scenes: ", "scenes: "), COUNT);
    assert_eq!(
        count_after(&stdout, "scenes: ", "generated, "),
        want.len() as u64
    );

    // Without the fault: the same scenes, all kept.
    std::fs::remove_dir_all(&failures).expect("clearing the failures");
    let out = run(&[]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert_eq!(
        count_after(&stdout, "scenes: ", "generated, "),
        want.len() as u64,
        "{stdout}"
    );
    assert!(stdout.contains("\nPASS: "), "{stdout}");
    assert!(!failures.exists(), "no scene failed");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad values of --first (and a range past the last index) exit 2 naming
/// the option, with nothing run and no panic.
#[test]
fn bad_first_values_are_refused_with_exit_2() {
    let dir = scratch("cli_fuzz", "bad");
    let failures = dir.join("failures");
    let max = u64::MAX.to_string();
    let cases: [(&[&str], &str); 4] = [
        (
            &["--first", "-1"],
            "invalid value '-1' for '--first <FIRST>'",
        ),
        (
            &["--first", "five"],
            "invalid value 'five' for '--first <FIRST>'",
        ),
        (
            &["--first", "18446744073709551616"],
            "invalid value '18446744073709551616' for '--first <FIRST>'",
        ),
        (
            &["--first", &max, "--count", "2"],
            "--first 18446744073709551615 with --count 2",
        ),
    ];
    for (args, message) in cases {
        let mut all = vec!["fuzz", "--failures", arg(&failures)];
        all.extend(args);
        assert_refused(&all, &[message]);
    }
    assert!(!failures.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `fuzz --processor fast`: the campaign runs on the fast processor (the
/// header says so) and passes; with a fault injected every accepted scene
/// fails; a bad processor is refused naming the choices.
#[test]
fn fuzz_runs_on_the_fast_processor() {
    let dir = scratch("cli_fuzz", "fast");
    let failures = dir.join("failures");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "fuzz",
            "--seed",
            "3",
            "--count",
            "12",
            "--processor",
            "fast",
        ];
        args.extend(["--failures", arg(&failures)]);
        args.extend(extra);
        rtcosim(&args)
    };
    let out = run(&[]);
    assert_eq!(out.status.code(), Some(0), "{}", both(&out));
    let stdout = text(&out.stdout);
    assert!(
        stdout
            .lines()
            .next()
            .is_some_and(|l| l.contains(", fast processor, ")),
        "{stdout}"
    );
    assert!(stdout.contains("0 divergent pixels"), "{stdout}");
    let out = run(&["--fault", "PRI_HALF:0x400"]);
    assert_eq!(out.status.code(), Some(1), "{}", both(&out));
    assert_refused(
        &["fuzz", "--count", "1", "--processor", "slow"],
        &[
            "invalid value 'slow' for '--processor <PROCESSOR>'",
            "[possible values: compact, fast]",
        ],
    );
}

/// A guided campaign with --out writes its report and its chart of
/// coverage against candidates; `fuzz --chart` draws several campaigns'
/// curves in one chart, and refuses (exit 2) a file that is not a
/// campaign's report, naming it, and a chart without --out.
#[test]
fn guided_campaigns_are_charted() {
    let dir = scratch("cli_fuzz", "chart");
    let (corpus, out) = (dir.join("corpus"), dir.join("out"));
    let run = rtcosim(&[
        "fuzz",
        "--corpus",
        arg(&corpus),
        "--count",
        "16",
        "--threads",
        "1",
        "--out",
        arg(&out),
    ]);
    assert_eq!(run.status.code(), Some(0), "{}", both(&run));
    for f in ["guided.json", "coverage.svg", "coverage.png"] {
        assert!(out.join(f).is_file(), "{f}: {}", both(&run));
    }
    let report = out.join("guided.json");
    let chart = dir.join("chart");
    let drawn = rtcosim(&[
        "fuzz",
        "--chart",
        arg(&report),
        arg(&report),
        "--out",
        arg(&chart),
    ]);
    assert_eq!(drawn.status.code(), Some(0), "{}", both(&drawn));
    let stdout = text(&drawn.stdout);
    assert_eq!(
        stdout
            .lines()
            .filter(|l| l.starts_with("guided, compact processor, seed 1: 16 candidates, "))
            .count(),
        2,
        "{stdout}"
    );
    let svg = std::fs::read_to_string(chart.join("coverage.svg")).expect("the SVG");
    assert!(svg.contains("reachable ISA transitions"), "{svg}");
    image::open(chart.join("coverage.png")).expect("the PNG");

    let bad = dir.join("bad.json");
    std::fs::write(&bad, "{}").expect("write");
    let refused = rtcosim(&["fuzz", "--chart", arg(&bad), "--out", arg(&chart)]);
    assert_eq!(refused.status.code(), Some(2), "{}", both(&refused));
    let stderr = text(&refused.stderr);
    assert!(
        stderr.contains(&format!(
            "{}: not a guided campaign's report",
            bad.display()
        )),
        "{stderr}"
    );
    let no_out = rtcosim(&["fuzz", "--chart", arg(&report)]);
    assert_eq!(no_out.status.code(), Some(2), "{}", both(&no_out));
    assert!(
        text(&no_out.stderr).contains("--chart: give --out DIR"),
        "{}",
        both(&no_out)
    );
    assert_refused(
        &["fuzz", "--chart", arg(&report), "--corpus", arg(&corpus)],
        &["'--chart <GUIDED_JSON>...' cannot be used with '--corpus <DIR>'"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}
