//! The command line as a user types it: what parses, into what, and what
//! is a usage error (exit 2).

use super::*;
use crate::args::{MethodArg, Size};
use crate::render::Model;
use clap::CommandFactory;
use golden::scene::Scene;
use golden::window::Window;
use rtcosim::design::processor::ProcessorKind;
use rtcosim::design::Fault;
use std::path::PathBuf;

#[test]
fn cli_definition_is_consistent() {
    Cli::command().debug_assert();
}

#[test]
fn a_typical_render_command_line_parses() {
    let cli = Cli::try_parse_from([
        "rtcosim",
        "render",
        "--model",
        "reference",
        "--scene",
        "mirror",
        "--size",
        "160x120",
        "--out",
        "/tmp/m.png",
        "--threads",
        "2",
    ])
    .expect("valid command line");
    let Command::Render(args) = cli.command else {
        panic!("expected the render subcommand, got {:?}", cli.command);
    };
    assert_eq!(args.model, Model::Reference);
    assert_eq!(args.scene.scene, "mirror");
    assert_eq!(
        args.scene.size,
        Some(Size {
            width: 160,
            height: 120
        })
    );
    assert_eq!(args.out, PathBuf::from("/tmp/m.png"));
    assert_eq!(args.threads.threads, Some(2));
}

#[test]
fn render_defaults_to_the_reference_scene_and_render_png() {
    let cli = Cli::try_parse_from(["rtcosim", "render"]).expect("valid command line");
    let Command::Render(args) = cli.command else {
        panic!("expected the render subcommand");
    };
    assert_eq!(args.model, Model::Reference);
    assert_eq!(args.scene.scene, "reference");
    assert_eq!(args.scene.size, None);
    assert_eq!(args.out, PathBuf::from("render.png"));
}

#[test]
fn bad_sizes_threads_and_unknown_models_are_usage_errors() {
    for size in [
        "0x10",
        "10x0",
        "100000x10",
        "800",
        "axb",
        "800x600x2",
        "-1x5",
    ] {
        let err = Cli::try_parse_from(["rtcosim", "render", "--size", size]).expect_err(size);
        assert_eq!(err.exit_code(), 2, "{size}");
    }
    let err = Cli::try_parse_from(["rtcosim", "render", "--model", "rtl-someday"])
        .expect_err("no such model");
    assert_eq!(err.exit_code(), 2);
    for sub in ["render", "cosim", "fp-check"] {
        let err = Cli::try_parse_from(["rtcosim", sub, "--threads", "0"]).expect_err("0 threads");
        assert_eq!(err.exit_code(), 2, "{sub}");
    }
    let cli = Cli::try_parse_from(["rtcosim", "render", "--model", "micro"])
        .expect("the micro-op model exists");
    let Command::Render(args) = cli.command else {
        panic!("expected the render subcommand");
    };
    assert_eq!(args.model, Model::Micro);
}

#[test]
fn a_trace_command_line_parses() {
    let cli = Cli::try_parse_from([
        "rtcosim",
        "render",
        "--model",
        "micro",
        "--trace",
        "/tmp/t.rtt",
        "--trace-window",
        "1,2,3,4",
    ])
    .expect("valid command line");
    let Command::Render(args) = cli.command else {
        panic!("expected the render subcommand");
    };
    assert_eq!(args.trace, Some(PathBuf::from("/tmp/t.rtt")));
    assert_eq!(args.trace_window, Some(Window::new(1, 2, 3, 3)));
    let cli = Cli::try_parse_from(["rtcosim", "trace-dump", "/tmp/t.rtt"]).expect("valid");
    assert!(matches!(cli.command, Command::TraceDump(_)));
}

