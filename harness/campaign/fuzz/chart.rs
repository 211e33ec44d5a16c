//! The chart of guided campaigns: coverage against candidates, one line
//! per campaign, drawn with plotters as SVG and PNG
//! ([`crate::output::chart`]).
//!
//! Left: golden's coverage points (transitions and written value
//! classes, [`golden::micro::cover`]) reached; right: the reachable ISA
//! transitions reached, the dashed line at all of them. x: candidates
//! drawn, linear from 0 (the seeds alone at 0). Each campaign is read from
//! its `guided.json` (`fuzz --corpus DIR --out OUT`), so a guided and a
//! random campaign from the same seed budget are compared in one chart.

use super::guided::{CurvePoint, GuidedReport};
use crate::output::chart::{self, ticks, Anchor, Drawing, Label, HEIGHT, LEFT, TOP, WIDTH};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::Deserialize;
use std::path::Path;

/// One campaign's line.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// The legend's text: strategy, processor and seed.
    pub label: String,
    /// The reachable transitions there are.
    pub reachable: usize,
    /// (candidates, points, transitions), from the seeds alone at 0.
    pub curve: Vec<(u64, usize, usize)>,
}

/// The parts of a `guided.json` the chart reads.
#[derive(Debug, Deserialize)]
struct Saved {
    seed: u64,
    strategy: String,
    processor: String,
    seed_points: usize,
    seed_transitions: usize,
    reachable_transitions: usize,
    curve: Vec<CurvePoint>,
}

impl Run {
    fn from_saved(s: Saved) -> Run {
        let curve = std::iter::once((0, s.seed_points, s.seed_transitions))
            .chain(
                s.curve
                    .iter()
                    .map(|p| (p.candidates, p.points, p.transitions)),
            )
            .collect();
        Run {
            label: format!("{}, {} processor, seed {}", s.strategy, s.processor, s.seed),
            reachable: s.reachable_transitions,
            curve,
        }
    }

    /// The line of a campaign's report.
    pub fn of(report: &GuidedReport) -> Run {
        Run::from_saved(Saved {
            seed: report.seed,
            strategy: report.strategy.name().to_string(),
            processor: report.processor.clone(),
            seed_points: report.seed_points,
            seed_transitions: report.seed_transitions,
            reachable_transitions: report.reachable_transitions,
            curve: report.curve.clone(),
        })
    }

    /// The line of the campaign whose `guided.json` is `path`.
    pub fn read(path: &Path) -> Result<Run, chart::ChartError> {
        let fail = |reason: String| chart::ChartError {
            path: path.to_path_buf(),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(|e| fail(e.to_string()))?;
        let saved: Saved = serde_json::from_str(&text)
            .map_err(|e| fail(format!("not a guided campaign's report (guided.json): {e}")))?;
        if saved.curve.is_empty() {
            return Err(fail(
                "the campaign ran no candidate: no curve to draw".into(),
            ));
        }
        Ok(Run::from_saved(saved))
    }
}

/// Writes the chart of `runs` to `svg` and `png`.
pub fn write(runs: &[Run], svg: &Path, png: &Path) -> Result<(), chart::ChartError> {
    chart::write(&Chart(runs), svg, png)
}

/// The lines' colours, in the order of the runs (then again).
const COLOURS: [RGBColor; 4] = [
    RGBColor(30, 90, 200),
    RGBColor(230, 120, 0),
    RGBColor(0, 150, 60),
    RGBColor(150, 150, 150),
];

/// The gap between the two panels, in pixels.
const GAP: u32 = 90;

struct Chart<'a>(&'a [Run]);

