//! The exit status of every command line: 0 when every check passed, 1
//! when a check failed (a divergence, a mismatch), 2 on an error.

use std::process::ExitCode;

/// The exit status of a command's outcome; an error is printed first.
pub fn status(outcome: anyhow::Result<bool>) -> ExitCode {
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        // The reader went away (`rtcosim ... | head`): nothing left to say.
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes, joined with `: ` as `{e:#}` prints them, but
/// without a cause whose text the message already ends with: an error
/// that words its source into its own text (thiserror's `{source}`) would
/// otherwise say it twice ("...: Not a directory (os error 20): Not a
/// directory (os error 20)").
fn message(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let c = cause.to_string();
        if text.is_empty() {
            text = c;
        } else if !text.ends_with(&c) {
            text.push_str(": ");
            text.push_str(&c);
        }
    }
    text
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

#[cfg(test)]
mod tests {
    use super::message;
    use anyhow::Context;

    #[derive(Debug, thiserror::Error)]
    #[error("cannot write {path}: {source}")]
    struct Worded {
        path: &'static str,
        source: std::io::Error,
    }

    #[test]
    fn a_cause_already_worded_is_said_once() {
        let io = || std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let e = anyhow::Error::new(Worded {
            path: "x/w.fst",
            source: io(),
        })
        .context("--wave 3");
        assert_eq!(message(&e), "--wave 3: cannot write x/w.fst: no such file");
        // A cause not in the text before it is kept, as {e:#} keeps it.
        let e = Err::<(), _>(io()).context("--out d").unwrap_err();
        assert_eq!(message(&e), format!("{e:#}"));
        assert_eq!(message(&e), "--out d: no such file");
    }
}
