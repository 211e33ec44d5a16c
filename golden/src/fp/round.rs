//! Mirror of `rtl/fp/fp_round.v`: round to nearest even and pack.

/// Packs `(-1)^sign * sig / 2^26 * 2^(exp - 127)` into binary32, rounding to
/// nearest even. `sig` must be normalized (bit 26 set); `sticky` says that
/// nonzero bits lie below `sig`'s lowest bit. Exponents at or below zero give
/// subnormals (or zero), exponents of 255 and above give infinity.
pub(crate) fn round_pack(sign: bool, exp: i32, sig: u32, sticky: bool) -> u32 {
    debug_assert!(sig >> 26 == 1, "round_pack: sig {sig:#x} not normalized");
    let sign_bit = (sign as u32) << 31;
    if exp >= 255 {
        return sign_bit | 0x7F80_0000;
    }
    let (field, sig, sticky) = if exp > 0 {
        (exp as u32, sig, sticky)
    } else {
        // Denormalize: shift right until the exponent field is zero.
        let shift = (1 - exp) as u32;
        if shift >= 27 {
            (0, 0, true)
        } else {
            (0, sig >> shift, sticky || sig & ((1 << shift) - 1) != 0)
        }
    };
    let mant = sig >> 3;
    let guard = (sig >> 2) & 1 == 1;
    let rest = sig & 3 != 0 || sticky;
    let round_up = guard && (rest || mant & 1 == 1);
    // A mantissa carry runs into the exponent field: the largest subnormal
    // rounds up to the smallest normal, the largest normal to infinity.
    let body = (field << 23) + (mant & 0x7F_FFFF) + round_up as u32;
    sign_bit | body
}
