//! Mutation testing's machinery, in every `cargo test` (docs/mutation.md).
//!
//! The campaign itself (`rtcosim mutate`, cargo feature `mutation`) judges
//! 1,200 mutants on a Verilator build of their netlist; preparing that
//! design takes Yosys three minutes (the seed tables of fp_recip and
//! fp_sqrt). The smoke test here runs the same script on the smoke list,
//! rtl/mutate/smoke.mutants, listed with those two units as black boxes
//! (seconds of Yosys), and judges a handful of its mutants under Icarus:
//!
//! - the netlist with no mutant selected agrees with golden, bit and cycle;
//! - the mutants a bug would be are killed: some pixel differs from golden;
//! - a mutant Yosys proves equivalent agrees with golden, and Yosys does not
//!   prove the killed ones equivalent (the prover can say no).
//!
//! Needs yosys and iverilog: without them the test says loudly that it did
//! not run, and fails under RTCOSIM_REQUIRE_YOSYS=1 / RTCOSIM_REQUIRE_ICARUS=1
//! (CI sets both).

mod common;

use common::icarus::{
    compile_mutants, differences, icarus_present, pix_lines, scene_hex, vvp_run, work_dir,
    write_scene_hex, SimPixel,
};
use common::{reduced, tool_present};
use golden::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

const SCRIPT: &str = "rtl/mutate/mutants.sh";
const SMOKE_LIST: &str = "rtl/mutate/smoke.mutants";
/// The fast processor's list (`MUTATE_DESIGN=fast_pp`; no campaign yet).
const FAST_LIST: &str = "rtl/mutate/fast_pp.mutants";

/// Mutants of the smoke list a bug would be, and what they break:
/// each must make some pixel differ from golden.
const KILLED: &[(u16, &str)] = &[
    (
        138,
        "fp_add.v:60, a bit of the smaller operand's magnitude inverted",
    ),
    (
        123,
        "fp_mul.v:45, the product's sign taken as if a were negative",
    ),
    (
        140,
        "alu_ctrl.v:45, the register-file write enable flipped by a control bit",
    ),
    (37, "alu.v:290, a result bit forced to 0"),
    (127, "memory.v:87, a bit of a stack write inverted"),
    (
        112,
        "pp_ctrl.v:181, the diffuse term's written flag inverted",
    ),
];
/// A mutant Yosys proves equivalent: ctrl_flow.vh (nearest_hit_next, as
/// pp_ctrl.v:554 calls it), bit 8 of the jump's state id forced to 0 (every
/// state id is below 128).
const EQUIVALENT: u16 = 46;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// `rtl/mutate/mutants.sh ARGS` on `list` for `design` (MUTATE_DESIGN),
/// its cache under cargo's temporary directory.
fn run_script(design: &str, list: &str, args: &[&str]) -> std::process::Output {
    Command::new("bash")
        .arg(root().join(SCRIPT))
        .args(args)
        .env("MUTATE_DESIGN", design)
        .env("MUTATE_LIST", root().join(list))
        .env(
            "MUTATE_CACHE",
            Path::new(env!("CARGO_TARGET_TMPDIR")).join("mutate"),
        )
        .output()
        .unwrap_or_else(|e| panic!("running {SCRIPT}: {e}"))
}

