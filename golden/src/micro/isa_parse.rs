//! The parser of `rtl/pp/isa.vh`, shared by `golden/build.rs` (which turns
//! the header into `isa.rs`) and the drift-guard test (which re-reads the
//! header and compares it with what was compiled in). Standard library only:
//! build scripts cannot use the crate they build.
//!
//! The grammar is in the header's banner. Every error names `origin:line`.

use std::collections::BTreeMap;

/// The four kinds of `define.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Kind {
    /// `ISA_OP_`: ALU opcode.
    Op,
    /// `ISA_REG_`: register-file address.
    Reg,
    /// `ISA_ST_`: controller FSM state id.
    St,
    /// `ISA_DIM_`: a width, count or stride (not a code, may repeat).
    Dim,
}

impl Kind {
    pub const ALL: [Kind; 4] = [Kind::Op, Kind::Reg, Kind::St, Kind::Dim];

    /// The macro prefix, e.g. "ISA_OP_".
    pub const fn prefix(self) -> &'static str {
        match self {
            Kind::Op => "ISA_OP_",
            Kind::Reg => "ISA_REG_",
            Kind::St => "ISA_ST_",
            Kind::Dim => "ISA_DIM_",
        }
    }
}

/// One `define.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Def {
    pub kind: Kind,
    /// The name after the prefix, e.g. "ADD" for `ISA_OP_ADD`.
    pub name: String,
    pub value: u32,
    /// 1-based line in the header.
    pub line: usize,
    /// The trailing `//` comment, or else the comment lines just above.
    pub doc: String,
}

/// A register array: `<group>0...` registers repeated `count` times.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Group {
    pub name: String,
    pub count: u32,
    pub stride: u32,
}

/// The parsed header.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Isa {
    /// Every define in file order.
    pub defs: Vec<Def>,
    pub groups: Vec<Group>,
}

impl Isa {
    /// The defines of one kind, in file order.
    pub fn of(&self, kind: Kind) -> impl Iterator<Item = &Def> {
        self.defs.iter().filter(move |d| d.kind == kind)
    }

    /// The value of `ISA_DIM_<name>`.
    pub fn dim(&self, name: &str) -> Option<u32> {
        self.of(Kind::Dim).find(|d| d.name == name).map(|d| d.value)
    }

    /// Every register address with a name, array elements expanded
    /// (`SPH0_C` -> `SPH0_C`, `SPH1_C`, ...), sorted by address.
    pub fn register_names(&self) -> Vec<(String, u32)> {
        let mut out = Vec::new();
        for d in self.of(Kind::Reg) {
            match self.group_of(&d.name) {
                Some((g, rest)) => {
                    for k in 0..g.count {
                        out.push((format!("{}{k}{rest}", g.name), d.value + k * g.stride));
                    }
                }
                None => out.push((d.name.clone(), d.value)),
            }
        }
        out.sort_by_key(|(_, code)| *code);
        out
    }

    /// The group a register name is element 0 of, and the rest of the name.
    fn group_of<'a>(&'a self, name: &'a str) -> Option<(&'a Group, &'a str)> {
        self.groups.iter().find_map(|g| {
            let rest = name.strip_prefix(g.name.as_str())?.strip_prefix('0')?;
            (rest.is_empty() || rest.starts_with('_')).then_some((g, rest))
        })
    }
}

