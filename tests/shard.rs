//! Sharded runs (docs/scale.md): N shards of a sweep or a fuzz campaign,
//! merged with `rtcosim merge`, give the unsharded run's outputs byte for
//! byte; so do the checked-in Slurm array scripts run for every array index
//! (with Slurm's variables, and with a Kubernetes Indexed Job's); and merge
//! refuses, naming them, sets of shards that are not one whole run.

mod common;

use common::{arg, both, scratch, text};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SHARD_VARIABLES: [&str; 6] = [
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_STEP",
    "JOB_COMPLETION_INDEX",
    "RTCOSIM_SHARD_COUNT",
];

/// `program args` with `vars` set and every other shard variable removed
/// (so that a test run inside a Slurm job is not taken for a shard).
fn run_with(program: &str, args: &[&str], vars: &[(&str, String)]) -> Output {
    let mut cmd = Command::new(program);
    cmd.args(args);
    for v in SHARD_VARIABLES {
        cmd.env_remove(v);
    }
    for (k, v) in vars {
        cmd.env(k, v);
    }
    cmd.output()
        .unwrap_or_else(|e| panic!("running {program}: {e}"))
}

fn rtcosim(args: &[&str], vars: &[(&str, String)]) -> Output {
    run_with(env!("CARGO_BIN_EXE_rtcosim"), args, vars)
}

fn ok(out: Output, what: &str) -> Output {
    assert!(out.status.success(), "{what}: {}", both(&out));
    out
}

/// The files of `dir` (not its subdirectories), by name.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("listing").path())
        .filter(|p| p.is_file())
        .collect();
    v.sort();
    v
}

/// How the output files of `a` and `b` differ: files only in one, files
/// whose bytes differ (with the first differing byte). Shard files are not
/// outputs and are left out.
fn differences(a: &Path, b: &Path) -> Vec<String> {
    let outputs = |d: &Path| -> Vec<String> {
        files(d)
            .iter()
            .filter_map(|p| p.file_name()?.to_str().map(String::from))
            .filter(|n| !n.ends_with(".shard.json"))
            .collect()
    };
    let (na, nb) = (outputs(a), outputs(b));
    let mut out = Vec::new();
    for n in na.iter().filter(|n| !nb.contains(n)) {
        out.push(format!("{n} only in {}", a.display()));
    }
    for n in nb.iter().filter(|n| !na.contains(n)) {
        out.push(format!("{n} only in {}", b.display()));
    }
    for n in na.iter().filter(|n| nb.contains(n)) {
        let (x, y) = (
            std::fs::read(a.join(n)).expect("readable"),
            std::fs::read(b.join(n)).expect("readable"),
        );
        if x != y {
            let at = x.iter().zip(&y).position(|(p, q)| p != q);
            out.push(format!(
                "{n}: {} and {} bytes, first difference at {at:?}",
                x.len(),
                y.len()
            ));
        }
    }
    out
}

fn assert_same_outputs(whole: &Path, merged: &Path, expected: &[&str]) {
    let names: Vec<String> = files(whole)
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, expected, "the unsharded run's outputs");
    let diff = differences(whole, merged);
    assert!(diff.is_empty(), "{}", diff.join("\n"));
}

const SWEEP: [&str; 9] = [
    "sweep",
    "--scenes",
    "reference,box_room",
    "--size",
    "40x30",
    "--depths",
    "1,4",
    "--sample",
    "16",
];

const SWEEP_OUTPUTS: [&str; 6] = [
    "chart-box_room.png",
    "chart-box_room.svg",
    "chart-reference.png",
    "chart-reference.svg",
    "sweep.csv",
    "sweep.json",
];