#[test]
fn cosim_defaults_to_the_whole_reference_scene_with_its_methods() {
    let cli = Cli::try_parse_from(["rtcosim", "cosim"]).expect("valid command line");
    let Command::Cosim(args) = cli.command else {
        panic!("expected the cosim subcommand, got {:?}", cli.command);
    };
    assert_eq!(args.scene.scene, "reference");
    assert_eq!((args.scene.size, args.window), (None, None));
    assert_eq!((args.scene.recip, args.scene.sqrt), (None, None));
    // As --help says: 100,000 cycles for each of the processor's contexts.
    assert_eq!(args.timeout.timeout_cycles, None);
    assert_eq!(args.timeout.cycles(ProcessorKind::Compact), 100_000);
    assert_eq!(args.timeout.cycles(ProcessorKind::Fast), 3_200_000);
    assert_eq!((args.threads.threads, args.fault), (None, None));
}

#[test]
fn a_full_cosim_command_line_parses() {
    let cli = Cli::try_parse_from([
        "rtcosim",
        "cosim",
        "--scene",
        "box_room",
        "--size",
        "40x30",
        "--window",
        "1,2,30,20",
        "--recip",
        "fast",
        "--sqrt",
        "exact",
        "--threads",
        "1",
        "--timeout-cycles",
        "5000",
        "--fault",
        "PRI_HALF:0x400",
    ])
    .expect("valid command line");
    let Command::Cosim(args) = cli.command else {
        panic!("expected the cosim subcommand");
    };
    assert_eq!(args.window.map(|w| w.to_string()), Some("1,2,30,20".into()));
    assert_eq!(args.scene.recip, Some(MethodArg::Fast));
    assert_eq!(args.scene.sqrt, Some(MethodArg::Exact));
    assert_eq!(args.timeout.timeout_cycles, Some(5000));
    assert_eq!(args.timeout.cycles(ProcessorKind::Fast), 5000);
    assert_eq!(
        args.fault,
        Some(Fault {
            state: golden::micro::isa::state::PRI_HALF,
            xor: 0x400
        })
    );
    for bad in [
        &["--timeout-cycles", "0"][..],
        &["--recip", "slow"],
        &["--window", "5,5,4,6"],
        &["--fault", "PRI_HALF"],
    ] {
        let err = Cli::try_parse_from([&["rtcosim", "cosim"][..], bad].concat())
            .expect_err("a usage error");
        assert_eq!(err.exit_code(), 2, "{bad:?}");
    }
}

#[test]
fn faults_name_a_state_by_name_or_number_and_a_nonzero_mask() {
    use golden::micro::isa::{state, state_name};
    let half = Fault {
        state: state::PRI_HALF,
        xor: 0x400,
    };
    for spec in [
        "PRI_HALF:0x400".to_string(),
        "pri_half:1024".to_string(),
        "ISA_ST_PRI_HALF:0X400".to_string(),
        format!(" {} : 0x0400 ", state::PRI_HALF),
    ] {
        assert_eq!(spec.parse::<Fault>(), Ok(half), "{spec:?}");
    }
    let all: Fault = "PRI_ITOF:0xffffffff".parse().expect("every bit");
    assert_eq!(all.xor, u32::MAX);
    let unnamed = (0..=u16::MAX)
        .find(|&id| state_name(id).is_none())
        .expect("some id is no state");
    for (spec, message) in [
        ("PRI_HALF".to_string(), "expected STATE:XOR"),
        ("PRI_HALF:0".to_string(), "nonzero"),
        ("PRI_HALF:0x100000000".to_string(), "32-bit"),
        ("PRI_HALF:-1".to_string(), "\"-1\""),
        ("PRI_HALF:0x".to_string(), "\"0x\""),
        (
            "NO_SUCH_STATE:1".to_string(),
            "\"NO_SUCH_STATE\" is not a controller state",
        ),
        (format!("{unnamed}:1"), "is not a controller state"),
        ("70000:1".to_string(), "is not a controller state"),
    ] {
        let err = spec.parse::<Fault>().expect_err(&spec);
        assert!(err.contains(message), "{spec:?}: {err}");
    }
    // The refusal lists the states to choose from.
    let err = "NOPE:1".parse::<Fault>().expect_err("no such state");
    assert!(
        err.contains("PRI_HALF") && err.contains("PRI_ITOF"),
        "{err}"
    );
}

