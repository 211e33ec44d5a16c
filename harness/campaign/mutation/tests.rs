//! The mutation module's unit tests.

use super::list::module_name;
use super::*;

#[test]
fn a_classification_reads_or_names_the_bad_line() {
    let ok = parse_classification(
        Files::of(ProcessorKind::Compact).survivors_path,
        "# c\n4 unreachable only when x | y\n9 hole a deeper scene\n",
    )
    .expect("reads");
    assert_eq!(ok[&4].class, Class::Unreachable);
    assert_eq!(ok[&4].reason, "only when x | y");
    assert!(ok[&4].class.is_equivalent() && !ok[&9].class.is_equivalent());
    for (bad, says) in [
        ("4 maybe why", "class \"maybe\""),
        ("x hole why", "mutant number"),
        ("4 hole", "not `ID CLASS reason`"),
        ("4 hole a\n4 open b", "classified twice"),
    ] {
        let e = parse_classification(Files::of(ProcessorKind::Fast).survivors_path, bad)
            .expect_err(bad)
            .to_string();
        assert!(
            e.starts_with(Files::of(ProcessorKind::Fast).survivors_path) && e.contains(says),
            "{bad}: {e}"
        );
    }
    for processor in ProcessorKind::ALL {
        List::committed(processor).expect("the committed list and classification read");
    }
}

#[test]
fn a_classification_of_another_list_is_refused() {
    // Its IDs would name other mutants: the survivors' file names the
    // list's RTL hash, or the list is refused with it.
    let files = Files::of(ProcessorKind::Compact);
    let hash = List::parse(files, files.list_text).expect("reads").rtl_hash;
    for (survivors, says) in [
        (
            "# rtl fnv1a64 0123456789abcdef\n".to_string(),
            "rtl fnv1a64 0123456789abcdef",
        ),
        ("# no hash\n".to_string(), "no `# rtl fnv1a64 HASH` line"),
    ] {
        let e = List::read(files, files.list_text, &survivors)
            .expect_err(&survivors)
            .to_string();
        assert!(
            e.starts_with(files.survivors_path) && e.contains(says) && e.contains(&hash),
            "{e}"
        );
    }
    List::read(files, files.list_text, &format!("# rtl fnv1a64 {hash}\n")).expect("its own");
}

#[test]
fn module_names_lose_their_parameters() {
    assert_eq!(module_name("$paramod$dc0217be\\fp_lzc"), "fp_lzc");
    assert_eq!(
        module_name("$paramod\\memory\\STACK_DEPTH=s32'00000000000000000000000000001000"),
        "memory"
    );
    assert_eq!(module_name("pp_ctrl"), "pp_ctrl");
}

#[test]
fn the_committed_lists_read_and_number_their_mutants_from_one() {
    for (processor, some_modules) in [
        (
            ProcessorKind::Compact,
            ["pp_ctrl", "alu", "memory", "fp_add", "fp_recip"],
        ),
        (
            ProcessorKind::Fast,
            [
                "fast_ctrl",
                "fast_alu",
                "fast_regfile",
                "fast_fp_add",
                "fast_fp_recip",
            ],
        ),
    ] {
        let list = List::committed(processor).unwrap();
        assert_eq!(list.files.processor, processor);
        assert!(list.mutants.len() >= 1000, "{} mutants", list.mutants.len());
        for (i, m) in list.mutants.iter().enumerate() {
            assert_eq!(usize::from(m.id), i + 1);
            assert!(m.command.starts_with("mutate -mode "));
            assert!(
                m.location.starts_with("rtl/") || m.location == "(no source line)",
                "{m:?}"
            );
        }
        let modules: std::collections::BTreeSet<&str> =
            list.mutants.iter().map(|m| m.module.as_str()).collect();
        for m in some_modules {
            assert!(
                modules.contains(m),
                "{processor}: no mutant of {m}: {modules:?}"
            );
        }
        // A float unit's mutant faces the unit checks, the
        // controller's does not.
        let of = |module: &str| {
            list.mutants
                .iter()
                .find(|m| m.module.ends_with(module))
                .unwrap()
                .id
        };
        let controller = std::path::Path::new(processor.row().controller)
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("a controller file");
        let (unit, ctrl) = (of("fp_add"), of(controller));
        assert!(list.in_float_unit(unit));
        assert!(!list.in_float_unit(ctrl));
    }
}

