//! Which models of the table ([`crate::design::models`]) this build made,
//! as the build script wrote it, and the refusal of one it did not.

include!(concat!(env!("OUT_DIR"), "/models_built.rs"));

/// Refuses a model class this build did not make, naming the cargo
/// features that make it (the units and the ALU; a [`Design`] says more
/// through [`Design::check`]).
pub(crate) fn require(class: &str) -> Result<(), String> {
    match BUILT.iter().find(|(c, _, _)| *c == class) {
        Some((_, _, true)) => Ok(()),
        Some((_, features, false)) => Err(how_to_build(features)),
        None => Err(format!(
            "{class} is not a model of the table (harness/design/models.rs)"
        )),
    }
}

/// The cargo features that build a model, as a command: this command
/// again, when it is the CLI.
pub(crate) fn how_to_build(features: &[&str]) -> String {
    let features = features.join(",");
    let args: Vec<String> = std::env::args().collect();
    let cli = args.first().and_then(|a| {
        std::path::Path::new(a)
            .file_stem()?
            .to_str()
            .map(String::from)
    });
    let again = match cli.as_deref() {
        Some("rtcosim") => args[1..].join(" "),
        _ => "...".to_string(),
    };
    format!(
        "this build lacks it; build it with the cargo feature{} `{features}`: cargo run --release \
         --features {features} -- {again}",
        if features.contains(',') { "s" } else { "" }
    )
}
