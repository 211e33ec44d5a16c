//! Random scene files: the inputs a user could write, not the ones we did.
//!
//! Scene `index` of seed `seed` comes from its own ChaCha stream, so any one
//! scene can be made again from (seed, index) alone, whatever ran before it
//! or on which thread. The generator writes TOML text, so every scene goes
//! through the same loader and validation as a user's file.
//!
//! What it varies: 0 to 8 spheres and 0 to 6 planes (so, now and then, no
//! object at all), materials, colours, the light and the camera, the stack
//! depth, both float methods, each speed-up, the weight cutoff, the
//! exposure, glass (a sphere's transmission and index of refraction: near
//! 1, below 1 where total internal reflection begins, up to 4). Magnitudes span the whole
//! accepted range: a scene has a scale anywhere from 2^-58 to 2^58 (most
//! often a familiar one), and any value may instead sit exactly on a limit
//! of `golden::scene` or just past it (a sphere's radius is also at least
//! `MIN_RADIUS_OF_EXTENT` of the scene's extent: a radius drawn on
//! MIN_RADIUS sits on the higher of the two bounds, just below it when
//! drawn just below, and a smaller one is lifted to it). A scene with a value past a limit is
//! marked [`Generated::in_limits`] false: it should be refused, and the
//! others mostly accepted. Nothing is filtered: what comes out is what the
//! campaign runs.

use golden::scene::{
    Extent, MAX_COORD, MAX_DEPTH, MAX_DISTANCE, MAX_EXPOSURE, MAX_IOR, MAX_PLANES, MAX_RADIUS,
    MAX_SPHERES, MIN_DISTANCE, MIN_IOR, MIN_RADIUS,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write;

/// The image sides of a generated scene: small, so that thousands of scenes
/// co-simulate in minutes.
pub const SIDES: std::ops::RangeInclusive<u32> = 2..=10;

/// One generated scene file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Generated {
    pub seed: u64,
    pub index: u64,
    /// The scene file.
    pub toml: String,
    /// Whether every value lies inside the documented limits (no value was
    /// put past one on purpose).
    pub in_limits: bool,
}

struct Gen {
    rng: ChaCha8Rng,
    /// A value was put past a limit on purpose.
    past: bool,
    /// The scene's scale: typical coordinates are within it.
    scale: f64,
}

/// Which of [`Gen::magnitude`]'s draws a value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Draw {
    /// Exactly on the lower limit.
    Least,
    /// Just below the lower limit (the scene is marked past a limit).
    BelowLeast,
    /// Anything else.
    Within,
}