/// Parses the header text. `origin` names the file in errors.
pub fn parse(text: &str, origin: &str) -> Result<Isa, String> {
    let err = |line: usize, msg: String| format!("{origin}:{line}: {msg}");
    let mut defs: Vec<Def> = Vec::new();
    let mut guard = 0; // 0: expect `ifndef, 1: expect `define ISA_VH, 2: body, 3: after `endif
    let mut pending_doc: Vec<String> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let (code, comment) = match raw.find("//") {
            Some(at) => (&raw[..at], Some(raw[at + 2..].trim())),
            None => (raw, None),
        };
        let words: Vec<&str> = code.split_whitespace().collect();
        if words.is_empty() {
            match comment {
                Some(c) => pending_doc.push(c.to_string()),
                None => pending_doc.clear(),
            }
            continue;
        }
        if guard == 3 {
            return Err(err(line, format!("text after `endif: {:?}", raw.trim())));
        }
        match (guard, words.as_slice()) {
            (0, ["`ifndef", "ISA_VH"]) => guard = 1,
            (0, _) => {
                return Err(err(
                    line,
                    format!(
                        "expected the include guard `ifndef ISA_VH, got {:?}",
                        raw.trim()
                    ),
                ))
            }
            (1, ["`define", "ISA_VH"]) => guard = 2,
            (1, _) => {
                return Err(err(
                    line,
                    format!(
                        "expected `define ISA_VH after `ifndef ISA_VH, got {:?}",
                        raw.trim()
                    ),
                ))
            }
            (2, ["`endif"]) => guard = 3,
            (2, ["`define", macro_name, value]) => {
                let (kind, name) = Kind::ALL
                    .iter()
                    .find_map(|&k| macro_name.strip_prefix(k.prefix()).map(|n| (k, n)))
                    .ok_or_else(|| {
                        err(
                            line,
                            format!(
                                "`{macro_name}` is none of ISA_OP_, ISA_REG_, ISA_ST_, ISA_DIM_"
                            ),
                        )
                    })?;
                let valid_name = name.starts_with(|c: char| c.is_ascii_uppercase())
                    && name
                        .chars()
                        .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_');
                if !valid_name {
                    return Err(err(
                        line,
                        format!("`{macro_name}`: the name must match [A-Z][A-Z0-9_]*"),
                    ));
                }
                let value = value
                    .parse::<u32>()
                    .ok()
                    .filter(|_| value.bytes().all(|b| b.is_ascii_digit()))
                    .ok_or_else(|| {
                        err(
                            line,
                            format!("`{macro_name}`: expected a decimal number, got {value:?}"),
                        )
                    })?;
                if let Some(first) = defs.iter().find(|d| d.kind == kind && d.name == name) {
                    return Err(err(
                        line,
                        format!(
                            "duplicate name `{macro_name}` (first defined on line {})",
                            first.line
                        ),
                    ));
                }
                let doc = match comment {
                    Some(c) if !c.is_empty() => c.to_string(),
                    _ => pending_doc.join(" "),
                };
                pending_doc.clear();
                defs.push(Def {
                    kind,
                    name: name.to_string(),
                    value,
                    line,
                    doc,
                });
            }
            (2, _) => {
                return Err(err(
                    line,
                    format!(
                        "expected `define ISA_<KIND>_<NAME> <decimal> or `endif, got {:?}",
                        raw.trim()
                    ),
                ))
            }
            _ => unreachable!("guard state {guard}"),
        }
    }
    if guard != 3 {
        let last = text.lines().count();
        return Err(err(
            last,
            "missing the include guard (`ifndef ISA_VH ... `endif)".to_string(),
        ));
    }
    let mut isa = Isa {
        defs,
        groups: Vec::new(),
    };
    check_widths(&isa, &err)?;
    isa.groups = groups(&isa, &err)?;
    check_codes(&isa, &err)?;
    Ok(isa)
}

type ErrFn<'a> = dyn Fn(usize, String) -> String + 'a;

fn dim_def<'a>(isa: &'a Isa, name: &str) -> Option<&'a Def> {
    isa.of(Kind::Dim).find(|d| d.name == name)
}