#[test]
fn sweep_shards_merge_to_the_unsharded_run_byte_for_byte() {
    let dir = scratch("shard", "sweep");
    let (whole, shards, merged) = (dir.join("whole"), dir.join("shards"), dir.join("merged"));
    let mut args = SWEEP.to_vec();
    args.extend(["--out", arg(&whole)]);
    ok(rtcosim(&args, &[]), "the unsharded sweep");
    for k in 0..3 {
        let shard = format!("{k}/3");
        let mut args = SWEEP.to_vec();
        args.extend(["--out", arg(&shards), "--shard", &shard]);
        let out = ok(rtcosim(&args, &[]), &shard);
        assert!(
            text(&out.stdout).contains(&format!("sweep-{k}-of-3.shard.json")),
            "{}",
            both(&out)
        );
        // A shard writes its shard file and nothing else.
        assert_eq!(files(&shards).len(), k + 1);
    }
    let out = ok(
        rtcosim(&["merge", arg(&shards), "--out", arg(&merged)], &[]),
        "merge",
    );
    assert!(text(&out.stdout).contains("merging 3 sweep shards"));
    assert_same_outputs(&whole, &merged, &SWEEP_OUTPUTS);

    // The comparison sees a dropped row and a changed byte of a chart.
    let csv = merged.join("sweep.csv");
    let full = std::fs::read_to_string(&csv).expect("sweep.csv");
    let mut lines: Vec<&str> = full.lines().collect();
    lines.remove(7);
    std::fs::write(&csv, lines.join("\n") + "\n").expect("writable");
    let diff = differences(&whole, &merged);
    assert!(
        diff.len() == 1 && diff[0].starts_with("sweep.csv"),
        "{diff:?}"
    );
    std::fs::write(&csv, &full).expect("writable");
    let png = merged.join("chart-reference.png");
    let mut bytes = std::fs::read(&png).expect("png");
    let last = bytes.len() - 20;
    bytes[last] ^= 1;
    std::fs::write(&png, &bytes).expect("writable");
    let diff = differences(&whole, &merged);
    assert!(
        diff.len() == 1 && diff[0].starts_with("chart-reference.png"),
        "{diff:?}"
    );
}

const FUZZ: [&str; 5] = ["fuzz", "--seed", "2026", "--count", "30"];

#[test]
fn fuzz_shards_merge_to_the_unsharded_campaign_byte_for_byte() {
    let dir = scratch("shard", "fuzz");
    let (whole, shards, merged) = (dir.join("whole"), dir.join("shards"), dir.join("merged"));
    let failures = dir.join("failures");
    let mut args = FUZZ.to_vec();
    args.extend(["--failures", arg(&failures), "--out", arg(&whole)]);
    let unsharded = ok(rtcosim(&args, &[]), "the unsharded campaign");
    for k in 0..4 {
        let shard = format!("{k}/4");
        let mut args = FUZZ.to_vec();
        args.extend([
            "--failures",
            arg(&failures),
            "--out",
            arg(&shards),
            "--shard",
            &shard,
        ]);
        ok(rtcosim(&args, &[]), &shard);
    }
    let out = ok(
        rtcosim(&["merge", arg(&shards), "--out", arg(&merged)], &[]),
        "merge",
    );
    assert_same_outputs(&whole, &merged, &["fuzz-report.txt"]);
    // The report is what the unsharded run printed, timing aside.
    let report = std::fs::read_to_string(whole.join("fuzz-report.txt")).expect("report");
    assert!(text(&unsharded.stdout).contains(&report));
    assert!(text(&out.stdout).contains(&report));
    assert!(report.contains("scenes: 30 generated") && report.contains("PASS"));

    // The comparison sees a changed count.
    let path = merged.join("fuzz-report.txt");
    std::fs::write(&path, report.replace("30 generated", "29 generated")).expect("writable");
    assert_eq!(differences(&whole, &merged).len(), 1);
}

