//! Faults injected on purpose, to prove that a checker catches them: the
//! same fault in the RTL (its fault port) and in the micro-op model.

use super::isa;
use std::str::FromStr;

/// A fault to inject: a self-test of a checker. Every register-file write
/// made in controller state `state` has its lane x XORed with `xor`
/// (written and traced alike; the controller's branches in that cycle see
/// the value before the XOR). The RTL takes it through its fault port, the
/// micro-op model through [`Processor::with_fault`](super::Processor::with_fault),
/// with the same effect, bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fault {
    /// Controller state id (`rtl/pp/isa.vh`) whose writes are hit.
    pub state: u16,
    /// Nonzero mask XORed into lane x of those writes.
    pub xor: u32,
}

/// A number in decimal, or in hex with a `0x` prefix.
pub fn parse_number(s: &str) -> Option<u64> {
    let s = s.trim();
    match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(hex) if !hex.starts_with('+') => u64::from_str_radix(hex, 16).ok(),
        Some(_) => None,
        None => s.parse().ok(),
    }
}

impl FromStr for Fault {
    type Err = String;

    /// `STATE:XOR`: a controller state of rtl/pp/isa.vh by name (any case,
    /// an `ISA_ST_` prefix allowed) or number, and a nonzero 32-bit mask in
    /// hex (`0x400`) or decimal.
    fn from_str(s: &str) -> Result<Fault, String> {
        let (state_arg, xor_arg) = s
            .split_once(':')
            .ok_or_else(|| format!("expected STATE:XOR, e.g. PRI_HALF:0x400; got {s:?}"))?;
        let state_arg = state_arg.trim();
        let state = match parse_number(state_arg) {
            Some(n) => u16::try_from(n)
                .ok()
                .filter(|&id| isa::state_name(id).is_some()),
            None => {
                let upper = state_arg.to_ascii_uppercase();
                isa::state_code(upper.strip_prefix("ISA_ST_").unwrap_or(&upper))
            }
        }
        .ok_or_else(|| {
            let names: Vec<&str> = isa::STATES.iter().map(|&(name, _)| name).collect();
            format!(
                "{state_arg:?} is not a controller state of rtl/pp/isa.vh; the states: {}",
                names.join(", ")
            )
        })?;
        let xor = parse_number(xor_arg)
            .and_then(|n| u32::try_from(n).ok())
            .filter(|&x| x != 0)
            .ok_or_else(|| {
                format!(
                    "the XOR mask {:?} is not a nonzero 32-bit number (hex 0x400 or decimal 1024)",
                    xor_arg.trim()
                )
            })?;
        Ok(Fault { state, xor })
    }
}

impl std::fmt::Display for Fault {
    /// `STATE:XOR` as [`Fault::from_str`] reads it: `PRI_HALF:0x400`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match isa::state_name(self.state) {
            Some(name) => write!(f, "{name}:{:#x}", self.xor),
            None => write!(f, "{}:{:#x}", self.state, self.xor),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fault_reads_back_from_its_text() {
        for text in ["PRI_HALF:0x400", "isa_st_norm_roots:2048", "11:0x80000000"] {
            let fault: Fault = text.parse().expect("parses");
            assert_eq!(fault.to_string().parse::<Fault>(), Ok(fault), "{text}");
        }
        let f: Fault = "pri_half:1024".parse().expect("parses");
        assert_eq!(f.to_string(), "PRI_HALF:0x400");
        assert!("PRI_HALF:0".parse::<Fault>().is_err());
        assert!("NOT_A_STATE:1".parse::<Fault>().is_err());
        assert!("PRI_HALF".parse::<Fault>().is_err());
    }
}