fn check_widths(isa: &Isa, err: &ErrFn) -> Result<(), String> {
    for (kind, dim) in [
        (Kind::Op, "OP_BITS"),
        (Kind::Reg, "REG_BITS"),
        (Kind::St, "ST_BITS"),
    ] {
        let bits =
            dim_def(isa, dim).ok_or_else(|| err(1, format!("missing `define ISA_DIM_{dim}")))?;
        let max_bits = if kind == Kind::St { 16 } else { 8 };
        if bits.value == 0 || bits.value > max_bits {
            return Err(err(
                bits.line,
                format!("ISA_DIM_{dim} must be 1..={max_bits}, got {}", bits.value),
            ));
        }
        for d in isa.of(kind) {
            if d.value >> bits.value != 0 {
                return Err(err(
                    d.line,
                    format!(
                        "`{}{}` = {} does not fit in ISA_DIM_{dim} = {} bits",
                        kind.prefix(),
                        d.name,
                        d.value,
                        bits.value
                    ),
                ));
            }
        }
    }
    Ok(())
}

fn groups(isa: &Isa, err: &ErrFn) -> Result<Vec<Group>, String> {
    let mut groups = Vec::new();
    for d in isa.of(Kind::Dim) {
        let Some(g) = d.name.strip_suffix("_COUNT") else {
            continue;
        };
        let stride = dim_def(isa, &format!("{g}_STRIDE")).ok_or_else(|| {
            err(
                d.line,
                format!("ISA_DIM_{} has no matching ISA_DIM_{g}_STRIDE", d.name),
            )
        })?;
        if d.value == 0 || stride.value == 0 {
            return Err(err(
                d.line,
                format!("register array {g}: count and stride must be > 0"),
            ));
        }
        groups.push(Group {
            name: g.to_string(),
            count: d.value,
            stride: stride.value,
        });
    }
    for d in isa.of(Kind::Dim) {
        if let Some(g) = d.name.strip_suffix("_STRIDE") {
            if !groups.iter().any(|gr| gr.name == g) {
                return Err(err(
                    d.line,
                    format!("ISA_DIM_{} has no matching ISA_DIM_{g}_COUNT", d.name),
                ));
            }
        }
    }
    for g in &groups {
        let probe = Isa {
            defs: Vec::new(),
            groups: vec![g.clone()],
        };
        if !isa.of(Kind::Reg).any(|d| probe.group_of(&d.name).is_some()) {
            let line = dim_def(isa, &format!("{}_COUNT", g.name)).map_or(1, |d| d.line);
            return Err(err(
                line,
                format!(
                    "register array {} has no element-0 register (ISA_REG_{}0...)",
                    g.name, g.name
                ),
            ));
        }
    }
    Ok(groups)
}

fn check_codes(isa: &Isa, err: &ErrFn) -> Result<(), String> {
    for kind in [Kind::Op, Kind::St] {
        let mut seen: BTreeMap<u32, &Def> = BTreeMap::new();
        for d in isa.of(kind) {
            if let Some(first) = seen.insert(d.value, d) {
                return Err(err(
                    d.line,
                    format!(
                        "duplicate code {}: `{}{}` and `{}{}` (line {})",
                        d.value,
                        kind.prefix(),
                        d.name,
                        kind.prefix(),
                        first.name,
                        first.line
                    ),
                ));
            }
        }
    }
    // Registers: every element of every array counts.
    let reg_bits = isa.dim("REG_BITS").unwrap_or(8);
    let mut seen: BTreeMap<u32, (String, usize)> = BTreeMap::new();
    for d in isa.of(Kind::Reg) {
        let elements: Vec<(String, u32)> = match isa.group_of(&d.name) {
            Some((g, rest)) => (0..g.count)
                .map(|k| (format!("{}{k}{rest}", g.name), d.value + k * g.stride))
                .collect(),
            None => vec![(d.name.clone(), d.value)],
        };
        for (name, code) in elements {
            if code >> reg_bits != 0 {
                return Err(err(
                    d.line,
                    format!("register {name} = {code} does not fit in {reg_bits} bits"),
                ));
            }
            if let Some((first, line)) = seen.insert(code, (name.clone(), d.line)) {
                return Err(err(
                    d.line,
                    format!("duplicate code {code}: registers {name} and {first} (line {line})"),
                ));
            }
        }
    }
    Ok(())
}

