//! The scenes embedded in the binary (`golden/scenes/*.toml`), loaded
//! through the same parser and validation as any file.

/// Every builtin scene: (name, the text of `golden/scenes/<name>.toml`).
const BUILTINS: &[(&str, &str)] = &[
    ("reference", include_str!("../../scenes/reference.toml")),
    ("mirror", include_str!("../../scenes/mirror.toml")),
    ("grazing", include_str!("../../scenes/grazing.toml")),
    ("light_touch", include_str!("../../scenes/light_touch.toml")),
    (
        "parallel_plane",
        include_str!("../../scenes/parallel_plane.toml"),
    ),
    ("box_room", include_str!("../../scenes/box_room.toml")),
    ("overexposed", include_str!("../../scenes/overexposed.toml")),
    ("glass_room", include_str!("../../scenes/glass_room.toml")),
    ("bubble", include_str!("../../scenes/bubble.toml")),
    ("touching", include_str!("../../scenes/touching.toml")),
];

/// The names of [`BUILTINS`], in its order.
pub(super) const NAMES: [&str; BUILTINS.len()] = {
    let mut names = [""; BUILTINS.len()];
    let mut i = 0;
    while i < BUILTINS.len() {
        names[i] = BUILTINS[i].0;
        i += 1;
    }
    names
};

/// The text of the builtin scene `name`.
pub(super) fn text(name: &str) -> Option<&'static str> {
    BUILTINS.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
}
