//! Every `rtcosim` command line the README and docs/*.md show must parse
//! with the CLI defined here, so a renamed option or subcommand fails this
//! test instead of a reader's copy and paste. (At the end: the source lines
//! the documents quote in pasted output must still be those states' lines.)
//!
//! What counts as a command line:
//! - in code (fenced blocks, indented blocks): every shell command that runs
//!   `cargo run --release -- ...`, `rtcosim ...`, `[./]target/release/rtcosim
//!   ...` or `[./]target/release/trace-diff ...` (the same arguments as
//!   `rtcosim trace-diff`), after joining `\` continuations, dropping
//!   comments, splitting at `;`, `&&`, `||`, `|` and redirections, and
//!   unrolling `for V in ...; do ...; done`; in a transcript (a block with `$ `
//!   lines) only the `$ ` lines;
//! - in prose: every inline code span that starts the same way.
//!
//! A command with a placeholder for a value (`FILE`, `WxH`, `K/N`,
//! `max|mean`, an unexpanded `$VAR`; `[...]` marks an optional part) is a
//! synopsis: its subcommand must exist and each `--option` in it must be
//! one of the subcommand's. A span that is only `rtcosim SUBCOMMAND` names
//! the subcommand, which must exist. Any other command is parsed in full
//! with `Cli::try_parse_from` (`--help` counts as parsing).

use super::Cli;
use clap::{CommandFactory, Parser};
use std::path::{Path, PathBuf};

/// One command line found in a document.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Found {
    /// `file:line` of its first line.
    at: String,
    /// The arguments after the program name.
    args: Vec<String>,
}

/// Splits a shell line into words: quotes group and are removed; the
/// operators `;`, `|`, `||`, `&&` are words of their own.
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quote = None;
    let mut chars = line.chars().peekable();
    let flush = |word: &mut String, out: &mut Vec<String>| {
        if !word.is_empty() {
            out.push(std::mem::take(word));
        }
    };
    while let Some(c) = chars.next() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => word.push(c),
            (None, '\'' | '"') => quote = Some(c),
            (None, c) if c.is_whitespace() => flush(&mut word, &mut out),
            (None, '#') if word.is_empty() => break,
            (None, ';' | '|' | '&') => {
                flush(&mut word, &mut out);
                let mut op = c.to_string();
                if chars.peek() == Some(&c) {
                    op.push(chars.next().expect("peeked"));
                }
                out.push(op);
            }
            (None, c) => word.push(c),
        }
    }
    flush(&mut word, &mut out);
    out
}

fn is_operator(w: &str) -> bool {
    matches!(w, ";" | "|" | "||" | "&&" | "&")
}

/// A shell script's simple commands, each with the index of the line it
/// starts on, `\` continuations joined and `for` loops unrolled.
fn commands(lines: &[(usize, &str)]) -> Vec<(usize, Vec<String>)> {
    let mut simple: Vec<(usize, Vec<String>)> = Vec::new();
    let mut logical: Option<(usize, String)> = None;
    for &(at, line) in lines {
        let (start, mut text) = logical.take().unwrap_or((at, String::new()));
        text.push_str(line);
        if let Some(open) = text.strip_suffix('\\') {
            logical = Some((start, open.to_string() + " "));
            continue;
        }
        let mut current = Vec::new();
        for w in words(&text) {
            if is_operator(&w) {
                simple.push((start, std::mem::take(&mut current)));
            } else {
                current.push(w);
            }
        }
        simple.push((start, current));
    }
    simple.retain(|c| !c.1.is_empty());
    let mut out = Vec::new();
    let mut i = 0;
    while i < simple.len() {
        let c = &simple[i].1;
        if c[0] == "for" && c.len() >= 3 && c[2] == "in" {
            let (var, values) = (&c[1], &c[3..]);
            let mut body = Vec::new();
            i += 1;
            while i < simple.len() && simple[i].1[0] != "done" {
                let (at, b) = &simple[i];
                let b = if b[0] == "do" { &b[1..] } else { &b[..] };
                if !b.is_empty() {
                    body.push((*at, b));
                }
                i += 1;
            }
            for v in values {
                let set = |w: &String| {
                    w.replace(&format!("${{{var}}}"), v)
                        .replace(&format!("${var}"), v)
                };
                out.extend(
                    body.iter()
                        .map(|(at, b)| (*at, b.iter().map(set).collect())),
                );
            }
        } else {
            out.push(simple[i].clone());
        }
        i += 1;
    }
    out
}

