//! The constants the hardware needs precomputed, derived from the scene
//! once, here, in f32, so that no two consumers can round them differently.

use super::types::{Camera, Plane, Sphere, Vec3f};

/// Constants derived from the scene, computed once here in f32 and shared by
/// every model and the RTL loader, so that none can round them differently.
#[derive(Debug, Clone, PartialEq)]
pub struct Derived {
    /// cos of the camera rotation angles: computed in f64, rounded to f32.
    pub cos: Vec3f,
    /// sin of the camera rotation angles: computed in f64, rounded to f32.
    pub sin: Vec3f,
    /// width / 2 (exact in f32).
    pub half_width: f32,
    /// height / 2 (exact in f32).
    pub half_height: f32,
    /// 1/r per sphere: `1.0f64 / r` rounded to f32 (which is the correctly
    /// rounded f32 reciprocal).
    pub inv_radius: Vec<f32>,
    /// r*r per sphere, in f32.
    pub radius_sq: Vec<f32>,
    /// 1/ior per sphere: `1.0f64 / ior` rounded to f32, the index ratio
    /// `eta` of the way into the sphere (refraction).
    pub inv_ior: Vec<f32>,
    /// `facing * unit(axis)` per plane (the other components are +0.0).
    pub plane_normal: Vec<Vec3f>,
    /// Lower corner of the axis-aligned box around all spheres: the exact
    /// `center - radius`, rounded down to f32 so the box never cuts a sphere.
    /// With no spheres the box is the single point at the origin (a ray that
    /// hits it then tests zero spheres, so the image does not change).
    pub bbox_min: Vec3f,
    /// Upper corner: the exact `center + radius`, rounded up to f32.
    pub bbox_max: Vec3f,
}

impl Derived {
    /// The constants of a validated camera and objects.
    pub(super) fn compute(camera: &Camera, spheres: &[Sphere], planes: &[Plane]) -> Derived {
        let angle = |i: usize| f64::from(camera.rotation_deg[i]).to_radians();
        let cos = [0, 1, 2].map(|i| angle(i).cos() as f32);
        let sin = [0, 1, 2].map(|i| angle(i).sin() as f32);
        let (bbox_min, bbox_max) = if spheres.is_empty() {
            ([0.0; 3], [0.0; 3])
        } else {
            let mut lo = [f32::INFINITY; 3];
            let mut hi = [f32::NEG_INFINITY; 3];
            for s in spheres {
                for i in 0..3 {
                    let c = f64::from(s.center[i]);
                    let r = f64::from(s.radius);
                    lo[i] = lo[i].min(round_down(c - r));
                    hi[i] = hi[i].max(round_up(c + r));
                }
            }
            (lo, hi)
        };
        Derived {
            cos,
            sin,
            half_width: camera.width as f32 / 2.0,
            half_height: camera.height as f32 / 2.0,
            inv_radius: spheres
                .iter()
                .map(|s| (1.0f64 / f64::from(s.radius)) as f32)
                .collect(),
            radius_sq: spheres.iter().map(|s| s.radius * s.radius).collect(),
            inv_ior: spheres
                .iter()
                .map(|s| (1.0f64 / f64::from(s.material.ior)) as f32)
                .collect(),
            plane_normal: planes.iter().map(Plane::normal).collect(),
            bbox_min,
            bbox_max,
        }
    }
}

/// The largest f32 <= x (x finite and within the f32 range).
pub(crate) fn round_down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x {
        next_toward_neg_inf(y)
    } else {
        y
    }
}

/// The smallest f32 >= x (x finite and within the f32 range).
pub(crate) fn round_up(x: f64) -> f32 {
    -round_down(-x)
}

fn next_toward_neg_inf(y: f32) -> f32 {
    if y == 0.0 {
        -f32::from_bits(1)
    } else if y > 0.0 {
        f32::from_bits(y.to_bits() - 1)
    } else {
        f32::from_bits(y.to_bits() + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_outwards_brackets_the_exact_value() {
        let x = 0.1f64;
        assert!(f64::from(round_down(x)) <= x && f64::from(round_up(x)) >= x);
        assert_eq!(round_up(x).to_bits(), round_down(x).to_bits() + 1);
        // Exact values stay put, on both sides of zero.
        assert_eq!((round_down(-2.0), round_up(-2.0)), (-2.0, -2.0));
        assert_eq!((round_down(0.0), round_up(0.0)), (0.0, 0.0));
        // Below the smallest subnormal, towards zero from either side.
        assert_eq!(round_down(1e-50), 0.0);
        assert_eq!(round_up(1e-50), f32::from_bits(1));
        assert_eq!(round_down(-1e-50), -f32::from_bits(1));
    }
}