/// A campaign and a sweep that fail (an injected RTL fault) merge to the
/// same failure, with the same exit status 1, as their unsharded runs.
#[test]
fn failing_runs_merge_to_the_same_failure() {
    let dir = scratch("shard", "failing");
    let failures = dir.join("failures");
    let fuzz = [
        "fuzz",
        "--seed",
        "4",
        "--count",
        "8",
        "--fault",
        "PRI_HALF:0x400",
        "--failures",
        arg(&failures),
    ];
    let sweep = [
        "sweep",
        "--size",
        "16x12",
        "--depths",
        "2",
        "--cutoffs",
        "0",
        "--sample",
        "8",
        "--fault",
        "PRI_HALF:0x400",
    ];
    for (name, args, outputs) in [
        ("fuzz", &fuzz[..], &["fuzz-report.txt"][..]),
        (
            "sweep",
            &sweep[..],
            &[
                "chart-reference.png",
                "chart-reference.svg",
                "sweep.csv",
                "sweep.json",
            ][..],
        ),
    ] {
        let (whole, shards, merged) = (
            dir.join(format!("{name}-whole")),
            dir.join(format!("{name}-shards")),
            dir.join(format!("{name}-merged")),
        );
        let mut v = args.to_vec();
        v.extend(["--out", arg(&whole)]);
        let out = rtcosim(&v, &[]);
        assert_eq!(out.status.code(), Some(1), "{name}: {}", both(&out));
        for k in 0..2 {
            let shard = format!("{k}/2");
            let mut v = args.to_vec();
            v.extend(["--out", arg(&shards), "--shard", &shard]);
            rtcosim(&v, &[]);
            assert!(shards.join(format!("{name}-{k}-of-2.shard.json")).is_file());
        }
        let out = rtcosim(&["merge", arg(&shards), "--out", arg(&merged)], &[]);
        assert_eq!(out.status.code(), Some(1), "{name}: {}", both(&out));
        assert!(
            text(&out.stdout).contains("FAILED"),
            "{name}: {}",
            both(&out)
        );
        assert_same_outputs(&whole, &merged, outputs);
    }
}

/// The array range of a script's `#SBATCH --array=A-B` line.
fn array_range(script: &str) -> (u64, u64) {
    let line = script
        .lines()
        .find_map(|l| l.strip_prefix("#SBATCH --array="))
        .expect("an #SBATCH --array line");
    let (a, b) = line.trim().split_once('-').expect("--array=A-B");
    (a.parse().expect("a number"), b.parse().expect("a number"))
}

/// Runs the checked-in script `name` under docs/scale with `vars` (the
/// variables it documents) the way every task of its array would see it,
/// as Slurm and as a Kubernetes Indexed Job, merges each, and compares both
/// with the script run unsharded.
fn script_runs_merge_to_the_unsharded_run(name: &str, vars: &[(&str, &str)], outputs: &[&str]) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("docs/scale")
        .join(name);
    let body = std::fs::read_to_string(&script).expect("the script");
    let (first, last) = array_range(&body);
    let count = last - first + 1;
    assert!(count >= 2, "{name}: an array of {count}");
    let dir = scratch("shard", name);
    let run = |out: &Path, extra: &[(&str, String)]| {
        let mut all: Vec<(&str, String)> = vec![
            ("RTCOSIM", env!("CARGO_BIN_EXE_rtcosim").to_string()),
            ("OUT", arg(out).to_string()),
            ("FAILURES", arg(&dir.join("failures")).to_string()),
        ];
        all.extend(vars.iter().map(|(k, v)| (*k, v.to_string())));
        all.extend(extra.iter().cloned());
        ok(run_with("bash", &[arg(&script)], &all), name)
    };
    let whole = dir.join("whole");
    run(&whole, &[]);
    // Slurm numbers the tasks from the array's first index; shift it to
    // prove the shard is the ID minus SLURM_ARRAY_TASK_MIN.
    let offset = 10;
    let slurm = dir.join("slurm");
    for id in first + offset..=last + offset {
        run(
            &slurm,
            &[
                ("SLURM_ARRAY_TASK_ID", id.to_string()),
                ("SLURM_ARRAY_TASK_MIN", (first + offset).to_string()),
                ("SLURM_ARRAY_TASK_COUNT", count.to_string()),
            ],
        );
    }
    let k8s = dir.join("k8s");
    for index in 0..count {
        run(
            &k8s,
            &[
                ("JOB_COMPLETION_INDEX", index.to_string()),
                ("RTCOSIM_SHARD_COUNT", count.to_string()),
            ],
        );
    }
    for shards in [&slurm, &k8s] {
        assert_eq!(files(shards).len() as u64, count, "{}", shards.display());
        let merged = shards.join("merged");
        ok(
            rtcosim(&["merge", arg(shards), "--out", arg(&merged)], &[]),
            "merge",
        );
        assert_same_outputs(&whole, &merged, outputs);
    }
}

#[test]
fn the_sweep_array_script_merges_to_the_unsharded_run() {
    script_runs_merge_to_the_unsharded_run(
        "sweep.sbatch",
        &[
            ("SCENES", "reference,mirror"),
            ("SIZE", "24x18"),
            ("DEPTHS", "2,4"),
        ],
        &[
            "chart-mirror.png",
            "chart-mirror.svg",
            "chart-reference.png",
            "chart-reference.svg",
            "sweep.csv",
            "sweep.json",
        ],
    );
}