/// The rtcosim arguments of a simple command, if it runs rtcosim: after
/// `VAR=value` words and a `time` wrapper, up to a redirection.
fn rtcosim_args(command: &[String]) -> Option<Vec<String>> {
    let mut w = command;
    while w
        .first()
        .is_some_and(|x| x.contains('=') && !x.starts_with('-'))
    {
        w = &w[1..];
    }
    if w.first()
        .is_some_and(|x| x == "time" || x.ends_with("/time"))
    {
        w = &w[1..];
        while let Some(flag) = w.first().filter(|x| x.starts_with('-')) {
            w = &w[if flag == "-f" || flag == "-o" { 2 } else { 1 }.min(w.len())..];
        }
    }
    let first = w.first()?.trim_start_matches("./");
    let (prefix, skip) = if w.len() >= 4 && w[..4] == ["cargo", "run", "--release", "--"] {
        (None, 4)
    } else if first == "rtcosim" || first == "target/release/rtcosim" {
        (None, 1)
    } else if first == "target/release/trace-diff" {
        (Some("trace-diff"), 1)
    } else {
        return None;
    };
    let rest = w[skip..]
        .iter()
        .take_while(|x| !x.starts_with('>') && !x.starts_with('<') && !x.starts_with("2>"));
    Some(
        prefix
            .map(String::from)
            .into_iter()
            .chain(rest.cloned())
            .collect(),
    )
}

/// Every command line of one Markdown document.
fn find(path: &Path, text: &str) -> Vec<Found> {
    let name = path
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    let code = |first: usize, block: &[&str], found: &mut Vec<Found>| {
        let transcript = block.iter().any(|l| l.trim_start().starts_with("$ "));
        let lines: Vec<(usize, &str)> = (first..)
            .zip(block)
            .filter_map(|(at, l)| {
                let l = l.trim_start();
                match l.strip_prefix("$ ") {
                    Some(cmd) => Some((at, cmd)),
                    None if transcript => None,
                    None => Some((at, l)),
                }
            })
            .collect();
        for (at, c) in commands(&lines) {
            if let Some(args) = rtcosim_args(&c) {
                found.push(Found {
                    at: format!("{name}:{}", at + 1),
                    args,
                });
            }
        }
    };
    let mut i = 0;
    let mut paragraph: Vec<(usize, &str)> = Vec::new();
    let prose = |paragraph: &mut Vec<(usize, &str)>, found: &mut Vec<Found>| {
        let text: Vec<&str> = paragraph.iter().map(|p| p.1).collect();
        let text = text.join(" ");
        for (k, span) in text.split('`').enumerate() {
            if k % 2 == 1 {
                // One command, not a script: a `|` in it is an alternative
                // of a synopsis (`max|mean`), not a pipe.
                let span = span.replace(['[', ']'], " ");
                let span: Vec<String> = span.split_whitespace().map(String::from).collect();
                let args = rtcosim_args(&span);
                if let Some(args) = args {
                    found.push(Found {
                        at: format!("{name}:{}", paragraph[0].0 + 1),
                        args,
                    });
                }
            }
        }
        paragraph.clear();
    };
    while i < lines.len() {
        let l = lines[i];
        if l.trim_start().starts_with("```") {
            prose(&mut paragraph, &mut found);
            let end = (i + 1..lines.len())
                .find(|&j| lines[j].trim_start().starts_with("```"))
                .unwrap_or(lines.len());
            code(i + 1, &lines[i + 1..end], &mut found);
            i = end + 1;
        } else if l.starts_with("    ") && paragraph.is_empty() {
            let end = (i..lines.len())
                .find(|&j| !(lines[j].starts_with("    ") || lines[j].trim().is_empty()))
                .unwrap_or(lines.len());
            code(i, &lines[i..end], &mut found);
            i = end;
        } else if l.trim().is_empty() {
            prose(&mut paragraph, &mut found);
            i += 1;
        } else {
            paragraph.push((i, l));
            i += 1;
        }
    }
    prose(&mut paragraph, &mut found);
    found
}

