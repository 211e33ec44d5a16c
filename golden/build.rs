//! Generates `$OUT_DIR/isa.rs` from `rtl/pp/isa.vh`, the single source of
//! truth for the pixel processor's opcodes, register addresses and FSM
//! states. A malformed line, a duplicate name or a duplicate code stops the
//! build with `file:line: what is wrong`.

use std::path::PathBuf;
use std::{env, fs, process};

#[path = "src/micro/isa_parse.rs"]
#[allow(dead_code)]
mod isa_parse;

fn main() {
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let header = manifest.join("../rtl/pp/isa.vh");
    println!("cargo:rerun-if-changed={}", header.display());
    let header = header.canonicalize().unwrap_or(header);
    println!("cargo:rerun-if-changed=src/micro/isa_parse.rs");
    let origin = header.display().to_string();
    let text = match fs::read_to_string(&header) {
        Ok(t) => t,
        Err(e) => fail(&format!("{origin}: cannot read the ISA header: {e}")),
    };
    let isa = match isa_parse::parse(&text, &origin) {
        Ok(isa) => isa,
        Err(e) => fail(&e),
    };
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("set by cargo")).join("isa.rs");
    if let Err(e) = fs::write(&out, isa_parse::generate(&isa, "rtl/pp/isa.vh")) {
        fail(&format!("{}: {e}", out.display()));
    }
}

fn fail(msg: &str) -> ! {
    eprintln!("error: {msg}");
    println!("cargo:warning={msg}");
    process::exit(1);
}
