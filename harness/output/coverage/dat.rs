//! Verilator's coverage database (`coverage.dat`, "SystemC::Coverage-3"):
//! read, merged and written as `verilator_coverage --write` does.
//!
//! Each point is a line `C '<key>' <count>`; the key is a list of fields,
//! each `\x01<name>\x02<value>`: `f` the source file, `l` its line, `page`
//! the kind (`v_line/<module>`, `v_branch/...`, `v_toggle/...`,
//! `v_user/...`), `o` the comment (a toggled bit's name, a cover point's
//! label), `h` the instance. Two files' points with the same key are the
//! same point: their counts add.

use super::CoverageError;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// The first line of every coverage.dat Verilator writes.
pub const HEADER: &str = "# SystemC::Coverage-3";

/// A set of coverage points and their counts, keyed as Verilator keys them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CoverageData {
    points: BTreeMap<String, u64>,
}

/// The kind of a point, from its `page`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// A block of statements (`v_line`).
    Line,
    /// A branch of an `if` or `case` (`v_branch`).
    Branch,
    /// One bit of a signal, counted when it toggles (`v_toggle`).
    Toggle,
    /// A controller state (`v_user`, label `s_<STATE>`).
    State,
    /// A controller state transition (`v_user`, label `t_<FROM>_to_<TO>`).
    Transition,
    /// Any other cover point.
    User,
}

impl Kind {
    pub const ALL: [Kind; 6] = [
        Kind::Line,
        Kind::Branch,
        Kind::Toggle,
        Kind::State,
        Kind::Transition,
        Kind::User,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Kind::Line => "line",
            Kind::Branch => "branch",
            Kind::Toggle => "toggle",
            Kind::State => "state",
            Kind::Transition => "transition",
            Kind::User => "user",
        }
    }
}

/// One point, its fields read out of the key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Point<'a> {
    pub kind: Kind,
    pub file: &'a str,
    pub line: u32,
    /// The module (the part of `page` after the slash).
    pub module: &'a str,
    /// The comment: a bit's name, a cover point's label, `block`, `if`, ...
    pub comment: &'a str,
    pub count: u64,
}

fn field<'a>(key: &'a str, name: &str) -> &'a str {
    key.split('\x01')
        .filter_map(|f| f.split_once('\x02'))
        .find(|(n, _)| *n == name)
        .map_or("", |(_, v)| v)
}

impl<'a> Point<'a> {
    fn of(key: &'a str, count: u64) -> Point<'a> {
        let page = field(key, "page");
        let (kind, module) = page.split_once('/').unwrap_or((page, ""));
        let comment = field(key, "o");
        let kind = match kind {
            "v_line" => Kind::Line,
            "v_branch" => Kind::Branch,
            "v_toggle" => Kind::Toggle,
            _ if comment.starts_with("s_") => Kind::State,
            _ if comment.starts_with("t_") && comment.contains("_to_") => Kind::Transition,
            _ => Kind::User,
        };
        Point {
            kind,
            file: field(key, "f"),
            line: field(key, "l").parse().unwrap_or(0),
            module,
            comment,
            count,
        }
    }

    /// A state point's state, a transition point's (from, to): the label
    /// without its prefix.
    pub fn state(&self) -> Option<&'a str> {
        (self.kind == Kind::State).then(|| &self.comment[2..])
    }

    pub fn transition(&self) -> Option<(&'a str, &'a str)> {
        if self.kind != Kind::Transition {
            return None;
        }
        self.comment[2..].split_once("_to_")
    }
}

impl CoverageData {
    /// Reads `text`, the contents of `path` (named in errors).
    pub fn parse(text: &str, path: &Path) -> Result<CoverageData, CoverageError> {
        let bad = |line: usize, message: String| CoverageError::Format {
            path: path.to_path_buf(),
            line,
            message,
        };
        let mut lines = text.lines().enumerate();
        match lines.next() {
            Some((_, first)) if first.trim_end() == HEADER => {}
            _ => {
                return Err(bad(
                    1,
                    format!("not a Verilator coverage file (the first line is not `{HEADER}`)"),
                ))
            }
        }
        let mut data = CoverageData::default();
        for (i, line) in lines {
            let line = line.trim_end();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let parsed = line.strip_prefix("C '").and_then(|rest| {
                let (key, count) = rest.rsplit_once("' ")?;
                Some((key, count.trim().parse::<u64>().ok()?))
            });
            let Some((key, count)) = parsed else {
                return Err(bad(i + 1, "expected `C '<key>' <count>`".into()));
            };
            data.add(key, count);
        }
        Ok(data)
    }