/// A word that stands for a value: `FILE`, `DIR...`, `WxH`, `K/N`,
/// `X0,Y0`, `STATE:XOR`, `max|mean`, `$VAR`.
fn placeholder(w: &str) -> bool {
    let w = w.trim_end_matches("...");
    w.contains('|')
        || w.starts_with('$')
        || w == "WxH"
        || (w.chars().any(|c| c.is_ascii_uppercase())
            && w.chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || "_/,:".contains(c)))
}

/// Why `found` does not parse, if it does not.
fn check(found: &Found) -> Option<String> {
    let cli = Cli::command();
    let Some(sub) = found.args.first() else {
        return Some("no subcommand".into());
    };
    let Some(command) = cli.find_subcommand(sub) else {
        return Some(format!("no subcommand {sub:?}"));
    };
    if found.args.len() == 1 && command.get_arguments().any(|a| a.is_required_set()) {
        return None; // the subcommand named in prose
    }
    if found.args.iter().any(|w| placeholder(w)) {
        let unknown: Vec<&String> = found
            .args
            .iter()
            .filter_map(|w| {
                w.strip_prefix("--")
                    .map(|o| (w, o.split('=').next().unwrap_or(o)))
            })
            .filter(|(_, o)| {
                *o != "help" && !command.get_arguments().any(|a| a.get_long() == Some(o))
            })
            .map(|(w, _)| w)
            .collect();
        return (!unknown.is_empty()).then(|| format!("{sub} has no option {unknown:?}"));
    }
    let argv = std::iter::once("rtcosim").chain(found.args.iter().map(String::as_str));
    match Cli::try_parse_from(argv) {
        Ok(_) => None,
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelp => None,
        Err(e) => Some(e.render().to_string()),
    }
}

