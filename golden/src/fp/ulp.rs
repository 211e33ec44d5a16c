//! ULP distance between f32 values.
//!
//! Built on `float-cmp`'s [`Ulps`] for the same-sign case, which is a plain
//! difference of bit patterns. Across signs the bit patterns are not ordered
//! (sign-magnitude), so the distance is measured through zero instead.

use float_cmp::Ulps;

/// How far apart two f32 values are, in units in the last place.
///
/// Orders as "closer first": every finite distance is below
/// [`UlpDistance::NanMismatch`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum UlpDistance {
    /// Both are numbers (or infinities) this many representable steps apart,
    /// or both are NaN (distance 0, whatever the payloads).
    Ulps(u32),
    /// One is NaN and the other is not.
    NanMismatch,
}

impl UlpDistance {
    /// True when the distance is at most `max_ulps` (never for a NaN mismatch).
    pub fn within(self, max_ulps: u32) -> bool {
        matches!(self, UlpDistance::Ulps(d) if d <= max_ulps)
    }
}

impl std::fmt::Display for UlpDistance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UlpDistance::Ulps(d) => write!(f, "{d} ulp"),
            UlpDistance::NanMismatch => f.write_str("NaN vs number"),
        }
    }
}

/// ULP distance from `a` to `b`.
///
/// NaN equals NaN; NaN against a number is [`UlpDistance::NanMismatch`].
/// `+0` and `-0` are one step apart, unless `zeros_equal` is set, in which
/// case they are the same point; the step through zero counts the same way
/// for values of opposite signs (so `-min_subnormal` to `+min_subnormal` is 3,
/// or 2 with `zeros_equal`).
pub fn ulp_distance(a: f32, b: f32, zeros_equal: bool) -> UlpDistance {
    match (a.is_nan(), b.is_nan()) {
        (true, true) => return UlpDistance::Ulps(0),
        (true, false) | (false, true) => return UlpDistance::NanMismatch,
        (false, false) => {}
    }
    if a.is_sign_negative() == b.is_sign_negative() {
        return UlpDistance::Ulps(a.ulps(&b).unsigned_abs());
    }
    let through_zero = if zeros_equal { 0 } else { 1 };
    // |x| is at most 0x7F80_0000 steps above zero, so the sum fits in u32.
    let from_zero = |x: f32| x.abs().ulps(&0.0).unsigned_abs();
    UlpDistance::Ulps(from_zero(a) + from_zero(b) + through_zero)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(a: f32, b: f32) -> UlpDistance {
        ulp_distance(a, b, false)
    }

    #[test]
    fn equal_values_are_zero_apart() {
        assert_eq!(d(1.5, 1.5), UlpDistance::Ulps(0));
        assert_eq!(d(-3.0, -3.0), UlpDistance::Ulps(0));
    }

    #[test]
    fn neighbours_are_one_apart_in_both_directions() {
        let x = 1.0f32;
        let up = f32::from_bits(x.to_bits() + 1);
        assert_eq!(d(x, up), UlpDistance::Ulps(1));
        assert_eq!(d(up, x), UlpDistance::Ulps(1));
        assert_eq!(d(f32::MAX, f32::INFINITY), UlpDistance::Ulps(1));
    }

    #[test]
    fn signed_zeros_differ_unless_flagged() {
        assert_eq!(ulp_distance(0.0, -0.0, false), UlpDistance::Ulps(1));
        assert_eq!(ulp_distance(0.0, -0.0, true), UlpDistance::Ulps(0));
    }

    #[test]
    fn distance_wraps_through_zero_across_signs() {
        let tiny = f32::from_bits(1);
        assert_eq!(ulp_distance(tiny, -tiny, false), UlpDistance::Ulps(3));
        assert_eq!(ulp_distance(-tiny, tiny, true), UlpDistance::Ulps(2));
        // Bit patterns 0x3F80_0000 and 0xBF80_0000 are 2^31 apart as raw integers;
        // through zero they are 2 * 0x3F80_0000 + 1 steps apart.
        assert_eq!(d(1.0, -1.0), UlpDistance::Ulps(2 * 0x3F80_0000 + 1));
        assert_eq!(
            d(f32::INFINITY, f32::NEG_INFINITY),
            UlpDistance::Ulps(0xFF00_0001)
        );
    }

    #[test]
    fn nan_equals_nan_whatever_the_payload() {
        let other_nan = f32::from_bits(0xFFC0_1234);
        assert_eq!(d(f32::NAN, other_nan), UlpDistance::Ulps(0));
    }

    #[test]
    fn nan_against_a_number_is_a_mismatch() {
        assert_eq!(d(f32::NAN, 1.0), UlpDistance::NanMismatch);
        assert_eq!(d(f32::INFINITY, f32::NAN), UlpDistance::NanMismatch);
        assert!(!UlpDistance::NanMismatch.within(u32::MAX));
        assert!(UlpDistance::Ulps(u32::MAX) < UlpDistance::NanMismatch);
    }
}