/// The shared groups are declared once: every command that takes a scene
/// takes the same flags, with the same help.
#[test]
fn every_scene_command_shares_one_scene_group_listing_every_builtin() {
    let cmd = Cli::command();
    for sub in ["render", "cosim", "diffmap"] {
        let sub = cmd.find_subcommand(sub).expect("subcommand");
        for flag in ["scene", "size", "recip", "sqrt", "threads"] {
            assert!(
                sub.get_arguments().any(|a| a.get_id() == flag),
                "{} lacks --{flag}",
                sub.get_name()
            );
        }
        let scene = sub
            .get_arguments()
            .find(|a| a.get_id() == "scene")
            .expect("--scene");
        let help = scene.get_help().expect("documented").to_string();
        for name in Scene::builtin_names() {
            assert!(help.contains(name), "--scene help lacks {name}: {help}");
        }
    }
}

#[test]
fn a_diffmap_command_line_with_per_side_methods_parses() {
    use crate::diffmap::{Renderer, Source};
    let cli = Cli::try_parse_from([
        "rtcosim",
        "diffmap",
        "rtl",
        "micro",
        "--a-recip",
        "fast",
        "--a-sqrt",
        "fast",
        "--b-sqrt",
        "exact",
        "--size",
        "16x12",
        "--thresholds",
        "1e-5,0.5,3",
        "--out",
        "/tmp/maps",
    ])
    .expect("valid command line");
    let Command::Diffmap(args) = cli.command else {
        panic!("expected the diffmap subcommand, got {:?}", cli.command);
    };
    assert_eq!(
        (args.a, args.b),
        (
            Source::Model(Renderer::Rtl),
            Source::Model(Renderer::Golden(Model::Micro))
        )
    );
    assert_eq!(
        (args.a_recip, args.a_sqrt),
        (Some(MethodArg::Fast), Some(MethodArg::Fast))
    );
    assert_eq!((args.b_recip, args.b_sqrt), (None, Some(MethodArg::Exact)));
    assert_eq!((args.scene.recip, args.scene.sqrt), (None, None));
    assert_eq!(args.thresholds, [0.00001, 0.5, 3.0]);
    assert_eq!(args.out, PathBuf::from("/tmp/maps"));
}

#[test]
fn diffmap_defaults_to_the_thesis_thresholds_and_takes_frame_files() {
    use crate::diffmap::{Renderer, Source};
    let cli = Cli::try_parse_from([
        "rtcosim",
        "diffmap",
        "run/rtl.exr",
        "reference",
        "--out",
        "d",
    ])
    .expect("valid command line");
    let Command::Diffmap(args) = cli.command else {
        panic!("expected the diffmap subcommand");
    };
    assert_eq!(args.a, Source::File(PathBuf::from("run/rtl.exr")));
    assert_eq!(args.b, Source::Model(Renderer::Golden(Model::Reference)));
    // The table near the thesis' figure 17.
    assert_eq!(args.thresholds, [0.00001, 0.0001, 0.5]);
    assert_eq!(args.scene.scene, "reference");
}

#[test]
fn diffmap_usage_errors_say_what_is_wrong() {
    for (bad, message) in [
        (&["mikro", "micro", "--out", "d"][..], "neither a model"),
        (&["micro", "reference"], "--out"),
        (
            &["micro", "reference", "--out", "d", "--thresholds=-1"],
            "threshold >= 0",
        ),
        (
            &["micro", "reference", "--out", "d", "--thresholds", "0.1,x"],
            "threshold >= 0",
        ),
        (
            &["micro", "reference", "--out", "d", "--thresholds", "inf"],
            "threshold >= 0",
        ),
        (
            &["micro", "reference", "--out", "d", "--a-recip", "slow"],
            "slow",
        ),
        (&["micro"], "<B>"),
        (
            &["micro", "reference", "--out", "d", "--block", "0"],
            "--block",
        ),
    ] {
        let err = Cli::try_parse_from([&["rtcosim", "diffmap"][..], bad].concat())
            .expect_err("a usage error");
        assert_eq!(err.exit_code(), 2, "{bad:?}");
        assert!(err.to_string().contains(message), "{bad:?}: {err}");
    }
}