impl Drawing for Chart<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<Vec<Label>, String> {
        let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(e)?;
        let runs = self.0;
        let most_candidates = runs
            .iter()
            .filter_map(|r| r.curve.last().map(|p| p.0))
            .max()
            .unwrap_or(1)
            .max(1) as f64;
        let most_points = runs
            .iter()
            .flat_map(|r| r.curve.iter().map(|p| p.1))
            .max()
            .unwrap_or(1) as f64;
        let reachable = runs.iter().map(|r| r.reachable).max().unwrap_or(1) as f64;
        let mut labels = Vec::new();
        let half = (WIDTH - LEFT - chart::RIGHT - GAP) / 2;
        // (left edge, y maximum, which value, title, the line at the top)
        let panels = [
            (
                LEFT,
                most_points * 1.1,
                1,
                "coverage points (golden's)",
                None,
            ),
            (
                LEFT + half + GAP,
                reachable * 1.05,
                2,
                "reachable ISA transitions",
                Some(reachable),
            ),
        ];
        for (left, y_max, which, title, all) in panels {
            let area = root.margin(TOP, chart::BOTTOM, left, WIDTH - left - half);
            let mut c = ChartBuilder::on(&area)
                .build_cartesian_2d(0.0..most_candidates, 0.0..y_max)
                .map_err(e)?;
            let light = ShapeStyle::from(&RGBColor(225, 225, 225)).stroke_width(1);
            for t in ticks(0.0, most_candidates) {
                c.draw_series([PathElement::new(vec![(t, 0.0), (t, y_max)], light)])
                    .map_err(e)?;
                let (px, py) = c.backend_coord(&(t, 0.0));
                labels.push(Label::new(format!("{t}"), (px, py + 8), Anchor::Center));
            }
            for t in ticks(0.0, y_max) {
                c.draw_series([PathElement::new(
                    vec![(0.0, t), (most_candidates, t)],
                    light,
                )])
                .map_err(e)?;
                let (px, py) = c.backend_coord(&(0.0, t));
                labels.push(Label::new(format!("{t}"), (px - 8, py - 7), Anchor::Right));
            }
            if let Some(all) = all {
                c.draw_series(DashedLineSeries::new(
                    [(0.0, all), (most_candidates, all)],
                    6,
                    4,
                    BLACK.stroke_width(1),
                ))
                .map_err(e)?;
            }
            c.draw_series([Rectangle::new(
                [(0.0, 0.0), (most_candidates, y_max)],
                BLACK.stroke_width(1),
            )])
            .map_err(e)?;
            for (i, run) in runs.iter().enumerate() {
                let colour = COLOURS[i % COLOURS.len()];
                let value = |p: &(u64, usize, usize)| if which == 1 { p.1 } else { p.2 };
                c.draw_series(LineSeries::new(
                    run.curve.iter().map(|p| (p.0 as f64, value(p) as f64)),
                    colour.stroke_width(2),
                ))
                .map_err(e)?;
                if let Some(last) = run.curve.last() {
                    let (px, py) = c.backend_coord(&(last.0 as f64, value(last) as f64));
                    labels.push(Label::new(
                        value(last).to_string(),
                        (px - 4, py + 4 + 18 * i as i32),
                        Anchor::Right,
                    ));
                }
            }
            labels.push(Label::new(
                title,
                (left as i32, TOP as i32 - 26),
                Anchor::Left,
            ));
        }
        labels.push(Label::new(
            "guided fuzzing: coverage against candidates",
            (LEFT as i32, 10),
            Anchor::Left,
        ));
        labels.push(Label::new(
            "candidates",
            ((WIDTH / 2) as i32, (HEIGHT - chart::BOTTOM) as i32 + 32),
            Anchor::Center,
        ));
        let legend: Vec<(String, RGBColor)> = runs
            .iter()
            .enumerate()
            .map(|(i, r)| (r.label.clone(), COLOURS[i % COLOURS.len()]))
            .collect();
        // Low in the left panel, where the lines have risen above it.
        let top = (HEIGHT - chart::BOTTOM) as i32 - 24 * legend.len() as i32 - 8;
        labels.extend(chart::legend(root, &legend, top)?);
        Ok(labels)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_report_that_is_not_a_campaigns_is_refused_by_name() {
        let dir = std::env::temp_dir().join(format!("rtcosim-fuzz-chart-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("guided.json");
        std::fs::write(&path, "{\"seed\": 1}").unwrap();
        let err = Run::read(&path).unwrap_err().to_string();
        assert!(
            err.contains("guided.json: not a guided campaign's report"),
            "{err}"
        );
        std::fs::write(
            &path,
            r#"{"seed": 1, "strategy": "guided", "processor": "compact", "seed_points": 5,
               "seed_transitions": 3, "reachable_transitions": 9,
               "curve": [{"candidates": 16, "corpus": 2, "points": 7, "transitions": 4}]}"#,
        )
        .unwrap();
        let run = Run::read(&path).unwrap();
        assert_eq!(run.curve, vec![(0, 5, 3), (16, 7, 4)]);
        assert_eq!(run.label, "guided, compact processor, seed 1");
        let (svg, png) = (dir.join("c.svg"), dir.join("c.png"));
        write(&[run.clone(), run], &svg, &png).unwrap();
        let text = std::fs::read_to_string(&svg).unwrap();
        assert!(text.contains("reachable ISA transitions"), "{text}");
        assert!(image::open(&png).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
