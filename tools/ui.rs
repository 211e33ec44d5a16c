//! What every command shows the user besides its results: progress bars on
//! stderr, and plurals.

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar of `len` steps on stderr: `{label} [=====>   ] ...`,
/// `detail` in indicatif's template syntax after the bar.
pub fn progress_bar(len: u64, label: &str, detail: &str) -> Result<ProgressBar> {
    let template = format!("{label} [{{bar:30}}] {detail}");
    Ok(ProgressBar::new(len).with_style(
        ProgressStyle::with_template(&template)
            .context("progress bar template")?
            .progress_chars("=> "),
    ))
}

/// A spinner on stderr for work of unknown length: `{label} ⠁ {detail}`.
pub fn progress_spinner(label: &str, detail: &str) -> Result<ProgressBar> {
    let template = format!("{label} {{spinner}} {detail}");
    Ok(ProgressBar::new_spinner()
        .with_style(ProgressStyle::with_template(&template).context("progress spinner template")?))
}

/// `"s"` unless `n` is 1.
pub fn plural(n: impl Into<u64>) -> &'static str {
    if n.into() == 1 {
        ""
    } else {
        "s"
    }
}

/// Writes a trace of `window` to `path` with a progress bar: `write` gets
/// the progress callback and returns the events written; then says so.
pub fn write_trace<E: std::error::Error + Send + Sync + 'static>(
    out: &mut impl std::io::Write,
    path: &std::path::Path,
    window: golden::window::Window,
    write: impl FnOnce(&dyn Fn(u64)) -> std::result::Result<u64, E>,
) -> Result<()> {
    let bar = progress_bar(window.pixels(), "tracing  ", "{percent:>3}% ({eta})")?;
    let events = write(&|n| bar.inc(n)).context("--trace")?;
    bar.finish_and_clear();
    writeln!(
        out,
        "wrote {}: {events} trace events of {} pixel{} (columns {}..={}, rows {}..={})",
        path.display(),
        window.pixels(),
        plural(window.pixels()),
        window.x,
        window.columns().end - 1,
        window.y,
        window.rows().end - 1
    )?;
    Ok(())
}
