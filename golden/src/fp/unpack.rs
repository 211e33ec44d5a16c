//! Operand decoding shared by the reciprocal and square-root models; mirrors
//! the input stage of `fp_recip` and `fp_sqrt`.

/// What an operand is, with finite values normalized.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Operand {
    Nan,
    Inf {
        sign: bool,
    },
    Zero {
        sign: bool,
    },
    /// `value = m / 2^23 * 2^(e - 127)` with `m` in `[2^23, 2^24)`. Subnormals
    /// are normalized, so `e` goes down to -22.
    Finite {
        sign: bool,
        e: i32,
        m: u32,
    },
}

pub(crate) fn unpack(bits: u32) -> Operand {
    let sign = bits >> 31 == 1;
    let field = (bits >> 23) & 0xFF;
    let frac = bits & 0x7F_FFFF;
    match (field, frac) {
        (0xFF, 0) => Operand::Inf { sign },
        (0xFF, _) => Operand::Nan,
        (0, 0) => Operand::Zero { sign },
        (0, _) => {
            // Shift the leading one up to bit 23, as the RTL's leading-zero count does.
            let shift = frac.leading_zeros() - 8;
            Operand::Finite {
                sign,
                e: 1 - shift as i32,
                m: frac << shift,
            }
        }
        _ => Operand::Finite {
            sign,
            e: field as i32,
            m: frac | 1 << 23,
        },
    }
}
