//! A sweep run as a whole, as sharding sees it ([`crate::campaign::shard`]).
//!
//! - [`RunConfig`]: everything `rtcosim sweep` was asked that affects its
//!   results, down to the scenes' own text (not their paths: a shard on
//!   another machine, or a merge a week later, sees the same scenes).
//! - The work list, [`RunConfig::work`]: every (scene, configuration), the
//!   scenes in the order given and each scene's grid in [`Grid::configs`]
//!   order, which is the CSV's row order. A shard measures the items
//!   [`Shard::positions`] gives it ([`measure`]).
//! - [`ShardResult`]: a shard's measured items for its shard file, rows as
//!   the CSV's own cells (exact: the CSV writer prints each f64 in its
//!   shortest round-trip form, NaN and infinities included, and reading
//!   them back gives the same bits).
//! - [`assemble`]: every item's result, from one run or merged from all
//!   shards, into the scenes' sweeps (the Pareto front marked). What
//!   follows (the RTL confirmation of the front, the CSV, the JSON, the
//!   charts) needs every row of a scene, so it runs once on the assembled
//!   sweeps: in the unsharded run, and in `rtcosim merge`.

use super::{
    measure_config, reference_frame, Axis, Config, ConfirmOptions, Grid, Row, SceneSweep, Skipped,
    SweepError,
};
use crate::campaign::shard::Shard;
use crate::check::cosim::CosimOptions;
use crate::design::processor::ProcessorKind;
use golden::scene::Scene;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// The tool name in shard files.
pub const TOOL: &str = "sweep";

/// A scene as the user named it and as it was loaded (overrides applied).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct NamedScene {
    pub name: String,
    /// [`Scene::to_toml`]: the scene back bit for bit.
    pub toml: String,
}

/// Every option of a sweep that affects its results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunConfig {
    pub scenes: Vec<NamedScene>,
    /// Stack depths of the grid (empty: every depth).
    pub depths: Vec<u32>,
    /// Weight cutoffs of the grid (empty: the sweep's default ones).
    pub cutoffs: Vec<f32>,
    pub clock_mhz: f64,
    /// Whether the front is co-simulated on the RTL, and how.
    pub rtl: bool,
    pub sample: u64,
    pub seed: u64,
    /// `STATE:XOR`, as `--fault` takes it.
    pub fault: Option<String>,
    /// `None`: each processor's default.
    pub timeout_cycles: Option<u64>,
    /// The processors swept (each row is confirmed on its own).
    pub processors: Vec<ProcessorKind>,
    /// The axis the front is on (shards of an older rtcosim: device
    /// frames/s).
    #[serde(default)]
    pub axis: Axis,
    /// The Verilator that built the RTL the front is confirmed on.
    pub verilator: String,
}

impl RunConfig {
    /// The grid every scene is swept over.
    pub fn grid(&self) -> Grid {
        let mut grid = Grid::full();
        if !self.processors.is_empty() {
            grid.processors = self.processors.clone();
        }
        if !self.depths.is_empty() {
            grid.depths = self.depths.clone();
        }
        if !self.cutoffs.is_empty() {
            grid.cutoffs = self.cutoffs.clone();
        }
        grid
    }

    /// The scenes, read back from their text.
    pub fn load_scenes(&self) -> Result<Vec<Scene>, SweepError> {
        self.scenes
            .iter()
            .map(|s| {
                Scene::from_toml(&s.toml, &s.name).map_err(|source| SweepError::Config {
                    scene: s.name.clone(),
                    config: "the scene's text".into(),
                    source: Box::new(source),
                })
            })
            .collect()
    }

    /// The work list: (scene position, configuration), in CSV row order;
    /// a scene without glass takes no configuration with the glass opaque
    /// ([`Grid::configs_for`]). (A scene whose text does not read counts
    /// as without glass here; [`RunConfig::load_scenes`] refuses it.)
    pub fn work(&self) -> Vec<(usize, Config)> {
        let configs = self.grid().configs();
        self.scenes
            .iter()
            .enumerate()
            .flat_map(|(s, named)| {
                let glass =
                    Scene::from_toml(&named.toml, &named.name).is_ok_and(|scene| scene.refracts());
                configs
                    .iter()
                    .filter(move |c| glass || !c.opaque_glass)
                    .map(move |&c| (s, c))
            })
            .collect()
    }

    pub fn clock_hz(&self) -> f64 {
        self.clock_mhz * 1e6
    }

    /// How the front is confirmed on the RTL; `None` without the RTL.
    pub fn confirm_options(&self) -> Result<Option<ConfirmOptions>, String> {
        if !self.rtl {
            return Ok(None);
        }
        let fault = self
            .fault
            .as_deref()
            .map(str::parse)
            .transpose()
            .map_err(|e| format!("fault: {e}"))?;
        Ok(Some(ConfirmOptions {
            sample: self.sample,
            seed: self.seed,
            cosim: CosimOptions {
                fault,
                timeout_cycles: self.timeout_cycles,
                ..CosimOptions::default()
            },
        }))
    }
}

/// One work item's result: its position in the work list and its row, or
/// why the scene refused its configuration.
pub type Measured = (u64, Result<Row, Skipped>);