#[test]
fn a_list_out_of_order_or_without_its_hash_is_refused() {
    let head = "# rtl fnv1a64 0123\n";
    let line = "mutate -mode inv -module pp_ctrl -cell x -port Y -src rtl/pp/pp_ctrl.v:5.1-5.2";
    let ok = List::parse(
        Files::of(ProcessorKind::Compact),
        &format!("{head}1 {line}\n2 {line}\n"),
    )
    .unwrap();
    assert_eq!(ok.mutants[1].location, "rtl/pp/pp_ctrl.v:5");
    let e = List::parse(
        Files::of(ProcessorKind::Compact),
        &format!("{head}1 {line}\n3 {line}\n"),
    )
    .unwrap_err();
    assert_eq!(e.line, 3);
    assert!(e.message.contains("expected 2"), "{e}");
    assert!(List::parse(Files::of(ProcessorKind::Compact), &format!("1 {line}\n")).is_err());
    let e = List::parse(
        Files::of(ProcessorKind::Compact),
        &format!("{head}1 mutant -mode inv\n"),
    )
    .unwrap_err();
    assert!(e.message.contains("not a `mutate` command"), "{e}");
}

/// A corpus takes the directed scenes' place: its scenes are judged whole,
/// one equal to a builtin check is left out, the spec records the corpus'
/// hash (which any change of a file changes), and a folder without scene
/// files is refused by name.
#[test]
fn a_corpus_judge_replaces_the_directed_scenes() {
    use golden::scene::Scene;
    let spec = JudgeSpec {
        width: 16,
        height: 12,
        fuzz_seed: 1,
        fuzz_count: 0,
        unit_operands: 0,
        timeout_cycles: crate::design::DEFAULT_TIMEOUT_CYCLES,
        corpus: None,
    };
    let written = Judge::new(ProcessorKind::Compact, spec).expect("the judge");
    assert_eq!(
        written.directed,
        DIRECTED.len() + DIRECTED.iter().filter(|d| d.framed_as.is_some()).count()
    );
    let dir = std::env::temp_dir().join(format!("rtcosim-corpus-judge-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let refused = Corpus::load(&dir).expect_err("empty").to_string();
    assert!(refused.contains("no scene files"), "{refused}");
    let builtin = Scene::builtin("reference")
        .expect("builtin")
        .resized(16, 12, "t")
        .expect("16x12");
    let own = Scene::builtin("mirror")
        .expect("builtin")
        .resized(5, 3, "t")
        .expect("5x3");
    std::fs::write(dir.join("builtin-reference.toml"), builtin.to_toml()).expect("write");
    std::fs::write(dir.join("mine.toml"), own.to_toml()).expect("write");
    std::fs::write(dir.join("notes.txt"), "not a scene").expect("write");
    let corpus = Corpus::load(&dir).expect("loads");
    assert_eq!(corpus.files.len(), 2);
    let judge = Judge::with_corpus(ProcessorKind::Compact, spec, &corpus).expect("the judge");
    assert_eq!(judge.spec.corpus, Some(corpus.hash));
    assert_eq!(judge.directed, 1);
    let names: Vec<&str> = judge.checks.iter().map(|c| c.name.as_str()).collect();
    assert!(
        names.iter().any(|n| n.starts_with("corpus mine.toml")),
        "{names:?}"
    );
    assert!(
        !names.iter().any(|n| n.starts_with("directed ")),
        "{names:?}"
    );
    assert!(
        !names.iter().any(|n| n.starts_with("corpus builtin-")),
        "{names:?}"
    );
    assert_eq!(judge.scenes(), written.scenes() - written.directed + 1);
    std::fs::write(dir.join("mine.toml"), own.to_toml() + "\n").expect("write");
    assert_ne!(Corpus::load(&dir).expect("loads").hash, corpus.hash);
    let _ = std::fs::remove_dir_all(&dir);
}
