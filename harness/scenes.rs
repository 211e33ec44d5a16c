//! Scenes as a user names them: a builtin's name or a scene file, and the
//! overrides every command takes (image size, float methods).

use golden::fp::Method;
use golden::scene::{Scene, SceneError};
use std::path::Path;

/// Why a named scene cannot be had.
#[derive(Debug, thiserror::Error)]
pub enum SceneArgError {
    #[error("{arg}: no such scene file, nor a builtin scene (builtins: {})", Scene::builtin_names().join(", "))]
    Unknown { arg: String },
    #[error(transparent)]
    Scene(#[from] SceneError),
}

/// The scene file `arg` if one exists, else the builtin scene of that name.
pub fn load(arg: &str) -> Result<Scene, SceneArgError> {
    let path = Path::new(arg);
    if path.exists() {
        return Ok(Scene::load(path)?);
    }
    Scene::builtin(arg).ok_or_else(|| SceneArgError::Unknown {
        arg: arg.to_string(),
    })
}

/// `scene` with other reciprocal and square-root methods, validated again
/// (`origin` names the override in errors).
pub fn with_methods(
    scene: &Scene,
    recip: Method,
    sqrt: Method,
    origin: &str,
) -> Result<Scene, SceneError> {
    let mut render = scene.render;
    render.recip = recip;
    render.sqrt = sqrt;
    scene.with_render(render, origin)
}

/// What a command line may change in a scene.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Overrides {
    /// Image size (width, height); the field of view is kept.
    pub size: Option<(u32, u32)>,
    pub recip: Option<Method>,
    pub sqrt: Option<Method>,
}

/// The scene `arg` names, with `overrides` applied; `flags` names each
/// override in errors (`--size`, `--recip/--sqrt`).
pub fn load_with(arg: &str, overrides: Overrides) -> Result<Scene, SceneArgError> {
    let mut scene = load(arg)?;
    if let Some((width, height)) = overrides.size {
        scene = scene.resized(width, height, "--size")?;
    }
    let recip = overrides.recip.unwrap_or(scene.render.recip);
    let sqrt = overrides.sqrt.unwrap_or(scene.render.sqrt);
    if (recip, sqrt) != (scene.render.recip, scene.render.sqrt) {
        scene = with_methods(&scene, recip, sqrt, "--recip/--sqrt")?;
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unknown_scene_name_lists_the_builtins() {
        let err = load("no-such-scene").expect_err("neither a file nor a builtin");
        let msg = err.to_string();
        assert!(
            msg.contains("no-such-scene") && msg.contains("mirror"),
            "{msg}"
        );
    }

    #[test]
    fn overrides_change_size_and_methods_and_nothing_else() {
        let base = load("reference").expect("builtin");
        let scene = load_with(
            "reference",
            Overrides {
                size: Some((80, 60)),
                recip: Some(Method::Fast),
                sqrt: None,
            },
        )
        .expect("valid");
        assert_eq!((scene.camera.width, scene.camera.height), (80, 60));
        assert_eq!(
            (scene.render.recip, scene.render.sqrt),
            (Method::Fast, base.render.sqrt)
        );
        assert_eq!(scene.spheres, base.spheres);
        assert_eq!(
            load_with("reference", Overrides::default()).expect("valid"),
            base
        );
    }
}
