//! `rtcosim cosim --wave K`: after the report, the first divergent pixel
//! re-run on the traced model and written as an FST window
//! (`rtcosim::output::wave`).

use anyhow::{Context, Result};
use golden::scene::Scene;
use rtcosim::check::cosim::CosimReport;
use rtcosim::design::parse_number;
use rtcosim::output::wave::{self, DivergenceAt, Replay, WaveWindow};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The cycles either side of a divergence that `cosim --out DIR` writes
/// when --wave does not say.
pub const DEFAULT_CYCLES: u64 = 20;

#[derive(clap::Args, Debug)]
pub struct WaveArgs {
    /// Re-run the first divergent pixel on the pixel processor verilated
    /// with FST tracing and write K cycles before and after the divergence
    /// (the cycle of the RTL's divergent event, or the pixel's last cycle)
    /// to an FST file, with a GTKWave save file and a filter naming the
    /// controller states: open them with `gtkwave wave.fst wave.gtkw`.
    #[arg(long, value_name = "K", value_parser = parse_k, allow_negative_numbers = true)]
    pub wave: Option<u64>,
    /// Where --wave writes the FST file; the save file (`.gtkw`) and the
    /// state filter (`-states.txt`) go beside it. Not with --out, whose
    /// directory gets the window as wave.fst.
    #[arg(long, value_name = "PATH", default_value = wave::FST_NAME, requires = "wave",
          conflicts_with = "out")]
    pub wave_out: PathBuf,
}

fn parse_k(s: &str) -> Result<u64, String> {
    parse_number(s).ok_or_else(|| format!("expected a number of cycles; got {s:?}"))
}

impl WaveArgs {
    /// Fails unless --wave-out, when the window would be written there (with
    /// --wave and no run directory), names a file in an existing directory:
    /// before the run, not after it.
    /// With --wave, `twin` (the design's waveform twin) must be in this
    /// build: refused before the run, with the feature that builds it.
    pub fn check(&self, dir: Option<&Path>, twin: &Replay) -> Result<()> {
        if let Some(k) = self.wave {
            twin.design
                .check()
                .map_err(|e| anyhow::anyhow!("--wave {k} re-runs a divergence on {e}"))?;
        }
        if self.wave.is_none() || dir.is_some() {
            return Ok(());
        }
        let path = &self.wave_out;
        if path.file_name().is_none() || path.is_dir() {
            anyhow::bail!(
                "--wave-out {}: not a file name (expected e.g. {})",
                path.display(),
                wave::FST_NAME
            );
        }
        crate::args::check_parent_dir("--wave-out", path)
    }

    /// With --wave, writes the window of the report's first divergence,
    /// re-run as `replay` of its row says (to
    /// `dir/wave.fst` when a run directory is given, else to --wave-out)
    /// and says where; without a divergence, says that none was written. A
    /// run directory gets the window of a divergence even without --wave,
    /// [`DEFAULT_CYCLES`] either side.
    pub fn write(
        &self,
        out: &mut impl Write,
        scene: &Scene,
        report: &CosimReport,
        dir: Option<&Path>,
        replay: impl Fn(u32) -> Replay,
    ) -> Result<Option<WaveWindow>> {
        let diverged = report.compare.first_divergence.is_some();
        let default = (dir.is_some() && diverged).then_some(DEFAULT_CYCLES);
        let Some(k) = self.wave.or(default) else {
            return Ok(None);
        };
        let Some(d) = &report.compare.first_divergence else {
            writeln!(out, "--wave {k}: no divergence, so no waveform was written")?;
            return Ok(None);
        };
        let replay = replay(d.y);
        // --out's window, unasked: skipped, said why, where this build has
        // no waveform twin.
        if let (None, Err(e)) = (self.wave, replay.design.check()) {
            writeln!(out, "\nwaveform: not written: {e}")?;
            return Ok(None);
        }
        let path = match dir {
            Some(dir) => dir.join(wave::FST_NAME),
            None => self.wave_out.clone(),
        };
        let w = wave::write_divergence(scene, report.fault, d, k, &path, replay)
            .with_context(|| format!("--wave {k}: pixel ({}, {})", d.x, d.y))?;
        let why = match w.at {
            DivergenceAt::Event { seq, state } => format!(
                "the RTL's event #{seq} ({}) in cycle {}",
                golden::micro::isa::state_label(state),
                w.divergence_cycle
            ),
            DivergenceAt::MissingEvent { seq, rtl_events } => format!(
                "event #{seq}, which the RTL never wrote ({rtl_events} events): its last cycle, {}",
                w.divergence_cycle
            ),
            DivergenceAt::LastCycle => format!("its last cycle, {}", w.divergence_cycle),
        };
        writeln!(
            out,
            "\nwaveform: pixel ({}, {}) re-run on the traced model{}; cycles {}..={} around {why} \
             (cycle c starts at c ns) in {}\n  with {} and {}\n  open it: {}",
            w.x,
            w.y,
            if w.replay.streamed() {
                format!(
                    " of the {} processor{}, fed tile {} from reset (cycles from its first \
                     take)",
                    w.replay.processor(),
                    if w.replay.design.exp_unit {
                        ""
                    } else {
                        " without its exponential"
                    },
                    w.replay.tile
                )
            } else {
                String::new()
            },
            w.first_cycle,
            w.last_cycle,
            w.fst.display(),
            w.gtkw.display(),
            w.filter.display(),
            w.open_command()
        )?;
        Ok(Some(w))
    }
}
