//! Scene mutations for the guided fuzzer ([`super::guided`]): a candidate
//! is a corpus scene with one to four changes stacked ("havoc"), made on
//! the scene file's TOML tree, so every candidate is a file a user could
//! have written and goes through the same loader and validation.
//!
//! The changes know the file's shape only as TOML: numbers, booleans,
//! strings, arrays and arrays of tables (the objects). What each does:
//!
//! - a number: one to 16 f32 ULPs either way (thresholds sit on exact
//!   values), times a power of two, negated, a special value (zeros, one,
//!   the smallest normal and subnormal floats, the scene limits of
//!   `golden::scene`, and their neighbours), another number of the same
//!   scene (coincidences: equal coordinates, a radius equal to a distance),
//!   or a uniform draw around it; an integer (image sides, depth) one
//!   either way or a small count;
//! - a boolean flipped; a string replaced by one the corpus has at the
//!   same key (an axis, a facing, a float method);
//! - an object duplicated, removed, swapped with another (the processors
//!   search objects in file order), or replaced by one of another corpus
//!   scene (crossover); a value or a key the scene lacks copied from
//!   another corpus scene at the same place;
//! - the whole scene moved along an axis (the eye, the light, every centre
//!   and the offsets of the planes across it), by 2^8 to 2^16 times its
//!   smallest radius: the same picture in exact arithmetic, its points now
//!   placed to a few bits of the radius in f32 (a discriminant that
//!   rounds below zero, a hit point off its sphere).

use golden::scene::{
    MAX_COORD, MAX_DISTANCE, MAX_EXPOSURE, MAX_IOR, MAX_RADIUS, MIN_DISTANCE, MIN_IOR, MIN_RADIUS,
};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use toml::{Table, Value};

/// A step of a path into a TOML tree.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Step {
    Key(String),
    Index(usize),
}

/// Every scalar leaf of `table` (numbers, booleans, strings, including
/// those inside arrays), by path.
fn leaves(table: &Table) -> Vec<Vec<Step>> {
    fn walk(v: &Value, path: &mut Vec<Step>, out: &mut Vec<Vec<Step>>) {
        match v {
            Value::Table(t) => {
                for (k, v) in t {
                    path.push(Step::Key(k.clone()));
                    walk(v, path, out);
                    path.pop();
                }
            }
            Value::Array(a) => {
                for (i, v) in a.iter().enumerate() {
                    path.push(Step::Index(i));
                    walk(v, path, out);
                    path.pop();
                }
            }
            Value::Float(_) | Value::Integer(_) | Value::Boolean(_) | Value::String(_) => {
                out.push(path.clone())
            }
            Value::Datetime(_) => {}
        }
    }
    let mut out = Vec::new();
    for (k, v) in table {
        walk(v, &mut vec![Step::Key(k.clone())], &mut out);
    }
    out
}