    /// Reads the file at `path`.
    pub fn read(path: &Path) -> Result<CoverageData, CoverageError> {
        let text = std::fs::read_to_string(path).map_err(|source| CoverageError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(&text, path)
    }

    fn add(&mut self, key: &str, count: u64) {
        let c = self.points.entry(key.to_string()).or_insert(0);
        *c = c.saturating_add(count);
    }

    /// Adds `other`'s counts to these (a point in either is in the sum).
    pub fn merge(&mut self, other: &CoverageData) {
        for (key, &count) in &other.points {
            self.add(key, count);
        }
    }

    /// The points, in key order.
    pub fn points(&self) -> impl Iterator<Item = Point<'_>> {
        self.points.iter().map(|(k, &c)| Point::of(k, c))
    }

    pub fn len(&self) -> usize {
        self.points.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The file's text, as Verilator writes it.
    pub fn to_text(&self) -> String {
        let mut text = format!("{HEADER}\n");
        for (key, count) in &self.points {
            let _ = writeln!(text, "C '{key}' {count}");
        }
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Three points as Verilator 5.006 wrote them for the pixel processor
    // (the line, a toggled bit, a transition of the controller).
    const SAMPLE: &str = "# SystemC::Coverage-3\n\
C '\x01f\x02rtl/fp/fp_add.v\x01l\x02118\x01n\x025\x01page\x02v_line/fp_add\x01o\x02block\x01S\x02118-119\x01h\x02TOP.pixel_processor.u_core.u_alu.u_add_*' 3\n\
C '\x01f\x02rtl/pp/pp_ctrl.v\x01l\x02152\x01n\x0217\x01page\x02v_toggle/pp_ctrl\x01o\x02st_q[0]\x01h\x02TOP.pixel_processor.u_ctrl' 0\n\
C '\x01f\x02rtl/cover/pp_ctrl.transitions\x01l\x027\x01n\x0221\x01page\x02v_user/pp_ctrl_cover\x01o\x02t_IDLE_to_PRI_ITOF\x01S\x027\x01h\x02TOP.pixel_processor.u_ctrl.u_cover.t_IDLE_to_PRI_ITOF' 12\n";

    #[test]
    fn reads_each_field_of_verilators_points() -> Result<(), CoverageError> {
        let d = CoverageData::parse(SAMPLE, Path::new("s.dat"))?;
        let p: Vec<Point> = d.points().collect();
        assert_eq!(p.len(), 3);
        let line = p
            .iter()
            .find(|p| p.kind == Kind::Line)
            .expect("a line point");
        assert_eq!(
            (line.file, line.line, line.module, line.comment, line.count),
            ("rtl/fp/fp_add.v", 118, "fp_add", "block", 3)
        );
        let bit = p
            .iter()
            .find(|p| p.kind == Kind::Toggle)
            .expect("a toggle point");
        assert_eq!((bit.comment, bit.count), ("st_q[0]", 0));
        let t = p
            .iter()
            .find(|p| p.kind == Kind::Transition)
            .expect("a transition");
        assert_eq!(t.transition(), Some(("IDLE", "PRI_ITOF")));
        assert_eq!(
            (t.file, t.line, t.count),
            ("rtl/cover/pp_ctrl.transitions", 7, 12)
        );
        Ok(())
    }

    #[test]
    fn merging_adds_the_counts_of_the_same_point_and_keeps_the_others() -> Result<(), CoverageError>
    {
        let a = CoverageData::parse(SAMPLE, Path::new("a.dat"))?;
        let mut sum = a.clone();
        sum.merge(&a);
        let counts: Vec<u64> = sum.points().map(|p| p.count).collect();
        let once: Vec<u64> = a.points().map(|p| p.count).collect();
        assert_eq!(counts, once.iter().map(|c| 2 * c).collect::<Vec<_>>());
        let other = CoverageData::parse(
            "# SystemC::Coverage-3\nC '\x01f\x02x.v\x01l\x021\x01page\x02v_line/x\x01o\x02if' 5\n",
            Path::new("b.dat"),
        )?;
        sum.merge(&other);
        assert_eq!(sum.len(), 4);
        // Written and read back: the same points.
        assert_eq!(
            CoverageData::parse(&sum.to_text(), Path::new("c.dat"))?,
            sum
        );
        Ok(())
    }

    #[test]
    fn refuses_a_foreign_or_broken_file_naming_the_line() {
        let e = CoverageData::parse("hello\n", Path::new("x.dat"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("x.dat:1") && e.contains("not a Verilator coverage file"),
            "{e}"
        );
        let e = CoverageData::parse("# SystemC::Coverage-3\nC 'abc' many\n", Path::new("y.dat"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("y.dat:2") && e.contains("C '<key>' <count>"),
            "{e}"
        );
    }
}