/// [`run_script`] on the compact processor: stdout, or the failure with
/// stderr.
fn script(list: &str, args: &[&str]) -> String {
    let out = run_script("pixel_processor", list, args);
    assert!(
        out.status.success(),
        "{SCRIPT} {}:\n{}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The `# rtl fnv1a64 H` line of a list.
fn listed_hash(list: &str) -> String {
    let text = std::fs::read_to_string(root().join(list)).expect("reading the list");
    text.lines()
        .find_map(|l| l.strip_prefix("# rtl fnv1a64 "))
        .unwrap_or_else(|| panic!("{list}: no '# rtl fnv1a64' line"))
        .to_string()
}

/// The fast campaign's finished shards (`rtl/mutate/campaign/fast_pp/`,
/// docs/mutation.md "What stands") judged today's fast list, each under
/// the name `rtcosim merge` gives its shard: a shard of another list
/// would merge verdicts on other mutants.
#[test]
fn the_committed_fast_shards_judged_todays_list() {
    let dir = root().join("rtl/mutate/campaign/fast_pp");
    let listed = listed_hash(FAST_LIST);
    let mut shards = 0;
    for entry in std::fs::read_dir(&dir).expect("rtl/mutate/campaign/fast_pp") {
        let path = entry.expect("an entry").path();
        let text = std::fs::read_to_string(&path).expect("reading a shard");
        let v: serde_json::Value = serde_json::from_str(&text).expect("a shard's JSON");
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        assert_eq!(v["tool"], "mutate", "{name}");
        assert_eq!(v["config"]["processor"], "fast", "{name}");
        assert_eq!(
            v["config"]["rtl_hash"], listed,
            "{name} judged another list than {FAST_LIST}: judge that shard again"
        );
        let shard = &v["shard"];
        assert_eq!(
            name,
            format!("mutate-{}-of-{}.shard.json", shard["index"], shard["count"]),
        );
        shards += 1;
    }
    assert!(shards > 0, "no shard in {}", dir.display());
}

/// The lists listed on the compact processor's sources: its own and the
/// smoke test's.
fn compact_lists() -> [&'static str; 2] {
    [
        rtcosim::design::processor::ProcessorKind::Compact
            .row()
            .mutants
            .list_path,
        SMOKE_LIST,
    ]
}

#[test]
fn the_mutant_lists_were_listed_on_todays_rtl() {
    let today = script(SMOKE_LIST, &["hash"]).trim().to_string();
    assert_eq!(today.len(), 16, "{SCRIPT} hash: {today:?}");
    for list in compact_lists() {
        assert_eq!(
            listed_hash(list),
            today,
            "{list} was listed on other RTL: run `{SCRIPT} list` (see docs/mutation.md)"
        );
    }
    // The smoke list names the black boxes it was listed with.
    let smoke = std::fs::read_to_string(root().join(SMOKE_LIST)).expect("reading");
    assert!(smoke
        .lines()
        .any(|l| l == "# black boxes: fp_recip fp_sqrt"));
    // The fast processor's list, on its own sources (rtl/fast too): the
    // hash of MUTATE_DESIGN=fast_pp, another than the compact one's.
    let out = run_script("fast_pp", FAST_LIST, &["hash"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let fast_today = String::from_utf8_lossy(&out.stdout).trim().to_string();
    assert_ne!(fast_today, today);
    assert_eq!(
        listed_hash(FAST_LIST),
        fast_today,
        "{FAST_LIST} was listed on other RTL: run `MUTATE_DESIGN=fast_pp {SCRIPT} list 1200 1` (see docs/mutation.md)"
    );
    // No list holds a mutation that `mutants.sh netlist` cannot write (a
    // memory's clock, read-enable or read-reset port: write_verilog asserts
    // on it, and the mutation build fails on the whole list).
    for list in compact_lists().into_iter().chain([FAST_LIST]) {
        let text = std::fs::read_to_string(root().join(list)).expect("reading");
        for (n, line) in text.lines().enumerate() {
            for port in ["RD_ARST", "RD_SRST", "RD_CLK", "RD_EN", "WR_CLK"] {
                assert!(
                    line.starts_with('#') || !line.contains(&format!(" -port {port} ")),
                    "{list}:{}: a mutation of a memory's {port} port, which the netlist cannot hold: run `{SCRIPT} list`",
                    n + 1
                );
            }
        }
    }
    // A design the script does not know is refused by name.
    let out = run_script("top", FAST_LIST, &["hash"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("MUTATE_DESIGN 'top' is neither pixel_processor nor fast_pp"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Runs `pixels` of `scene` on mutant `id` of the compiled netlist.
fn run_mutant(
    vvp: &Path,
    dir: &Path,
    scene_file: &Path,
    n_writes: usize,
    pixels: &[(u32, u32)],
    id: u16,
) -> Vec<SimPixel> {
    let stdout = vvp_run(
        vvp,
        scene_file,
        n_writes,
        &dir.join(format!("pixels-{id}.hex")),
        pixels,
        &[&format!("+mutsel={id}")],
    );
    let lines = pix_lines(&stdout);
    // A mutant may hang a pixel: the testbench then prints HUNG and stops.
    lines.into_iter().map(|(p, _)| p).collect()
}

#[test]
fn smoke_mutants_are_killed_or_proved_equivalent() {
    let test = "smoke_mutants_are_killed_or_proved_equivalent";
    if !tool_present(test, "yosys", "-V", "RTCOSIM_REQUIRE_YOSYS", "yosys") || !icarus_present(test)
    {
        return;
    }
    let dir = work_dir("mutation_smoke");
    let netlist: PathBuf = dir.join("smoke.v");
    let mut ids: Vec<String> = KILLED.iter().map(|(id, _)| id.to_string()).collect();
    ids.push(EQUIVALENT.to_string());
    let mut args = vec!["netlist", common::arg(&netlist)];
    args.extend(ids.iter().map(String::as_str));
    script(SMOKE_LIST, &args);
    let vvp = compile_mutants(&dir, &netlist);

    let scene: Scene = reduced("reference");
    let pixels: Vec<(u32, u32)> = (0..scene.camera.height)
        .step_by(7)
        .flat_map(|y| (0..scene.camera.width).step_by(9).map(move |x| (x, y)))
        .collect();
    let scene_file = write_scene_hex(&dir, &scene);
    let n_writes = scene_hex(&scene).1;
    let judge = |id: u16| {
        let got = run_mutant(&vvp, &dir, &scene_file, n_writes, &pixels, id);
        let mut diff = differences(&scene, &got);
        if got.len() < pixels.len() {
            diff.push(format!(
                "{} of {} pixels came back (hung)",
                got.len(),
                pixels.len()
            ));
        }
        diff
    };

    let baseline = judge(0);
    assert!(
        baseline.is_empty(),
        "no mutant selected, yet:\n{}",
        baseline.join("\n")
    );
    for (id, what) in KILLED {
        assert!(
            !judge(*id).is_empty(),
            "mutant {id} ({what}) survived the smoke judge"
        );
    }
    let same = judge(EQUIVALENT);
    assert!(
        same.is_empty(),
        "mutant {EQUIVALENT} is to be equivalent, yet:\n{}",
        same.join("\n")
    );

    // The prover on the equivalent mutant and on the first killed one (a
    // small module: seconds).
    let (killed, _) = KILLED[0];
    let verdicts = script(
        SMOKE_LIST,
        &["equiv", &EQUIVALENT.to_string(), &killed.to_string()],
    );
    let verdict = |id: u16| {
        verdicts
            .lines()
            .find_map(|l| l.strip_prefix(&format!("{id} ")))
            .unwrap_or_else(|| panic!("no verdict for mutant {id} in:\n{verdicts}"))
            .to_string()
    };
    assert_eq!(verdict(EQUIVALENT), "equivalent", "{verdicts}");
    assert_eq!(verdict(killed), "not-proved", "{verdicts}");
}

#[test]
fn mutate_refuses_bad_mutant_lists() {
    for (bad, says) in [
        ("0", "expected mutant numbers"),
        ("5-3", "expected mutant numbers"),
        ("1-x", "expected mutant numbers"),
        ("70000", "expected mutant numbers"),
    ] {
        common::assert_refused(&["mutate", "--mutants", bad], &["--mutants", says]);
    }
}

#[cfg(not(feature = "mutation"))]
#[test]
fn mutate_without_the_netlist_says_how_to_build_it() {
    let out = common::rtcosim(&["mutate", "--mutants", "1"]);
    let stderr = common::text(&out.stderr);
    assert!(!out.status.success(), "{}", common::both(&out));
    assert!(
        stderr.contains("--features mutation") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

/// A campaign through the binary, judged whole (`judge` and `--out
/// DIR/whole`) and in two shards merged (`DIR/merged`): asserts the whole
/// run's header and that the merged verdicts are the whole run's; returns
/// the whole run's stdout and its `mutation.json`.
#[cfg(feature = "mutation")]
fn whole_and_merged(dir: &Path, judge: &[&str]) -> (String, serde_json::Value) {
    use common::{arg, both, rtcosim, text};
    let json = |dir: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join("mutation.json")).expect("json"))
            .expect("JSON")
    };
    let verdicts = |v: &serde_json::Value| -> Vec<(u64, String)> {
        v["outcomes"]
            .as_array()
            .expect("outcomes")
            .iter()
            .map(|o| (o["id"].as_u64().expect("id"), o["verdict"].to_string()))
            .collect()
    };
    let whole = dir.join("whole");
    let mut args = judge.to_vec();
    args.extend(["--out", arg(&whole)]);
    let out = rtcosim(&args);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("the netlist with no mutant selected passes the judge"),
        "{}",
        both(&out)
    );
    let got = json(&whole);
    // Exit 0 only when every mutant was killed or proved equivalent.
    assert_eq!(
        out.status.success(),
        verdicts(&got).iter().all(|v| v.1.contains("killed")),
        "{}",
        both(&out)
    );
    let shards = dir.join("shards");
    for k in ["0/2", "1/2"] {
        let mut args = judge.to_vec();
        args.extend(["--shard", k, "--out", arg(&shards)]);
        let out = rtcosim(&args);
        assert!(text(&out.stdout).contains("wrote"), "{}", both(&out));
    }
    let merged = dir.join("merged");
    let out = rtcosim(&["merge", arg(&shards), "--out", arg(&merged)]);
    assert!(merged.join("mutation-report.md").exists(), "{}", both(&out));
    assert_eq!(verdicts(&json(&merged)), verdicts(&got), "{}", both(&out));
    (stdout, got)
}

/// A campaign's `mutation.json`: its mutants' ids, and how many it killed.
#[cfg(feature = "mutation")]
fn killed_ids(json: &serde_json::Value) -> (Vec<u64>, usize) {
    let outcomes = json["outcomes"].as_array().expect("outcomes");
    let ids = outcomes
        .iter()
        .map(|o| o["id"].as_u64().expect("id"))
        .collect();
    let killed = outcomes.iter().filter(|o| o["verdict"] == "killed").count();
    (ids, killed)
}

/// The campaign through the binary (cargo feature `mutation`): a few
/// mutants judged whole and in two shards merged give the same verdicts.
#[cfg(feature = "mutation")]
#[test]
fn mutate_judges_and_its_shards_merge_to_the_same_verdicts() {
    let dir = common::scratch("mutation", "campaign");
    let judge = ["mutate", "--mutants", "1-6", "--size", "8x6", "--fuzz", "2"];
    let (_, got) = whole_and_merged(&dir, &judge);
    let (ids, killed) = killed_ids(&got);
    assert_eq!(ids, (1..=6).collect::<Vec<_>>());
    assert!(killed >= 1, "{got}");
    common::assert_refused(
        &["mutate", "--mutants", "60000"],
        &["there is no mutant 60000"],
    );
}

/// The fast processor's mutants (cargo feature `mutation`): judged on its
/// own netlist (rtl/mutate/fast_pp.mutants behind `mutsel`, driven as a top
/// of its contexts), and its shards merge through the fast list: the design
/// passes, mutants of its modules are killed and named by them.
#[cfg(feature = "mutation")]
#[test]
fn the_fast_processors_mutants_are_judged_and_their_shards_merge() {
    let dir = common::scratch("mutation", "fast");
    let judge = [
        "mutate",
        "--processor",
        "fast",
        "--mutants",
        "1-4",
        "--size",
        "8x6",
        "--fuzz",
        "1",
    ];
    let (stdout, got) = whole_and_merged(&dir, &judge);
    assert!(
        stdout.contains("rtl/mutate/fast_pp.mutants") && stdout.contains("fast checks"),
        "{stdout}"
    );
    let (ids, killed) = killed_ids(&got);
    assert_eq!(ids, (1..=4).collect::<Vec<_>>());
    assert!(killed >= 1, "{got}");
    // Mutant 4 (fast_fp_mul.v:90, a product bit forced to 1) dies in the
    // unit stage: the pipelined multiplier cut from the same netlist.
    let four = &got["outcomes"][3];
    assert_eq!(four["check"], "fast_fp_mul edge cases", "{four}");
    assert!(
        !dir.join("whole").join("mutate.journal.jsonl").exists(),
        "the journal is removed once the results are written"
    );
    // The whole run and the merge read the fast processor's list and
    // classification.
    for report in [dir.join("whole"), dir.join("merged")]
        .map(|d| std::fs::read_to_string(d.join("mutation-report.md")).expect("report"))
    {
        assert!(
            report.contains("rtl/mutate/fast_pp.survivors")
                && report.contains("| fast_")
                && !report.contains("| pp_ctrl"),
            "{report}"
        );
    }
    common::assert_refused(
        &["mutate", "--processor", "fast", "--mutants", "1201"],
        &["there is no mutant 1201", "rtl/mutate/fast_pp.mutants"],
    );
}

/// A campaign with --out journals each verdict and, run again after a
/// kill, resumes from the journal (cargo feature `mutation`): a verdict
/// planted in the journal of the same campaign is taken as judged, not
/// judged again; a journal of another campaign is refused.
#[cfg(feature = "mutation")]
#[test]
fn a_killed_campaign_resumes_from_its_journal() {
    use common::{arg, both, rtcosim, text};
    use rtcosim::campaign::mutation::{Campaign, JudgeSpec, List, Outcome, Verdict};
    use rtcosim::campaign::shard::file::run_config;
    use rtcosim::campaign::shard::journal::Journal;
    use rtcosim::design::processor::ProcessorKind;
    let dir = common::scratch("mutation", "resume");
    let list = List::committed(ProcessorKind::Compact).expect("the list");
    // The campaign `mutate --mutants 1-2 --size 8x6 --fuzz 0` runs (its
    // defaults as tools/mutate.rs has them).
    let campaign = |fuzz_count| Campaign {
        processor: ProcessorKind::Compact,
        judge: JudgeSpec {
            width: 8,
            height: 6,
            fuzz_seed: 1,
            fuzz_count,
            unit_operands: 10_000,
            timeout_cycles: rtcosim::design::DEFAULT_TIMEOUT_CYCLES,
            corpus: None,
            corpus: None,
        },
        mutants: vec![1, 2],
        rtl_hash: list.rtl_hash.clone(),
        verilator: rtcosim::VERILATOR_VERSION.into(),
    };
    let (journal, resumed) =
        Journal::open::<Outcome>(&dir, "mutate", &run_config(&campaign(0)), None).expect("journal");
    assert!(!resumed.found);
    journal.record(&Outcome {
        id: 2,
        verdict: Verdict::Killed {
            check: "planted by the test".into(),
            how: "never judged".into(),
        },
        pixels: 0,
        seconds: 0.0,
    });
    drop(journal);
    let args = [
        "mutate",
        "--mutants",
        "1-2",
        "--size",
        "8x6",
        "--fuzz",
        "0",
        "--out",
        arg(&dir),
    ];
    let out = rtcosim(&args);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("resuming: 1 of the 2 mutants judged before")
            && stdout.contains("planted by the test: 1")
            && stdout.contains("mutants: 2 judged"),
        "{}",
        both(&out)
    );
    assert!(!dir.join("mutate.journal.jsonl").exists());
    // Another campaign's journal in the directory: refused by name.
    let (journal, _) =
        Journal::open::<Outcome>(&dir, "mutate", &run_config(&campaign(3)), None).expect("journal");
    drop(journal);
    common::assert_refused(
        &args,
        &[
            "mutate.journal.jsonl",
            "the journal of another run",
            "delete it",
        ],
    );
}

/// The judge's float-unit stage (cargo feature `mutation`): mutant 1
/// (fp_lzc.v:33, a select bit of the count forced to 0; it survived every
/// scene of the judge before the stage existed) is killed by a float unit's
/// edge cases, cut from the same netlist, with the operand that tells it
/// from golden.
#[cfg(feature = "mutation")]
#[test]
fn the_float_unit_stage_kills_a_mutant_every_scene_misses() {
    use common::{both, rtcosim, text};
    let out = rtcosim(&["mutate", "--mutants", "1", "--size", "8x6", "--fuzz", "0"]);
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("mutants: 1 judged, 1 killed"),
        "{}",
        both(&out)
    );
    assert!(
        stdout.contains(" edge cases: 1"),
        "not killed by a unit's edge cases:\n{}",
        both(&out)
    );
}

/// The judge's reset check (cargo feature `mutation`): mutant 626
/// (pp_core.v:28, the ALU's rst_n tied high) survives every scene, whose
/// runs reset the processor only between pixels with the ALU idle, and is
/// killed by a reset in the middle of a pixel; the design passes it.
#[cfg(feature = "mutation")]
#[test]
fn a_reset_mid_pixel_kills_an_alu_that_never_resets() {
    use rtcosim::campaign::mutation::{judge, Judge, JudgeSpec, Stimulus, Verdict};
    use rtcosim::design::processor::ProcessorKind;
    let spec = JudgeSpec {
        width: 8,
        height: 6,
        fuzz_seed: 1,
        fuzz_count: 0,
        unit_operands: 0,
        timeout_cycles: rtcosim::design::DEFAULT_TIMEOUT_CYCLES,
    };
    let full = Judge::new(ProcessorKind::Compact, spec).expect("the judge");
    let resets = |j: &Judge| {
        j.checks
            .iter()
            .filter(|c| matches!(c.stimulus, Stimulus::ResetMidPixel { .. }))
            .count()
    };
    assert_eq!(resets(&full), 1);
    let mut scenes_only = full.clone();
    scenes_only
        .checks
        .retain(|c| !matches!(c.stimulus, Stimulus::ResetMidPixel { .. }));
    let verdict = |id, j: &Judge| judge(id, false, j).expect("judged").verdict;
    assert_eq!(
        verdict(0, &full),
        Verdict::Survived,
        "the design fails the reset check"
    );
    assert_eq!(verdict(626, &scenes_only), Verdict::Survived);
    match verdict(626, &full) {
        Verdict::Killed { check, .. } => assert!(check.starts_with("reset mid-pixel"), "{check}"),
        Verdict::Survived => panic!("mutant 626 survived a reset mid-pixel"),
    }
}

/// Only the exact methods are cut from the mutant netlist: asking for
/// another unit is a clear error, not a crash.
#[cfg(feature = "mutation")]
#[test]
fn a_unit_the_mutant_netlist_lacks_is_a_clear_error() {
    use golden::fp::Method;
    use rtcosim::design::fp_unit::{FpUnit, UnitKind};
    use rtcosim::design::processor::ProcessorKind;
    for kind in [
        UnitKind::Recip(Method::Fast),
        UnitKind::FastSqrt(Method::Fast),
    ] {
        let err = FpUnit::new_mutant(kind, 1)
            .err()
            .unwrap_or_else(|| panic!("{kind} is not in a mutant netlist"));
        assert!(err.to_string().contains("exact methods only"), "{err}");
    }
    let processors = [ProcessorKind::Compact, ProcessorKind::Fast];
    for kind in processors
        .into_iter()
        .flat_map(rtcosim::campaign::mutation::units)
    {
        let mut unit = FpUnit::new_mutant(kind, 0).expect("a unit of the netlist");
        let (a, b) = (vec![0x3F80_0000u32], vec![0x4000_0000u32]);
        let (y, _) = unit
            .eval(&a, if kind.is_binary() { &b } else { &[] })
            .expect("eval");
        assert_eq!(
            y[0],
            kind.golden(a[0], b[0]),
            "{kind} of 1.0 with no mutant"
        );
    }
}

/// A multi-cycle unit must hold y while it computes the next result: the
/// four mutants of the units' hold paths (fp_recip 150, fp_sqrt 217 and
/// 564, fp_exp 817; docs/mutation.md), whose results are right when
/// out_valid rises but whose y moves in between, are caught by the units'
/// driver, naming the edge, and unmutated (mutsel 0) the same units pass.
#[cfg(feature = "mutation")]
#[test]
fn a_unit_whose_y_does_not_hold_between_results_is_caught() {
    use golden::fp::Method;
    use rtcosim::design::fp_unit::{FpUnit, UnitKind};
    let (a, _) = rtcosim::check::operands::random_chunk(UnitKind::Exp, 7, 0, 200);
    // fp_exp's working range is x <= 0 (exposure * colour).
    let negative: Vec<u32> = a.iter().map(|x| x | 0x8000_0000).collect();
    for (id, kind, a) in [
        (150, UnitKind::Recip(Method::Exact), &a),
        (217, UnitKind::Sqrt(Method::Exact), &a),
        (564, UnitKind::Sqrt(Method::Exact), &a),
        (817, UnitKind::Exp, &negative),
    ] {
        let clean = FpUnit::new_mutant(kind, 0).expect("the unit").eval(a, &[]);
        assert!(clean.is_ok(), "{kind} unmutated: {clean:?}");
        let err = FpUnit::new_mutant(kind, id)
            .expect("the unit")
            .eval(a, &[])
            .err()
            .unwrap_or_else(|| panic!("mutant {id} of {kind} passed"))
            .to_string();
        assert!(
            err.contains("while out_valid was low"),
            "mutant {id}: {err}"
        );
    }
}

/// Each hard operand of `MUTANT_KILLERS` (found by exhaustive simulation,
/// examples/mutant_exhaustive.rs, or by `mutants.sh miter`'s
/// counterexample; docs/mutation.md) is an edge case of its unit, and
/// tells its mutant of today's list from golden while the unmutated unit
/// agrees.
#[cfg(feature = "mutation")]
#[test]
fn the_hard_operands_kill_their_mutants() {
    use rtcosim::check::operands::{edge_cases, MUTANT_KILLERS};
    use rtcosim::design::fp_unit::FpUnit;
    assert!(!MUTANT_KILLERS.is_empty());
    for killer in MUTANT_KILLERS {
        let (kind, a, b, id) = (killer.unit, killer.a, killer.b, killer.mutant);
        let (edges_a, edges_b) = edge_cases(kind);
        let is_edge =
            (0..edges_a.len()).any(|i| edges_a[i] == a && (!kind.is_binary() || edges_b[i] == b));
        assert!(
            is_edge,
            "({a:#010x}, {b:#010x}) (mutant {id}) is not an edge case of {kind}"
        );
        let want = kind.golden(a, b);
        let y = |id| {
            let bs = [b];
            FpUnit::new_mutant(kind, id)
                .expect("the unit")
                .eval(&[a], if kind.is_binary() { &bs } else { &[] })
                .expect("eval")
                .0[0]
        };
        assert_eq!(y(0), want, "{kind} unmutated on {a:#010x}, {b:#010x}");
        assert_ne!(
            y(id),
            want,
            "mutant {id} of {kind} agrees with golden on {a:#010x}, {b:#010x}"
        );
    }
}

/// Every scene of both processors' judges (builtins at the judge's size,
/// the directed scenes as written and framed, fuzz scenes, and the fast
/// processor's reference with its results stalled) agrees with
/// golden on the processors as written, in every `cargo test`: a directed
/// scene kills mutants only if the design passes it (the campaign's
/// baseline checks this too, but only in a build with the mutant netlist).
/// straight_up (survivor 797) is here with the infinities it was written
/// for: golden's trace of its pixel ends at BOX_BEHIND with S = (NaN, -inf,
/// +inf).
#[test]
fn the_judges_scenes_agree_with_golden_on_both_processors() {
    use golden::fp::Method;
    use rtcosim::campaign::mutation::{Judge, JudgeSpec, Stimulus};
    use rtcosim::check::cosim::{self, CosimOptions};
    use rtcosim::design::processor::ProcessorKind;
    use rtcosim::design::top::Stall;
    use rtcosim::design::Design;
    for processor in ProcessorKind::ALL {
        // The defaults: glass_shortcut's and glass_corridor's deepest
        // pixels take more than 100,000 cycles on the fast processor, whose
        // 32 contexts share its pipeline, and less than its default.
        let spec = JudgeSpec {
            width: 16,
            height: 12,
            fuzz_seed: 1,
            fuzz_count: 4,
            unit_operands: 0,
            timeout_cycles: processor.row().default_timeout_cycles(),
            corpus: None,
        };
        let options = CosimOptions::default();
        let mut dut = Design::new(processor, Method::Exact, Method::Exact)
            .open()
            .expect("the processor");
        let judge = Judge::new(processor, spec).expect("the judge");
        let mut checked = 0;
        for check in &judge.checks {
            let (scene, window, stall) = match &check.stimulus {
                Stimulus::Scene { scene, window } => (scene, window, Stall::NONE),
                Stimulus::Stalled {
                    scene,
                    window,
                    stall,
                } => (scene, window, *stall),
                _ => continue,
            };
            let options = CosimOptions { stall, ..options };
            let report = cosim::run_on(&mut dut, scene, *window, &options, &mut |_| {})
                .unwrap_or_else(|e| panic!("{processor}: {}: {e}", check.name));
            assert!(report.passed(), "{processor}: {} diverges", check.name);
            assert_eq!(
                report.compare.counts.pixels,
                window.pixels(),
                "{}",
                check.name
            );
            checked += 1;
        }
        let stalled = usize::from(processor == ProcessorKind::Fast);
        assert_eq!(checked, judge.scenes() + stalled, "{processor}");
        assert!(
            judge
                .checks
                .iter()
                .any(|c| c.name.starts_with("directed straight_up")),
            "{processor}"
        );
    }
}