/// The Rust source `build.rs` writes to `$OUT_DIR/isa.rs`.
pub fn generate(isa: &Isa, origin: &str) -> String {
    let mut s = String::new();
    s += &format!("// Generated by golden/build.rs from {origin}. Do not edit.\n\n");
    let doc = |d: &Def| {
        if d.doc.is_empty() {
            format!(
                "    /// `{}{}` (line {}).\n",
                d.kind.prefix(),
                d.name,
                d.line
            )
        } else {
            format!(
                "    /// {} (`{}{}`, line {}).\n",
                markdown_escape(&d.doc),
                d.kind.prefix(),
                d.name,
                d.line
            )
        }
    };
    let module = |s: &mut String, name: &str, what: &str, kind: Kind, ty: &str| {
        *s += &format!("/// {what}\npub mod {name} {{\n");
        for d in isa.of(kind) {
            *s += &doc(d);
            *s += &format!("    pub const {}: {ty} = {};\n", d.name, d.value);
        }
        *s += "}\n\n";
    };
    module(&mut s, "op", "ALU opcodes (`ISA_OP_*`).", Kind::Op, "u8");
    module(
        &mut s,
        "reg",
        "Register-file addresses (`ISA_REG_*`); array elements other than 0 \
         are reached with the `dim` strides.",
        Kind::Reg,
        "u8",
    );
    module(
        &mut s,
        "state",
        "Controller FSM state ids (`ISA_ST_*`).",
        Kind::St,
        "u16",
    );
    module(
        &mut s,
        "dim",
        "Widths, counts and strides (`ISA_DIM_*`).",
        Kind::Dim,
        "usize",
    );
    // The same codes typed, for the model's instructions: `Reg::EYE` is
    // `Reg(reg::EYE)`.
    let typed = |s: &mut String, ty: &str, module: &str, kind: Kind| {
        *s += &format!("impl {ty} {{\n");
        for d in isa.of(kind) {
            *s += &doc(d);
            *s += &format!("    pub const {0}: {ty} = {ty}({module}::{0});\n", d.name);
        }
        *s += "}\n\n";
    };
    typed(&mut s, "Reg", "reg", Kind::Reg);
    typed(&mut s, "State", "state", Kind::St);
    let table = |s: &mut String, what: &str, name: &str, ty: &str, rows: Vec<(String, u32)>| {
        *s += &format!("/// {what}\npub const {name}: &[(&str, {ty})] = &[\n");
        for (n, v) in rows {
            *s += &format!("    ({n:?}, {v}),\n");
        }
        *s += "];\n\n";
    };
    let rows = |kind: Kind| -> Vec<(String, u32)> {
        isa.of(kind).map(|d| (d.name.clone(), d.value)).collect()
    };
    let in_order = "Every (name, code), in header order.";
    table(&mut s, in_order, "OPS", "u8", rows(Kind::Op));
    table(&mut s, in_order, "STATES", "u16", rows(Kind::St));
    table(&mut s, in_order, "DIMS", "usize", rows(Kind::Dim));
    table(
        &mut s,
        "Every named register address, array elements expanded, by address.",
        "REGISTERS",
        "u8",
        isa.register_names(),
    );
    s
}

