//! From options to what a picture is made of: the loaded scene (the built-in one, or a
//! file's), the frame settings (camera, lights, tiers, post) and the PBR environment. No GL:
//! the session, the window, the reference renderer and the tools all start here, so
//! `--keys` headless and the keys in a window give the same view.
use crate::error::Result;
use crate::options::Options;
use crate::scene::lod::clusters::Clusters;
use crate::scene::model::material::TextureOptions;
use crate::scene::Scene;
use crate::scene::{LoadOptions, ProgressFn};
use glview_render::view::settings::{adjust_scene, env_request};

/// Loads the model (or the built-in scene). Files that take a while report their progress
/// (bytes scanned, then the triangle count) to the installed reporter ([`crate::progress`]).
pub fn load_scene(args: &Options) -> Result<Scene> {
    load_scene_with(args, true)
}

/// [`load_scene`], with the warnings printed or not (`--check` lists them in its report).
pub fn load_scene_with(args: &Options, print_warnings: bool) -> Result<Scene> {
    load_scene_prepared_with(args, print_warnings).map(|(scene, _)| scene)
}

/// As [`load_scene`], with the meshes' clusters when the mesh cache had or built them
/// ([`crate::scene::load_prepared`]).
pub fn load_scene_prepared(args: &Options) -> Result<(Scene, Option<Vec<Option<Clusters>>>)> {
    load_scene_prepared_with(args, true)
}

fn load_scene_prepared_with(
    args: &Options,
    print_warnings: bool,
) -> Result<(Scene, Option<Vec<Option<Clusters>>>)> {
    let size = args
        .load
        .model
        .as_ref()
        .and_then(|p| std::fs::metadata(p).ok())
        .map_or(0, |m| m.len());
    // About 1 s of loading on a slow machine: below that a bar would only flicker.
    let bar: Option<std::sync::Arc<dyn crate::progress::Task>> = (size > 16 << 20)
        .then(|| {
            let name = args
                .load
                .model
                .as_ref()
                .map(|p| p.display().to_string())
                .unwrap_or_default();
            crate::progress::start(
                &format!("loading {name}"),
                size,
                crate::progress::Unit::Bytes,
            )
        })
        .flatten()
        .map(std::sync::Arc::from);
    let progress = bar
        .clone()
        .map(|b| std::sync::Arc::new(move |done: u64, _total: u64| b.set(done)) as ProgressFn);
    let opts = load_options(args, progress);
    let scene = match &args.load.model {
        Some(path) => crate::scene::load_prepared(path, &opts),
        None => crate::scene::builtin::load(&opts).map(|s| (s, None)),
    };
    if let Some(b) = &bar {
        match &scene {
            Ok((s, _)) => b.finish(Some(format!("loaded {} triangles", s.triangle_count()))),
            Err(_) => b.finish(None),
        }
    }
    let scene = match scene {
        Ok((mut s, c)) => {
            adjust_scene(args, &mut s)?;
            Ok((s, c))
        }
        other => other,
    };
    // One warning line per problem worked around; `--check` lists them in its report instead.
    if let (Ok((s, _)), true) = (&scene, print_warnings) {
        for w in &s.warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(scene?)
}

/// What the options ask of the loader (the mesh cache's bound is set here too).
pub fn load_options(args: &Options, progress: Option<ProgressFn>) -> LoadOptions {
    crate::scene::cache::set_max_bytes(args.load.cache_size.0);
    // A hit trusts size, time and inode; this also compares the model's content hash.
    crate::scene::cache::set_verify(
        std::env::var_os("GLVIEW_CACHE_VERIFY").is_some_and(|v| v == "1"),
    );
    LoadOptions {
        textures: TextureOptions {
            allow_outside_paths: args.load.allow_outside_paths,
            max_dimension: 0,
        },
        progress,
        cache: args.load.cache,
        honor_transparency: args.load.honor_transparency,
        creases: match (args.load.flat, args.load.crease) {
            (true, _) => crate::scene::geometry::normals::Creases::Flat,
            (false, Some(d)) => crate::scene::geometry::normals::Creases::Angle(d),
            (false, None) => Default::default(),
        },
        up: args.load.up,
        texture: args.load.texture.clone(),
        scene: args.load.scene.clone(),
        variant: args.load.variant.clone(),
    }
}

/// The environment a PBR reference render integrates (None for the legacy tier).
pub(crate) fn reference_env(
    args: &Options,
    shading: crate::frame::Shading,
) -> Result<Option<crate::reference::PbrEnv>> {
    if shading != crate::frame::Shading::Pbr {
        return Ok(None);
    }
    let req = env_request(args)?;
    Ok(Some(crate::reference::PbrEnv {
        env: std::sync::Arc::new(crate::pbr::env::Environment::from_source(&req.source)?),
        samples: args.pbr.reference_samples.max(1),
    }))
}