/// A point as TOML.
fn vec3(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

/// `v` rounded to f32, as the loader rounds it.
fn f32s(v: [f64; 3]) -> [f32; 3] {
    v.map(|x| x as f32)
}

/// The next f32 above `x` (x > 0), as f64.
fn f32_up(x: f32) -> f64 {
    f64::from(f32::from_bits(x.to_bits() + 1))
}

/// The next f32 below `x` (x > 0), as f64.
fn f32_down(x: f32) -> f64 {
    f64::from(f32::from_bits(x.to_bits() - 1))
}

/// A TOML float that reads back as exactly `x`.
fn num(x: f64) -> String {
    format!("{x:e}")
}

impl Gen {
    fn chance(&mut self, p: f64) -> bool {
        self.rng.random_bool(p)
    }

    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.rng.random_range(lo..=hi)
    }

    fn sign(&mut self) -> f64 {
        if self.chance(0.5) {
            1.0
        } else {
            -1.0
        }
    }

    /// A positive magnitude in `[lo, hi]`: the bounds themselves now and
    /// then, just past them rarely (marking the scene), else `typical()`
    /// clamped into the range.
    fn magnitude(&mut self, lo: f32, hi: f32, typical: f64) -> f64 {
        self.magnitude_drawn(lo, hi, typical).0
    }

    /// [`Gen::magnitude`], and which of its draws it made.
    fn magnitude_drawn(&mut self, lo: f32, hi: f32, typical: f64) -> (f64, Draw) {
        let roll = self.uniform(0.0, 1.0);
        if roll < 0.02 {
            (f64::from(lo), Draw::Least)
        } else if roll < 0.04 {
            (f64::from(hi), Draw::Within)
        } else if roll < 0.045 {
            self.past = true;
            (f32_down(lo), Draw::BelowLeast)
        } else if roll < 0.05 {
            self.past = true;
            (f32_up(hi), Draw::Within)
        } else {
            (typical.clamp(f64::from(lo), f64::from(hi)), Draw::Within)
        }
    }

    /// A coordinate: within the scene's scale, or on or past ±MAX_COORD.
    fn coord(&mut self, centre: f64, spread: f64) -> f64 {
        let roll = self.uniform(0.0, 1.0);
        if roll < 0.015 {
            self.sign() * f64::from(MAX_COORD)
        } else if roll < 0.0175 {
            self.past = true;
            self.sign() * f32_up(MAX_COORD)
        } else {
            let x = centre + self.uniform(-spread, spread) * self.scale;
            x.clamp(-f64::from(MAX_COORD), f64::from(MAX_COORD))
        }
    }

    fn point(&mut self, centre: [f64; 3], spread: f64) -> [f64; 3] {
        centre.map(|c| self.coord(c * self.scale, spread))
    }

    /// A value in [0, 1]: often 0 or 1 exactly, rarely just past.
    fn unit(&mut self) -> f64 {
        let roll = self.uniform(0.0, 1.0);
        if roll < 0.1 {
            0.0
        } else if roll < 0.2 {
            1.0
        } else if roll < 0.202 {
            self.past = true;
            if self.chance(0.5) {
                -f64::from(f32::from_bits(1))
            } else {
                f32_up(1.0)
            }
        } else {
            self.uniform(0.0, 1.0)
        }
    }

    fn colour(&mut self) -> String {
        let c = [self.unit(), self.unit(), self.unit()];
        format!("[{}, {}, {}]", num(c[0]), num(c[1]), num(c[2]))
    }

    fn material(&mut self, out: &mut String) {
        let colour = self.colour();
        let (d, s, r) = (self.unit(), self.unit(), self.unit());
        let _ = writeln!(
            out,
            "color = {colour}\ndiffuse = {}\nspecular = {}\nreflection = {}",
            num(d),
            num(s),
            num(r)
        );
    }

    /// A sphere's glass: its transmission (as any unit value) and its index
    /// relative to the outside, where refraction is delicate: 1 or within
    /// 2^-10 of it, below 1 (total internal reflection past asin(ior)),
    /// familiar glass, up to 4; now and then exactly on a limit or just
    /// past one.
    fn glass(&mut self, out: &mut String) {
        let kt = self.unit();
        let ior = if self.chance(0.01) {
            self.past = true;
            if self.chance(0.5) {
                f32_down(MIN_IOR)
            } else {
                f32_up(MAX_IOR)
            }
        } else {
            match self.rng.random_range(0..6) {
                0 => 1.0,
                1 => 1.0 + self.uniform(-1.0, 1.0) * 2f64.powi(-10),
                2 => self.uniform(f64::from(MIN_IOR), 1.0),
                3 => self.uniform(1.0, 2.5),
                4 => self.uniform(2.5, f64::from(MAX_IOR)),
                _ => f64::from(if self.chance(0.5) { MIN_IOR } else { MAX_IOR }),
            }
        };
        let _ = writeln!(out, "transmission = {}\nior = {}", num(kt), num(ior));
    }

    /// A count in `0..=max`, rarely one past it.
    fn count(&mut self, max: usize) -> usize {
        if self.chance(0.005) {
            self.past = true;
            max + 1
        } else {
            self.rng.random_range(0..=max)
        }
    }
}