fn get<'t>(table: &'t Table, path: &[Step]) -> Option<&'t Value> {
    let (Step::Key(first), rest) = path.split_first()? else {
        return None;
    };
    let mut v = table.get(first)?;
    for step in rest {
        v = match (step, v) {
            (Step::Key(k), Value::Table(t)) => t.get(k)?,
            (Step::Index(i), Value::Array(a)) => a.get(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

fn get_mut<'t>(table: &'t mut Table, path: &[Step]) -> Option<&'t mut Value> {
    let (Step::Key(first), rest) = path.split_first()? else {
        return None;
    };
    let mut v = table.get_mut(first)?;
    for step in rest {
        v = match (step, v) {
            (Step::Key(k), Value::Table(t)) => t.get_mut(k)?,
            (Step::Index(i), Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(v)
}

/// Sets the value at `path`, making the last key if its table lacks it.
fn set(table: &mut Table, path: &[Step], value: Value) -> bool {
    let Some((last, parent)) = path.split_last() else {
        return false;
    };
    let parent = if parent.is_empty() {
        None
    } else {
        match get_mut(table, parent) {
            Some(p) => Some(p),
            None => return false,
        }
    };
    match (last, parent) {
        (Step::Key(k), None) => {
            table.insert(k.clone(), value);
            true
        }
        (Step::Key(k), Some(Value::Table(t))) => {
            t.insert(k.clone(), value);
            true
        }
        (Step::Index(i), Some(Value::Array(a))) if *i < a.len() => {
            a[*i] = value;
            true
        }
        _ => false,
    }
}

/// The path's keys alone (`sphere.center`): where a value sits whatever
/// the object's index.
#[cfg(test)]
fn shape(path: &[Step]) -> String {
    path.iter()
        .filter_map(|s| match s {
            Step::Key(k) => Some(k.as_str()),
            Step::Index(_) => None,
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// The arrays of tables of `table` (`sphere`, `plane`): the objects.
fn object_lists(table: &Table) -> Vec<String> {
    table
        .iter()
        .filter(
            |(_, v)| matches!(v, Value::Array(a) if a.iter().all(Value::is_table) && !a.is_empty()),
        )
        .map(|(k, _)| k.clone())
        .collect()
}

/// Values a number is set to now and then: zeros, one, the float range's
/// edges, and the scene limits with their neighbours.
fn special_numbers() -> Vec<f64> {
    let limits = [
        MAX_COORD,
        MAX_RADIUS,
        MIN_RADIUS,
        MAX_DISTANCE,
        MIN_DISTANCE,
        MAX_EXPOSURE,
        MAX_IOR,
        MIN_IOR,
        1.0,
    ];
    let mut out = vec![
        0.0,
        -0.0,
        -1.0,
        f64::from(f32::MIN_POSITIVE),
        f64::from(f32::from_bits(1)),
        f64::from(f32::MAX),
    ];
    for l in limits {
        out.push(f64::from(l));
        out.push(f64::from(f32::from_bits(l.to_bits() + 1)));
        out.push(f64::from(f32::from_bits(l.to_bits() - 1)));
    }
    out
}

/// The f32 `ulps` steps from `x` (as f64), through zero and with the sign.
fn f32_step(x: f64, ulps: i64) -> f64 {
    // Floats ordered as integers: negative ones mirrored below zero.
    let key = |f: f32| -> i64 {
        let b = i64::from(f.to_bits());
        if b >> 31 == 1 {
            -(b & 0x7FFF_FFFF)
        } else {
            b
        }
    };
    let k = (key(x as f32) + ulps).clamp(-0x7F7F_FFFF, 0x7F7F_FFFF);
    let bits = if k < 0 {
        (-k) as u32 | 0x8000_0000
    } else {
        k as u32
    };
    f64::from(f32::from_bits(bits))
}

/// One change applied to a scene, for the candidate's header.
pub type Change = String;

/// Applies one to four changes to `scene` (its TOML tree), drawing from
/// `rng` and taking crossover material from `donors`; returns what was
/// done. A change that finds nothing to act on (no object to remove) is
/// skipped.
pub fn mutate(scene: &mut Table, donors: &[&Table], rng: &mut ChaCha8Rng) -> Vec<Change> {
    let count = 1 << rng.random_range(0..3u32);
    let mut done = Vec::new();
    for _ in 0..count.min(4) {
        if let Some(c) = change(scene, donors, rng) {
            done.push(c);
        }
    }
    done
}

fn pick<'a, T>(rng: &mut ChaCha8Rng, items: &'a [T]) -> Option<&'a T> {
    if items.is_empty() {
        None
    } else {
        Some(&items[rng.random_range(0..items.len())])
    }
}

fn change(scene: &mut Table, donors: &[&Table], rng: &mut ChaCha8Rng) -> Option<Change> {
    match rng.random_range(0..11) {
        0..=5 => change_leaf(scene, rng),
        6 => change_objects(scene, rng),
        7 => translate(scene, rng),
        _ => crossover(scene, donors, rng),
    }
}

/// The numbers of the array at `path` (a point: `camera.eye`).
fn point_mut<'t>(table: &'t mut Table, path: &[&str]) -> Option<&'t mut Vec<Value>> {
    let path: Vec<Step> = path.iter().map(|k| Step::Key((*k).into())).collect();
    match get_mut(table, &path)? {
        Value::Array(a) if a.len() == 3 && a.iter().all(|v| number(v).is_some()) => Some(a),
        _ => None,
    }
}

/// A number of the file, written as a float or an integer.
fn number(v: &Value) -> Option<f64> {
    match v {
        Value::Float(x) => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

/// `v` plus `by`, as the file can spell it (an f32).
fn moved(v: &mut Value, by: f64) {
    if let Some(x) = number(v) {
        *v = Value::Float(f64::from((x + by) as f32));
    }
}

/// The whole scene moved by `2^k` times its smallest radius (1 without a
/// sphere), k in 8..=16, along one axis, either way: the eye, the light,
/// every sphere's centre and the offset of every plane across that axis.
fn translate(scene: &mut Table, rng: &mut ChaCha8Rng) -> Option<Change> {
    let radius = match scene.get("sphere") {
        Some(Value::Array(spheres)) => spheres
            .iter()
            .filter_map(|s| number(s.get("radius")?))
            .map(f64::abs)
            .filter(|r| *r > 0.0)
            .fold(f64::INFINITY, f64::min),
        _ => f64::INFINITY,
    };
    let radius = if radius.is_finite() { radius } else { 1.0 };
    let k = rng.random_range(8..=16i32);
    let axis = rng.random_range(0..3usize);
    let by = radius * 2f64.powi(k) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    for path in [&["camera", "eye"][..], &["light", "position"][..]] {
        if let Some(p) = point_mut(scene, path) {
            moved(&mut p[axis], by);
        }
    }
    if let Some(Value::Array(spheres)) = scene.get_mut("sphere") {
        for sphere in spheres.iter_mut() {
            if let Some(Value::Array(c)) = sphere.get_mut("center") {
                if let Some(v) = c.get_mut(axis) {
                    moved(v, by);
                }
            }
        }
    }
    let name = ["x", "y", "z"][axis];
    if let Some(Value::Array(planes)) = scene.get_mut("plane") {
        for plane in planes.iter_mut() {
            if plane.get("axis").and_then(Value::as_str) == Some(name) {
                if let Some(offset) = plane.get_mut("offset") {
                    moved(offset, by);
                }
            }
        }
    }
    Some(format!(
        "the scene moved by {by:e} along {name} (2^{k} radii)"
    ))
}

fn path_text(path: &[Step]) -> String {
    let mut s = String::new();
    for step in path {
        match step {
            Step::Key(k) if s.is_empty() => s.push_str(k),
            Step::Key(k) => {
                s.push('.');
                s.push_str(k);
            }
            Step::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

fn change_leaf(scene: &mut Table, rng: &mut ChaCha8Rng) -> Option<Change> {
    let all = leaves(scene);
    let path = pick(rng, &all)?.clone();
    let numbers: Vec<f64> = all.iter().filter_map(|p| number(get(scene, p)?)).collect();
    let old = get(scene, &path)?.clone();
    let (new, how) = match old {
        Value::Float(x) => {
            let (y, how) = match rng.random_range(0..6) {
                0 => {
                    let ulps =
                        rng.random_range(1..=16i64) * if rng.random_bool(0.5) { 1 } else { -1 };
                    (f32_step(x, ulps), format!("{ulps:+} ulp"))
                }
                1 => {
                    let k = rng.random_range(-8..=8i32);
                    (x * 2f64.powi(k), format!("times 2^{k}"))
                }
                2 => (-x, "negated".into()),
                3 => {
                    let s = *pick(rng, &special_numbers())?;
                    (s, "a special value".into())
                }
                4 => {
                    let y = *pick(rng, &numbers)?;
                    (y, "another number of the scene".into())
                }
                _ => {
                    // An earlier change of the stack may have left an
                    // infinity or a NaN (the loader refuses either).
                    let r = if x == 0.0 || !x.is_finite() {
                        1.0
                    } else {
                        2.0 * x.abs()
                    };
                    (rng.random_range(-r..=r), "drawn around it".into())
                }
            };
            // What the file can spell: an f32, written back exactly.
            (Value::Float(f64::from(y as f32)), how)
        }
        Value::Integer(i) => {
            let y = match rng.random_range(0..3) {
                0 => i + 1,
                1 => i - 1,
                _ => rng.random_range(1..=16),
            };
            (Value::Integer(y), "an integer moved".into())
        }
        Value::Boolean(b) => (Value::Boolean(!b), "flipped".into()),
        // Strings are changed by crossover, from the corpus' own.
        _ => return None,
    };
    let text = format!("{} {} ({})", path_text(&path), how, value_text(&new));
    set(scene, &path, new).then_some(text)
}

fn value_text(v: &Value) -> String {
    match v {
        Value::Float(f) => format!("{f:e}"),
        other => other.to_string(),
    }
}

fn change_objects(scene: &mut Table, rng: &mut ChaCha8Rng) -> Option<Change> {
    let lists = object_lists(scene);
    let key = pick(rng, &lists)?.clone();
    let Some(Value::Array(objects)) = scene.get_mut(&key) else {
        return None;
    };
    let n = objects.len();
    let i = rng.random_range(0..n);
    match rng.random_range(0..5) {
        4 => {
            // No object of this kind at all: a search without planes ends
            // on its last sphere (one at a time, a corpus scene seldom
            // loses them all).
            let removed = objects.len();
            objects.clear();
            Some(format!("every {key} removed ({removed})"))
        }
        3 => {
            // A material whose terms the controller branches on, all at
            // once (one number at a time seldom gets there): black, a pure
            // mirror, pure glass (a sphere's), matte.
            let Value::Table(object) = &mut objects[i] else {
                return None;
            };
            let (name, terms): (&str, &[(&str, f64)]) = match rng.random_range(0..4) {
                0 => (
                    "black",
                    &[("diffuse", 0.0), ("specular", 0.0), ("reflection", 0.0)],
                ),
                1 => (
                    "a pure mirror",
                    &[("diffuse", 0.0), ("specular", 0.0), ("reflection", 1.0)],
                ),
                2 if key == "sphere" => (
                    "pure glass",
                    &[
                        ("diffuse", 0.0),
                        ("specular", 0.0),
                        ("reflection", 0.0),
                        ("transmission", 1.0),
                    ],
                ),
                _ => (
                    "matte",
                    &[("diffuse", 1.0), ("specular", 0.0), ("reflection", 0.0)],
                ),
            };
            for &(term, x) in terms {
                object.insert(term.into(), Value::Float(x));
            }
            Some(format!("{key}[{i}] made {name}"))
        }
        0 => {
            let copy = objects[i].clone();
            let at = rng.random_range(0..=n);
            objects.insert(at, copy);
            Some(format!("{key}[{i}] duplicated at {at}"))
        }
        1 => {
            objects.remove(i);
            Some(format!("{key}[{i}] removed"))
        }
        _ => {
            let j = rng.random_range(0..n);
            objects.swap(i, j);
            Some(format!("{key}[{i}] and {key}[{j}] swapped"))
        }
    }
}

/// `path` of another scene at the same place in `scene`: indices of object
/// lists wrapped into ours (a value's own lanes, `center[2]`, stay), or
/// None where `scene` has no object list there.
fn wrap(scene: &Table, path: &[Step]) -> Option<Vec<Step>> {
    let mut ours = Vec::new();
    for (k, step) in path.iter().enumerate() {
        match step {
            Step::Index(i) => {
                let len = match get(scene, &ours) {
                    Some(Value::Array(a)) => a.len(),
                    _ => return None,
                };
                if len == 0 {
                    return None;
                }
                let wrapped = if k + 1 < path.len() { i % len } else { *i };
                ours.push(Step::Index(wrapped));
            }
            key => ours.push(key.clone()),
        }
    }
    Some(ours)
}

/// A value (or an object) of a donor scene put at the same place in
/// `scene`: a leaf at a path of the same shape (indices taken modulo the
/// scene's own), or a whole object.
fn crossover(scene: &mut Table, donors: &[&Table], rng: &mut ChaCha8Rng) -> Option<Change> {
    let donor = *pick(rng, donors)?;
    if rng.random_bool(0.3) {
        let lists = object_lists(donor);
        let key = pick(rng, &lists)?.clone();
        let Some(Value::Array(theirs)) = donor.get(&key) else {
            return None;
        };
        let object = pick(rng, theirs)?.clone();
        let ours = scene
            .entry(key.clone())
            .or_insert_with(|| Value::Array(Vec::new()));
        let Value::Array(ours) = ours else {
            return None;
        };
        if ours.is_empty() || rng.random_bool(0.5) {
            ours.push(object);
            return Some(format!("a {key} of another corpus scene added"));
        }
        let at = rng.random_range(0..ours.len());
        ours[at] = object;
        return Some(format!(
            "{key}[{at}] replaced by one of another corpus scene"
        ));
    }
    let theirs = leaves(donor);
    // Half the time a value at a place the scene does not have (an
    // optional key: a weight cutoff, an exposure, glass), if there is one.
    let missing: Vec<Vec<Step>> = theirs
        .iter()
        .filter(|p| wrap(scene, p).is_some_and(|w| get(scene, &w).is_none()))
        .cloned()
        .collect();
    let from = if !missing.is_empty() && rng.random_bool(0.5) {
        &missing
    } else {
        &theirs
    };
    let path = pick(rng, from)?.clone();
    let value = get(donor, &path)?.clone();
    let ours = wrap(scene, &path)?;
    let text = format!(
        "{} from another corpus scene ({})",
        path_text(&ours),
        value_text(&value)
    );
    set(scene, &ours, value).then_some(text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn reference() -> Table {
        let scene = golden::scene::Scene::reference();
        scene
            .to_toml()
            .parse::<Table>()
            .expect("the reference's TOML")
    }

    #[test]
    fn f32_steps_cross_zero_and_keep_to_floats() {
        assert_eq!(f32_step(1.0, 1), f64::from(f32::from_bits(0x3F80_0001)));
        assert_eq!(f32_step(1.0, -1), f64::from(f32::from_bits(0x3F7F_FFFF)));
        assert_eq!(f32_step(0.0, -1), -f64::from(f32::from_bits(1)));
        assert_eq!(
            f32_step(-f64::from(f32::from_bits(1)), 2),
            f64::from(f32::from_bits(1))
        );
        assert_eq!(f32_step(f64::from(f32::MAX), 5), f64::from(f32::MAX));
    }

    #[test]
    fn a_path_reads_and_writes_the_same_place() {
        let mut t = reference();
        let all = leaves(&t);
        assert!(all.iter().any(|p| shape(p) == "sphere.center"));
        assert!(all.iter().any(|p| shape(p) == "camera.width"));
        let path = vec![
            Step::Key("sphere".into()),
            Step::Index(1),
            Step::Key("radius".into()),
        ];
        assert!(set(&mut t, &path, Value::Float(3.5)));
        assert_eq!(get(&t, &path), Some(&Value::Float(3.5)));
        // A key the table lacks is made; an index past the end is not.
        let ior = vec![
            Step::Key("sphere".into()),
            Step::Index(0),
            Step::Key("ior".into()),
        ];
        assert!(set(&mut t, &ior, Value::Float(1.5)));
        let past = vec![
            Step::Key("sphere".into()),
            Step::Index(99),
            Step::Key("radius".into()),
        ];
        assert!(!set(&mut t, &past, Value::Float(1.0)));
    }

    /// A stack of changes may leave an infinity or a NaN that a later
    /// change of the same stack acts on: no change panics on one.
    #[test]
    fn non_finite_numbers_are_changed_without_a_panic() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..2000 {
            let mut t: Table = "x = inf\ny = nan\nz = -inf\nw = 3.4e38"
                .parse()
                .expect("TOML");
            mutate(&mut t, &[], &mut rng);
        }
    }

    /// Mutants of the reference: each is a different file, most load, and
    /// a seed gives the same ones again.
    #[test]
    fn mutants_change_the_file_and_most_still_load() {
        let base = reference();
        let donor = golden::scene::Scene::builtin("glass_room")
            .expect("a builtin")
            .to_toml()
            .parse::<Table>()
            .expect("TOML");
        let run = |seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            (0..200)
                .map(|_| {
                    let mut t = base.clone();
                    let changes = mutate(&mut t, &[&donor], &mut rng);
                    (toml::to_string(&t).expect("writes"), changes)
                })
                .collect::<Vec<_>>()
        };
        let a = run(7);
        assert_eq!(a, run(7));
        let original = toml::to_string(&base).expect("writes");
        let changed = a.iter().filter(|(t, _)| *t != original).count();
        assert!(changed > 150, "only {changed} of 200 changed");
        let loaded = a
            .iter()
            .filter(|(t, _)| golden::scene::Scene::from_toml(t, "mutant").is_ok())
            .count();
        assert!(loaded > 100, "only {loaded} of 200 load");
        // What was done is said, for the kept scene's header.
        assert!(a
            .iter()
            .filter(|(t, _)| *t != original)
            .all(|(_, c)| !c.is_empty()));
        // Material presets occur, and set their terms (when the preset
        // is the last change made).
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut black = 0;
        for _ in 0..2000 {
            let mut t = base.clone();
            let changes = mutate(&mut t, &[&donor], &mut rng);
            let Some(last) = changes.last().filter(|c| c.ends_with(" made black")) else {
                continue;
            };
            black += 1;
            let (key, index) = last.split_once('[').expect("an object");
            let i: usize = index
                .split(']')
                .next()
                .and_then(|n| n.parse().ok())
                .expect("index");
            let object = t[key].as_array().expect("objects")[i]
                .as_table()
                .expect("object");
            for term in ["diffuse", "specular", "reflection"] {
                assert_eq!(object[term].as_float(), Some(0.0), "{last}");
            }
        }
        assert!(black > 0, "no black material in 2000 mutants");
        // A whole kind of object goes, and the rest still loads.
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let bare = (0..2000)
            .filter_map(|_| {
                let mut t = base.clone();
                let changes = mutate(&mut t, &[&donor], &mut rng);
                changes
                    .iter()
                    .any(|c| c.starts_with("every plane removed"))
                    .then_some(t)
            })
            .filter(|t| t["plane"].as_array().is_some_and(|a| a.is_empty()))
            .filter_map(|t| golden::scene::Scene::from_toml(&toml::to_string(&t).ok()?, "m").ok())
            .count();
        assert!(bare > 0, "no scene without planes loaded in 2000 mutants");
    }

    #[test]
    fn a_moved_scene_keeps_its_shape_and_loads() {
        let material = "color = [0.5, 0.5, 0.5]\ndiffuse = 0.5\nspecular = 0.2\nreflection = 0.1\n";
        let text = format!(
            "[camera]\neye = [0.0, 0.0, -10.0]\nrotation = [0.0, 0.0, 0.0]\ndistance = 10.0\nwidth = 4\nheight = 4\n\
             [light]\nposition = [5.0, 5.0, -10.0]\ncolor = [1.0, 1.0, 1.0]\n\
             [[sphere]]\ncenter = [0.0, 0.0, 5.0]\nradius = 2.0\n{material}\
             [[sphere]]\ncenter = [1, 2, 8]\nradius = 0.5\n{material}\
             [[plane]]\naxis = \"z\"\nfacing = \"-\"\noffset = 20.0\n{material}\
             [[plane]]\naxis = \"y\"\nfacing = \"+\"\noffset = -3.0\n{material}\
             [render]\nmax_depth = 3\n"
        );
        let original: Table = toml::from_str(&text).expect("the scene");
        golden::scene::Scene::from_toml(&text, "original").expect("the original loads");
        let num = |t: &Table, path: &[Step]| get(t, path).and_then(number).expect("a number");
        let key = |k: &str| Step::Key(k.into());
        let mut moves = 0;
        for seed in 0..200 {
            let mut scene = original.clone();
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let done = translate(&mut scene, &mut rng).expect("a scene to move");
            // What moved, by how much, along which axis.
            let axis = ["x", "y", "z"]
                .iter()
                .position(|a| done.contains(&format!("along {a}")))
                .expect(&done);
            let by = num(
                &scene,
                &[
                    key("sphere"),
                    Step::Index(0),
                    key("center"),
                    Step::Index(axis),
                ],
            ) - num(
                &original,
                &[
                    key("sphere"),
                    Step::Index(0),
                    key("center"),
                    Step::Index(axis),
                ],
            );
            let k = (by.abs() / 0.5).log2().round() as i32;
            assert!((8..=16).contains(&k), "{done}: moved by {by}");
            for (path, lane) in [
                (vec![key("camera"), key("eye")], axis),
                (vec![key("light"), key("position")], axis),
                (vec![key("sphere"), Step::Index(1), key("center")], axis),
            ] {
                let mut p = path.clone();
                p.push(Step::Index(lane));
                let d = num(&scene, &p) - num(&original, &p);
                assert!(
                    (d - by).abs() <= by.abs() * 2f64.powi(-20),
                    "{done}: {p:?} moved by {d}"
                );
                for other in (0..3).filter(|&o| o != lane) {
                    let mut q = path.clone();
                    q.push(Step::Index(other));
                    assert_eq!(num(&scene, &q), num(&original, &q), "{done}: {q:?}");
                }
            }
            for (i, plane_axis) in [(0, 2), (1, 1)] {
                let p = [key("plane"), Step::Index(i), key("offset")];
                let d = num(&scene, &p) - num(&original, &p);
                let want = if plane_axis == axis { by } else { 0.0 };
                assert!(
                    (d - want).abs() <= by.abs() * 2f64.powi(-20),
                    "{done}: plane {i} moved by {d}"
                );
            }
            // Within the extent rule (a radius at least 2^-16 of the
            // largest coordinate) it loads; a move of 2^16 radii may end
            // just past it, and is refused by that rule alone.
            let file = toml::to_string(&scene).expect("TOML");
            match golden::scene::Scene::from_toml(&file, "moved") {
                Ok(_) => moves += 1,
                Err(e) => assert!(k == 16 && e.to_string().contains("extent"), "{done}: {e}"),
            }
        }
        assert!(moves > 150, "{moves} of 200 moved scenes load");
    }
}