fn documents() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // docs/*.md and the command pages, docs/cli/*.md.
    let mut docs: Vec<PathBuf> = ["docs", "docs/cli"]
        .iter()
        .flat_map(|dir| std::fs::read_dir(root.join(dir)).expect("a docs folder"))
        .map(|e| e.expect("a docs/ entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    docs.insert(0, root.join("README.md"));
    docs
}

#[test]
fn every_documented_command_line_parses() {
    let mut all = Vec::new();
    for path in documents() {
        let text = std::fs::read_to_string(&path).expect("a document");
        all.extend(find(&path, &text));
    }
    let readme = all
        .iter()
        .filter(|f| f.at.starts_with("README.md:"))
        .count();
    let parsed = all
        .iter()
        .filter(|f| !f.args.iter().any(|w| placeholder(w)))
        .count();
    // Counted by hand (grep) when this test was written: the README shows
    // 14 full command lines in code, the docs dozens more.
    assert!(readme >= 14 && parsed >= 60, "found too few: {all:#?}");
    let failures: Vec<String> = all
        .iter()
        .filter_map(|f| {
            check(f).map(|why| format!("{}: rtcosim {}\n  {why}", f.at, f.args.join(" ")))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} documented command lines do not parse:\n{}",
        failures.len(),
        all.len(),
        failures.join("\n")
    );
}

#[test]
fn the_extractor_finds_what_a_reader_would_run() {
    let doc = [
        "Intro `rtcosim cosim --size 80x60` and `rtcosim tune --scene S [--area]`.",
        "",
        "```sh",
        "# a comment naming rtcosim cosim",
        "for e in 5 2; do ./target/release/rtcosim tune --max-error $e --area; done",
        "cargo run --release -- sweep --scene reference \\",
        "    --out /tmp/x | tail -3",
        "cargo run --release -p golden --example perturb -- docs",
        "RTCOSIM_TOPS=8 cargo build --release && rtcosim cosim --procs 8 > log.txt",
        "```",
        "",
        "```",
        "$ rtcosim merge shards --out m",
        "rtcosim merge: output, not a command",
        "```",
        "",
        "    for s in a b; do",
        "        cargo run --release -- render --scene $s --out ${s}.png",
        "    done",
    ]
    .join("\n");
    let found: Vec<String> = find(Path::new("x.md"), &doc)
        .iter()
        .map(|f| format!("{} {}", f.at, f.args.join(" ")))
        .collect();
    assert_eq!(
        found,
        [
            "x.md:1 cosim --size 80x60",
            "x.md:1 tune --scene S --area",
            "x.md:5 tune --max-error 5 --area",
            "x.md:5 tune --max-error 2 --area",
            "x.md:6 sweep --scene reference --out /tmp/x",
            "x.md:9 cosim --procs 8",
            "x.md:13 merge shards --out m",
            "x.md:18 render --scene a --out a.png",
            "x.md:18 render --scene b --out b.png",
        ]
    );
    let verdict = |args: &[&str]| {
        check(&Found {
            at: String::new(),
            args: args.iter().map(|s| s.to_string()).collect(),
        })
    };
    assert_eq!(verdict(&["tune", "--scene", "S", "--area"]), None);
    assert_eq!(verdict(&["tune"]), None);
    assert_eq!(verdict(&["cosim", "--help"]), None);
    assert!(verdict(&["tune", "--scene", "S", "--aera"]).is_some_and(|e| e.contains("--aera")));
    assert!(verdict(&["cosim", "--size", "80by60"]).is_some());
    assert!(verdict(&["cosmis"]).is_some());
    assert!(
        verdict(&["tune", "--scene", "mirror"]).is_some(),
        "--max-error is required"
    );
}

/// Each `state NAME (id) [rtl/pp/pp_ctrl.v:N]` (or `[rtl/fast/fast_ctrl.v:N]`)
/// a document quotes (pasted output of cosim and trace-diff) must name the
/// line of that controller where `ISA_ST_NAME` is decoded, and each `program.rs:M` quoted for a state
/// (`issued by ...` on the same line, or `NAME issued in fn f (...:M`)
/// the line of golden that issues it: the output goes stale when either
/// file moves, and a reader follows these numbers.
#[test]
fn quoted_source_lines_are_the_states_lines() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let source = |p: &str| std::fs::read_to_string(root.join(p)).expect(p);
    let controllers = [
        ("rtl/pp/pp_ctrl.v", source("rtl/pp/pp_ctrl.v")),
        ("rtl/fast/fast_ctrl.v", source("rtl/fast/fast_ctrl.v")),
    ];
    let program = source("golden/src/micro/program.rs");
    let line_of = |text: &str, n: &str| -> String {
        let n: usize = n.parse().unwrap_or(0);
        text.lines()
            .nth(n.wrapping_sub(1))
            .unwrap_or("")
            .to_string()
    };
    // The digits right after `marker` in `s`, if any.
    let number_after = |s: &str, marker: &str| -> Option<String> {
        let at = s.find(marker)? + marker.len();
        let digits: String = s[at..].chars().take_while(char::is_ascii_digit).collect();
        (!digits.is_empty()).then_some(digits)
    };
    let (mut checked, mut wrong) = (0, Vec::new());
    for path in documents() {
        let text = std::fs::read_to_string(&path).expect("a document");
        let name = path
            .file_name()
            .expect("a file")
            .to_string_lossy()
            .into_owned();
        for (k, line) in text.lines().enumerate() {
            let words: Vec<&str> = line.split_whitespace().collect();
            for (i, w) in words.iter().enumerate() {
                let state = match (*w, words.get(i + 1)) {
                    ("state", Some(s)) => *s,
                    (s, Some(&"issued")) => s,
                    _ => continue,
                };
                if !state
                    .chars()
                    .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
                {
                    continue;
                }
                let at = format!("{name}:{}: {state}", k + 1);
                // This state's own quote: up to the next state quoted.
                let rest = words[i + 1..].join(" ");
                let own = rest.split(" state ").next().unwrap_or("");
                for (file, ctrl) in &controllers {
                    if let Some(n) = number_after(own, &format!("[{file}:")) {
                        checked += 1;
                        if !line_of(ctrl, &n).contains(&format!("`ISA_ST_{state}:")) {
                            wrong.push(format!("{at}: {file}:{n} is {:?}", line_of(ctrl, &n)));
                        }
                    }
                }
                if let Some(m) = number_after(own, "golden/src/micro/program.rs:") {
                    checked += 1;
                    if !line_of(&program, &m).contains(&format!("State::{state},")) {
                        wrong.push(format!(
                            "{at}: program.rs:{m} is {:?}",
                            line_of(&program, &m)
                        ));
                    }
                }
            }
        }
    }
    assert!(checked >= 8, "found only {checked} quoted lines");
    assert!(
        wrong.is_empty(),
        "stale source lines in the docs:\n{}",
        wrong.join("\n")
    );
}