/// Scene `index` of the campaign with seed `seed`.
pub fn scene(seed: u64, index: u64) -> Generated {
    // One stream per scene: the seed picks the campaign, the index the
    // stream within it.
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index);
    let scale_exp: f64 = if rng.random_bool(0.6) {
        rng.random_range(3.0..=11.0)
    } else {
        rng.random_range(-58.0..=58.0)
    };
    let mut g = Gen {
        rng,
        past: false,
        scale: scale_exp.exp2(),
    };
    let mut t = String::new();
    let _ = writeln!(t, "# rtcosim fuzz: seed {seed}, scene {index}\n");

    // Camera: behind the scene, looking roughly along +z.
    let width = g.rng.random_range(SIDES);
    let height = g.rng.random_range(SIDES);
    let eye = g.point([0.0, 0.0, -3.0], 1.0);
    let rotation: [f64; 3] = std::array::from_fn(|_| {
        if g.chance(0.2) {
            0.0
        } else if g.chance(0.7) {
            g.uniform(-30.0, 30.0)
        } else {
            g.uniform(-180.0, 180.0)
        }
    });
    let typical_distance = if g.chance(0.6) {
        f64::from(width) * g.uniform(0.3, 3.0)
    } else {
        g.uniform(-60.0, 60.0).exp2()
    };
    let distance = g.magnitude(MIN_DISTANCE, MAX_DISTANCE, typical_distance);
    let _ = writeln!(
        t,
        "[camera]\neye = {}\nrotation = [{}, {}, {}]\ndistance = {}\nwidth = {width}\nheight = {height}\n",
        vec3(eye),
        num(rotation[0]),
        num(rotation[1]),
        num(rotation[2]),
        num(distance)
    );

    let position = g.point([0.0, 2.0, -1.0], 3.0);
    let colour = g.colour();
    let _ = writeln!(
        t,
        "[light]\nposition = {}\ncolor = {colour}\n",
        vec3(position)
    );

    let spheres = g.count(MAX_SPHERES);
    let planes = g.count(MAX_PLANES);
    // Each sphere's centre, radius and material, finished after the last
    // draw (its glass; its radius once the scene's extent is known).
    let mut sphere_draws = Vec::new();
    let mut sphere_text = Vec::new();
    for _ in 0..spheres {
        let centre = g.point([0.0, 0.0, 0.0], 1.5);
        let typical = g.scale * g.uniform(-5.0, 0.0).exp2();
        sphere_draws.push((centre, g.magnitude_drawn(MIN_RADIUS, MAX_RADIUS, typical)));
        let mut st = String::new();
        g.material(&mut st);
        sphere_text.push(st);
    }
    let mut offsets = Vec::new();
    // The camera and the light; the planes and render settings follow in `t`.
    let head = std::mem::take(&mut t);
    for _ in 0..planes {
        let axis = ["x", "y", "z"][g.rng.random_range(0..3)];
        let facing = if g.chance(0.5) { "+" } else { "-" };
        let offset = g.coord(0.0, 3.0);
        offsets.push(offset as f32);
        let _ = writeln!(
            t,
            "[[plane]]\naxis = \"{axis}\"\nfacing = \"{facing}\"\noffset = {}",
            num(offset)
        );
        g.material(&mut t);
        t.push('\n');
    }

    let depth = if g.chance(0.005) {
        g.past = true;
        if g.chance(0.5) {
            0
        } else {
            MAX_DEPTH + 1
        }
    } else {
        g.rng.random_range(1..=MAX_DEPTH)
    };
    let method = |g: &mut Gen| if g.chance(0.5) { "exact" } else { "fast" };
    let (recip, sqrt) = (method(&mut g), method(&mut g));
    let bounding_box = g.chance(0.5);
    // Their preconditions (docs/scenes.md) rarely hold in a random scene:
    // often enough to run them, rarely enough to keep most scenes inside
    // the limits loadable.
    let fast_plane = g.chance(0.03);
    let shadow_shortcut = g.chance(0.03);
    let _ = writeln!(
        t,
        "[render]\nmax_depth = {depth}\nbounding_box = {bounding_box}\nfast_plane = {fast_plane}\n\
         shadow_shortcut = {shadow_shortcut}\nrecip = \"{recip}\"\nsqrt = \"{sqrt}\""
    );
    // The weight cutoff (drawn last, so the scenes of a seed without it
    // are the scenes they were): in a quarter of the scenes, mostly where
    // it refuses some reflections, now and then exactly on a limit (0, 1)
    // or just past one.
    if g.chance(0.25) {
        let cutoff = if g.chance(0.01) {
            g.past = true;
            if g.chance(0.5) {
                -f64::from(f32::MIN_POSITIVE)
            } else {
                f32_up(1.0)
            }
        } else if g.chance(0.05) {
            if g.chance(0.5) {
                0.0
            } else {
                1.0
            }
        } else {
            f64::from(g.rng.random_range(0.0f32..0.7))
        };
        let _ = writeln!(t, "weight_cutoff = {}", num(cutoff));
    }
    // The exposure (drawn after the cutoff, for the same reason): in a
    // quarter of the scenes, mostly a familiar one, now and then exactly on
    // its limit (-MAX_EXPOSURE, the smallest negative f32) or just past one
    // (0, -MAX_EXPOSURE one step further, a positive value).
    if g.chance(0.25) {
        let limit = -f64::from(MAX_EXPOSURE);
        let exposure = if g.chance(0.01) {
            g.past = true;
            match g.rng.random_range(0..3) {
                0 => 0.0,
                1 => -f32_up(MAX_EXPOSURE),
                _ => 1.0,
            }
        } else if g.chance(0.05) {
            if g.chance(0.5) {
                limit
            } else {
                -f64::from(f32::from_bits(1))
            }
        } else {
            f64::from(g.rng.random_range(-4.0f32..-0.05))
        };
        let _ = writeln!(t, "exposure = {}", num(exposure));
    }
    // Glass (drawn last, for the same reason): in a quarter of the scenes,
    // one sphere (now and then each) transparent.
    if spheres > 0 && g.chance(0.25) {
        let one = g.rng.random_range(0..spheres);
        let each = g.chance(0.2);
        for (i, st) in sphere_text.iter_mut().enumerate() {
            if i == one || each {
                g.glass(st);
            }
        }
    }
    // The radii: at least MIN_RADIUS_OF_EXTENT of the scene's extent
    // (docs/scenes.md), which a radius on MIN_RADIUS (or just below it)
    // becomes when the bound is the higher of the two; the others are lifted
    // to it.
    let centres: Vec<[f32; 3]> = sphere_draws.iter().map(|&(c, _)| f32s(c)).collect();
    let least = Extent::of(f32s(eye), &centres, &offsets)
        .least_radius()
        .max(f64::from(MIN_RADIUS));
    // The spheres go in before the planes and the render settings.
    let rest = std::mem::replace(&mut t, head);
    for (&(centre, (radius, draw)), st) in sphere_draws.iter().zip(&sphere_text) {
        let radius = match draw {
            Draw::Least => least,
            Draw::BelowLeast => f32_down(least as f32),
            Draw::Within => radius.max(least),
        };
        let _ = writeln!(
            t,
            "[[sphere]]\ncenter = {}\nradius = {}",
            vec3(centre),
            num(radius)
        );
        t.push_str(st);
        t.push('\n');
    }
    t.push_str(&rest);
    Generated {
        seed,
        index,
        toml: t,
        in_limits: !g.past,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use golden::scene::Scene;

    #[test]
    fn a_scene_depends_only_on_seed_and_index() {
        assert_eq!(scene(7, 42), scene(7, 42));
        assert_ne!(scene(7, 42).toml, scene(7, 43).toml);
        assert_ne!(scene(7, 42).toml, scene(8, 42).toml);
    }

    #[test]
    fn generated_files_are_well_formed_toml_scenes() {
        // Every refusal is a validation refusal (a field and a rule), never
        // a syntax error: the generator writes the format right.
        for i in 0..300 {
            let g = scene(1, i);
            if let Err(e) = Scene::from_toml(&g.toml, "fuzz.toml") {
                assert!(
                    matches!(e, golden::scene::SceneError::Invalid { .. }),
                    "scene {i}: {e}\n{}",
                    g.toml
                );
            }
        }
    }

    #[test]
    fn glass_is_drawn_and_mostly_accepted() {
        // Glass in about a quarter of the scenes with a sphere; many of
        // those inside the limits load (a transparent sphere that another
        // object cuts into, or that holds the eye or the light, is refused
        // by name), and indices below 1 (total internal reflection) occur.
        let (mut with_spheres, mut glass, mut inside, mut accepted, mut below_1) = (0, 0, 0, 0, 0);
        for i in 0..2000 {
            let g = scene(5, i);
            if !g.toml.contains("[[sphere]]") {
                continue;
            }
            with_spheres += 1;
            if !g.toml.contains("transmission = ") {
                continue;
            }
            glass += 1;
            below_1 += usize::from(g.toml.lines().any(|l| {
                l.strip_prefix("ior = ")
                    .and_then(|v| v.parse::<f64>().ok())
                    .is_some_and(|v| v < 1.0)
            }));
            if g.in_limits {
                inside += 1;
                match Scene::from_toml(&g.toml, "fuzz.toml") {
                    Ok(_) => accepted += 1,
                    Err(e) => assert!(
                        e.to_string().contains("transparent") || !e.to_string().contains("ior"),
                        "scene {i}: {e}"
                    ),
                }
            }
        }
        assert!(
            (with_spheres / 6..with_spheres / 3).contains(&glass),
            "{glass} of {with_spheres} with glass"
        );
        // 161 of 352 with seed 5: a coordinate on MAX_COORD lifts every
        // radius to 2^44 (MIN_RADIUS_OF_EXTENT), and spheres that large
        // cut into each other, which glass may not.
        assert!(
            accepted * 5 > inside * 2,
            "{accepted} of {inside} glass scenes accepted"
        );
        assert!(below_1 > 20, "{below_1} with an index below 1");
    }

    #[test]
    fn past_the_limits_is_refused_and_inside_mostly_accepted() {
        // Scenes without glass (glass_is_drawn_and_mostly_accepted has the
        // others: a transparent sphere adds refusals of its own).
        let (mut inside, mut accepted) = (0, 0);
        for i in 0..2000 {
            let g = scene(3, i);
            let ok = Scene::from_toml(&g.toml, "fuzz.toml").is_ok();
            if g.in_limits && g.toml.contains("transmission = ") {
                continue;
            }
            if g.in_limits {
                inside += 1;
                accepted += u32::from(ok);
            } else {
                assert!(!ok, "scene {i} is past a limit but accepted:\n{}", g.toml);
            }
        }
        assert!(
            inside > 1200,
            "{inside} of 2000 inside the limits, without glass"
        );
        assert!(
            f64::from(accepted) >= 0.9 * f64::from(inside),
            "{accepted} of {inside} accepted"
        );
    }
}