#[test]
fn the_fuzz_array_script_merges_to_the_unsharded_run() {
    script_runs_merge_to_the_unsharded_run(
        "fuzz.sbatch",
        &[("SEED", "5"), ("COUNT", "24")],
        &["fuzz-report.txt"],
    );
}

/// A sweep of the reference scene small enough for refusals: 32
/// configurations of 8x6 pixels, no RTL.
const TINY_SWEEP: [&str; 6] = ["sweep", "--size", "8x6", "--depths", "1", "--no-rtl"];

/// Writes the shard `k/n` of a tiny sweep (no RTL) with `extra` options
/// into `dir`, and returns its file.
fn sweep_shard(dir: &Path, k: u64, n: u64, extra: &[&str]) -> PathBuf {
    let shard = format!("{k}/{n}");
    let mut args = TINY_SWEEP.to_vec();
    args.extend(["--out", arg(dir), "--shard", &shard]);
    args.extend_from_slice(extra);
    ok(rtcosim(&args, &[]), &shard);
    dir.join(format!("sweep-{k}-of-{n}.shard.json"))
}

/// Runs merge on `args` and returns its stderr; it must fail with 2.
fn refused(args: &[&Path]) -> String {
    let out = Path::new("/nonexistent-merge-output");
    let mut v = vec!["merge"];
    v.extend(args.iter().map(|p| arg(p)));
    v.extend(["--out", arg(out)]);
    let run = rtcosim(&v, &[]);
    assert_eq!(run.status.code(), Some(2), "{}", both(&run));
    text(&run.stderr)
}

#[test]
fn merge_refuses_sets_that_are_not_one_run_naming_them() {
    let dir = scratch("shard", "refusals");
    let a = dir.join("a");
    let s0 = sweep_shard(&a, 0, 3, &[]);
    let s2 = sweep_shard(&a, 2, 3, &[]);
    // Missing: shard 1 of 3.
    let e = refused(&[&a]);
    assert!(e.contains("missing shard 1 of 3 (found 0, 2)"), "{e}");

    // Another configuration: its key is named, and both files.
    let b = dir.join("b");
    let other = sweep_shard(&b, 1, 3, &["--clock-mhz", "50"]);
    let e = refused(&[&a, &b]);
    assert!(
        e.contains(&format!(
            "{} and {} are shards of different runs",
            s0.display(),
            other.display()
        )) && e.contains("config.clock_mhz is 8.94 in the first, 50.0 in the second"),
        "{e}"
    );

    // A shard twice.
    let c = dir.join("c");
    std::fs::create_dir_all(&c).expect("mkdir");
    let copy = c.join("copy.shard.json");
    std::fs::copy(&s2, &copy).expect("copy");
    let e = refused(&[&a, &c]);
    assert!(
        e.contains(&format!(
            "shard 2/3 twice: {} and {}",
            s2.display(),
            copy.display()
        )),
        "{e}"
    );

    // A different split of the same run.
    let d = dir.join("d");
    let half = sweep_shard(&d, 1, 2, &[]);
    let e = refused(&[&s0, &half]);
    assert!(e.contains("split into 3 and into 2 shards"), "{e}");

    // A fuzz shard with a sweep shard.
    let f = dir.join("f");
    ok(
        rtcosim(
            &[
                "fuzz",
                "--count",
                "2",
                "--out",
                arg(&f),
                "--shard",
                "0/3",
                "--failures",
                arg(&dir.join("failures")),
            ],
            &[],
        ),
        "fuzz shard",
    );
    let e = refused(&[&s0, &f.join("fuzz-0-of-3.shard.json")]);
    assert!(
        e.contains("the first is a sweep shard, the second a fuzz shard"),
        "{e}"
    );

    // Damaged: an edited configuration, a truncated file, another JSON,
    // another format, items not the shard's.
    let text0 = std::fs::read_to_string(&s0).expect("shard file");
    let damaged = |name: &str, body: String| {
        let p = dir.join(name);
        std::fs::write(&p, body).expect("writable");
        p
    };
    let edited = damaged("edited.json", text0.replace("\"seed\":1", "\"seed\":2"));
    let e = refused(&[&edited]);
    assert!(
        e.contains(&format!(
            "{}: damaged: its configuration hashes to",
            edited.display()
        )),
        "{e}"
    );
    let cut = damaged("cut.json", text0[..text0.len() / 2].to_string());
    let e = refused(&[&cut]);
    assert!(
        e.contains(&format!("{}: not a shard file of rtcosim", cut.display())),
        "{e}"
    );
    let foreign = damaged("other.json", "{\"rows\": []}".into());
    let e = refused(&[&foreign]);
    assert!(
        e.contains("other.json: not a shard file of rtcosim: no \"format\" number"),
        "{e}"
    );
    let future = damaged("future.json", text0.replace("\"format\":1", "\"format\":9"));
    let e = refused(&[&future]);
    assert!(e.contains("format 9, this rtcosim reads format 1"), "{e}");
    // Its first item dropped.
    let at = text0.find("\"items\":[").expect("items") + "\"items\":[".len();
    let comma = at + text0[at..].find(',').expect("two items or more");
    let items = damaged(
        "items.json",
        format!("{}{}", &text0[..at], &text0[comma + 1..]),
    );
    let e = refused(&[&items]);
    assert!(e.contains("items.json: damaged: shard 0/3"), "{e}");

    // A row that is not its item's configuration (the result is not
    // hashed: the rows are checked against the work list).
    let swapped = damaged(
        "swapped.json",
        text0.replacen(
            "\"reference\",\"8\",\"6\",\"compact\",\"exact\"",
            "\"reference\",\"8\",\"6\",\"compact\",\"fast\"",
            1,
        ),
    );
    assert_ne!(std::fs::read_to_string(&swapped).expect("written"), text0);
    let set = [&swapped, &a.join("sweep-1-of-3.shard.json"), &s2];
    sweep_shard(&a, 1, 3, &[]);
    let e = refused(&set.map(|p| p.as_path()));
    assert!(
        e.contains("swapped.json: damaged: item")
            && e.contains("should be compact, depth 1, recip exact"),
        "{e}"
    );

    // A directory without shard files.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).expect("mkdir");
    let e = refused(&[&empty]);
    assert!(e.contains("no shard files (*.shard.json)"), "{e}");
}

