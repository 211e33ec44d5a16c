//! Where coverage models write their counts: the process's coverage
//! directory (set by `output::coverage::enable`, or by [`ENV`]), and the
//! file each model writes into `DIR/raw/` when it is dropped. The drivers
//! of this layer write; `output::coverage` merges and reports.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, Once};

/// The environment variable that enables coverage for a whole process
/// (`RTCOSIM_COVERAGE=DIR cargo test --features coverage`).
pub const ENV: &str = "RTCOSIM_COVERAGE";

/// The subdirectory each model's counts are written into.
pub const RAW: &str = "raw";

static DIR: Mutex<Option<PathBuf>> = Mutex::new(None);
static FROM_ENV: Once = Once::new();

/// Makes every model built from now on in this process a coverage model
/// writing into `dir` (`output::coverage::enable` checks and creates it).
pub fn set_dir(dir: &Path) {
    FROM_ENV.call_once(|| {});
    *DIR.lock().unwrap_or_else(|e| e.into_inner()) = Some(dir.to_path_buf());
}

/// The directory coverage goes to: [`enable`]'s, else [`ENV`]'s (read once).
pub fn dir() -> Option<PathBuf> {
    FROM_ENV.call_once(|| {
        if let Some(d) = std::env::var_os(ENV).filter(|d| !d.is_empty()) {
            let d = PathBuf::from(d);
            let _ = std::fs::create_dir_all(d.join(RAW));
            *DIR.lock().unwrap_or_else(|e| e.into_inner()) = Some(d);
        }
    });
    DIR.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// A new file name in `dir/raw/` for one model's counts: unique across
/// the models of a process and the processes writing into one directory.
pub(crate) fn raw_file(dir: &Path) -> PathBuf {
    static SEQ: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    dir.join(RAW).join(format!(
        "{}-{nanos}-{}.dat",
        std::process::id(),
        SEQ.fetch_add(1, Ordering::Relaxed)
    ))
}

/// Writes one coverage model's counts into `dir/raw/` ([`raw_file`])
/// through `write` (the model's `write_coverage`). Called when the model
/// is dropped, where a failure cannot be returned: it is reported on
/// stderr with the file whose counts were lost.
pub(crate) fn write_raw(dir: &Path, write: impl FnOnce(&str) -> Result<(), cxx::Exception>) {
    let path = raw_file(dir);
    let written = path
        .to_str()
        .ok_or_else(|| "the path is not UTF-8".to_string())
        .and_then(|p| write(p).map_err(|e| e.what().to_string()));
    if let Err(e) = written {
        eprintln!("rtcosim: coverage counts lost, {}: {e}", path.display());
    }
}