/// The header's comment as plain Markdown text for a doc comment.
fn markdown_escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '`' => out.push('\''),
            '<' | '>' | '[' | ']' | '*' | '_' => {
                out.push('\\');
                out.push(c);
            }
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "`ifndef ISA_VH\n`define ISA_VH\n\
        `define ISA_DIM_OP_BITS 4\n`define ISA_DIM_REG_BITS 4\n`define ISA_DIM_ST_BITS 4\n";

    fn header(body: &str) -> String {
        format!("{HEAD}{body}`endif\n")
    }

    #[test]
    fn a_small_header_parses_with_docs_and_expanded_arrays() {
        let text = header(
            "// Adds.\n`define ISA_OP_ADD 1\n`define ISA_OP_SUB 2 // Subtracts.\n\
             `define ISA_DIM_A_COUNT 2\n`define ISA_DIM_A_STRIDE 2\n\
             `define ISA_REG_A0_X 4\n`define ISA_REG_A0_Y 5\n`define ISA_REG_Z 0\n\
             `define ISA_ST_GO 3\n",
        );
        let isa = parse(&text, "t.vh").expect("valid");
        let ops: Vec<_> = isa
            .of(Kind::Op)
            .map(|d| (&*d.name, d.value, &*d.doc))
            .collect();
        assert_eq!(ops, [("ADD", 1, "Adds."), ("SUB", 2, "Subtracts.")]);
        let regs = isa.register_names();
        let names: Vec<_> = regs.iter().map(|(n, c)| (n.as_str(), *c)).collect();
        assert_eq!(
            names,
            [("Z", 0), ("A0_X", 4), ("A0_Y", 5), ("A1_X", 6), ("A1_Y", 7)]
        );
    }

    fn error_of(body: &str) -> String {
        parse(&header(body), "isa.vh").expect_err("must be refused")
    }

    #[test]
    fn malformed_lines_are_refused_with_file_and_line() {
        let e = error_of("`define ISA_OP_ADD 0x1\n");
        assert!(e.starts_with("isa.vh:6:") && e.contains("decimal"), "{e}");
        let e = error_of("`define ISA_FOO_ADD 1\n");
        assert!(e.starts_with("isa.vh:6:") && e.contains("none of"), "{e}");
        let e = error_of("`define ISA_OP_add 1\n");
        assert!(e.starts_with("isa.vh:6:"), "{e}");
        let e = error_of("wire x;\n");
        assert!(e.starts_with("isa.vh:6:"), "{e}");
        let e = error_of("`define ISA_OP_ADD 1 2\n");
        assert!(e.starts_with("isa.vh:6:"), "{e}");
        let e = parse("`define ISA_OP_ADD 1\n", "isa.vh").expect_err("no guard");
        assert!(e.starts_with("isa.vh:1:") && e.contains("guard"), "{e}");
        let e = parse(HEAD, "isa.vh").expect_err("no `endif");
        assert!(e.contains("guard"), "{e}");
    }

    #[test]
    fn duplicate_names_and_codes_are_refused() {
        let e = error_of("`define ISA_OP_ADD 1\n`define ISA_OP_ADD 2\n");
        assert!(
            e.starts_with("isa.vh:7:") && e.contains("duplicate name"),
            "{e}"
        );
        let e = error_of("`define ISA_OP_ADD 1\n`define ISA_OP_SUB 1\n");
        assert!(
            e.starts_with("isa.vh:7:") && e.contains("duplicate code 1"),
            "{e}"
        );
        let e = error_of("`define ISA_ST_A 1\n`define ISA_ST_B 1\n");
        assert!(e.contains("duplicate code"), "{e}");
        // The same code in different kinds is fine.
        parse(&header("`define ISA_OP_A 1\n`define ISA_ST_A 1\n"), "x").expect("valid");
        // An array element colliding with a plain register.
        let e = error_of(
            "`define ISA_DIM_A_COUNT 2\n`define ISA_DIM_A_STRIDE 1\n\
             `define ISA_REG_A0 3\n`define ISA_REG_B 4\n",
        );
        assert!(e.contains("duplicate code 4") && e.contains("A1"), "{e}");
    }

    #[test]
    fn codes_must_fit_their_widths() {
        let e = error_of("`define ISA_OP_BIG 16\n");
        assert!(e.starts_with("isa.vh:6:") && e.contains("4 bits"), "{e}");
        let e = error_of(
            "`define ISA_DIM_A_COUNT 9\n`define ISA_DIM_A_STRIDE 2\n`define ISA_REG_A0 0\n",
        );
        assert!(e.contains("does not fit"), "{e}");
    }
}
