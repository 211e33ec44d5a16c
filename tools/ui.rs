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

/// `"s"` unless `n` is 1.
pub fn plural(n: impl Into<u64>) -> &'static str {
    if n.into() == 1 {
        ""
    } else {
        "s"
    }
}