/// Variables of an environment, name and value.
type Vars<'a> = &'a [(&'a str, &'a str)];

#[test]
fn bad_shards_are_refused_naming_the_flag_or_variable() {
    let dir = scratch("shard", "bad");
    let cases: [(&[&str], Vars, &str); 5] = [
        (
            &["--shard", "3/3"],
            &[],
            "--shard: shard 3 of 3: K counts from 0",
        ),
        (&["--shard", "1/0"], &[], "shard count 0"),
        (
            &[],
            &[("SLURM_ARRAY_TASK_ID", "1"), ("JOB_COMPLETION_INDEX", "1")],
            "both SLURM_ARRAY_TASK_ID=1 and JOB_COMPLETION_INDEX=1",
        ),
        (
            &[],
            &[("JOB_COMPLETION_INDEX", "0")],
            "--shard-count N or RTCOSIM_SHARD_COUNT",
        ),
        (
            &["--shard-count", "4"],
            &[],
            "JOB_COMPLETION_INDEX, and that is not set",
        ),
    ];
    for (extra, vars, message) in cases {
        let mut args = TINY_SWEEP.to_vec();
        args.extend(["--out", arg(&dir)]);
        args.extend_from_slice(extra);
        let vars: Vec<(&str, String)> = vars.iter().map(|(k, v)| (*k, v.to_string())).collect();
        let out = rtcosim(&args, &vars);
        let stderr = text(&out.stderr);
        assert_eq!(
            out.status.code(),
            Some(2),
            "{extra:?} {vars:?}: {}",
            both(&out)
        );
        assert!(stderr.contains(message), "{extra:?} {vars:?}: {stderr}");
    }
    // A fuzz shard needs somewhere to write its file.
    let out = rtcosim(&["fuzz", "--count", "2", "--shard", "0/2"], &[]);
    assert_eq!(out.status.code(), Some(2), "{}", both(&out));
    assert!(text(&out.stderr).contains("give --out"), "{}", both(&out));
}