/// Measures `shard`'s items of the work list. Each scene's f64 reference is
/// rendered once, by each shard that has an item of the scene (that cost
/// does not divide by the shard count); the items run in parallel on the
/// current rayon pool. `progress` is called once per item finished;
/// `reference` before each scene's reference frame, with the scene's name.
pub fn measure(
    config: &RunConfig,
    scenes: &[Scene],
    shard: Shard,
    reference: &dyn Fn(&str),
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<Measured>, SweepError> {
    let grid = config.grid();
    for (named, scene) in config.scenes.iter().zip(scenes) {
        super::check_costs(&named.name, scene, &grid)?;
    }
    let work = config.work();
    let clock_hz = config.clock_hz();
    let positions = shard.positions(work.len() as u64);
    let mut out = Vec::new();
    for (s, (named, scene)) in config.scenes.iter().zip(scenes).enumerate() {
        let mine: Vec<(u64, Config)> = positions
            .iter()
            .copied()
            .filter(|&i| work[i as usize].0 == s)
            .map(|i| (i, work[i as usize].1))
            .collect();
        if mine.is_empty() {
            continue;
        }
        reference(&named.name);
        let frame = reference_frame(&named.name, scene)?;
        out.par_extend(mine.par_iter().map(|&(i, c)| {
            let result = measure_config(&named.name, &c, scene, &frame, clock_hz);
            progress(1);
            (i, result)
        }));
    }
    Ok(out)
}

/// The items of a shard file: rows as CSV cells under `columns`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardResult {
    pub columns: Vec<String>,
    pub items: Vec<Item>,
}

/// One item in a shard file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Item {
    pub position: u64,
    /// The row's CSV cells, or `None` for a refused configuration.
    pub row: Option<Vec<String>>,
    /// Why the scene refused the configuration.
    pub refused: Option<String>,
}

impl ShardResult {
    /// `measured` as a shard file holds it.
    pub fn new(measured: &[Measured]) -> ShardResult {
        let rows: Vec<&Row> = measured
            .iter()
            .filter_map(|(_, r)| r.as_ref().ok())
            .collect();
        // Through the CSV writer (which writes the header with the first
        // row) and back to cells.
        let mut writer = csv::Writer::from_writer(Vec::new());
        for row in &rows {
            writer.serialize(row).expect("a row is plain data");
        }
        let text = writer.into_inner().expect("writing to memory");
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(!rows.is_empty())
            .from_reader(&text[..]);
        let columns: Vec<String> = if rows.is_empty() {
            Vec::new()
        } else {
            let header = reader.headers().expect("the header just written");
            header.iter().map(String::from).collect()
        };
        let mut records = reader.records();
        let items = measured
            .iter()
            .map(|(position, result)| match result {
                Ok(_) => {
                    let record = records
                        .next()
                        .expect("one record per row")
                        .expect("the record just written");
                    Item {
                        position: *position,
                        row: Some(record.iter().map(String::from).collect()),
                        refused: None,
                    }
                }
                Err(s) => Item {
                    position: *position,
                    row: None,
                    refused: Some(s.reason.clone()),
                },
            })
            .collect();
        ShardResult { columns, items }
    }

    /// The items back, checked against the work list: the positions must be
    /// `positions`, and each row must be of its item's scene and
    /// configuration. The error says what is wrong, for the caller to name
    /// the file.
    pub fn decode(&self, config: &RunConfig, positions: &[u64]) -> Result<Vec<Measured>, String> {
        let work = config.work();
        let got: Vec<u64> = self.items.iter().map(|i| i.position).collect();
        if got != positions {
            return Err(format!(
                "its result holds {} items, its shard {}; they differ",
                got.len(),
                positions.len()
            ));
        }
        let header = csv::StringRecord::from(self.columns.clone());
        self.items
            .iter()
            .map(|item| {
                let (s, c) = *work
                    .get(item.position as usize)
                    .ok_or_else(|| format!("item {} is past the work list", item.position))?;
                let result = match (&item.row, &item.refused) {
                    (Some(cells), None) => {
                        let record = csv::StringRecord::from(cells.clone());
                        let row: Row = record
                            .deserialize(Some(&header))
                            .map_err(|e| format!("item {}: {e}", item.position))?;
                        if row.scene != config.scenes[s].name || row.config() != c {
                            return Err(format!(
                                "item {} should be {} of {}, is {} of {}",
                                item.position,
                                c.label(),
                                config.scenes[s].name,
                                row.config().label(),
                                row.scene
                            ));
                        }
                        Ok(row)
                    }
                    (None, Some(reason)) => Err(Skipped {
                        config: c,
                        reason: reason.clone(),
                    }),
                    _ => {
                        return Err(format!(
                            "item {} has both a row and a refusal, or neither",
                            item.position
                        ))
                    }
                };
                Ok((item.position, result))
            })
            .collect()
    }
}

/// The scenes' sweeps from every item of the work list (any order; each
/// position once), the Pareto front of each scene marked.
pub fn assemble(
    config: &RunConfig,
    scenes: &[Scene],
    mut measured: Vec<Measured>,
) -> Vec<SceneSweep> {
    measured.sort_by_key(|(i, _)| *i);
    let work = config.work();
    let mut per_scene: Vec<Vec<Result<Row, Skipped>>> = vec![Vec::new(); scenes.len()];
    for (i, result) in measured {
        per_scene[work[i as usize].0].push(result);
    }
    config
        .scenes
        .iter()
        .zip(scenes)
        .zip(per_scene)
        .map(|((named, scene), results)| {
            SceneSweep::assemble(&named.name, scene, results, config.axis)
        })
        .collect()
}
