//! The quality benchmark's scene set: each scene is a model plus lights, so any row of the
//! table can be reproduced with `glview MODEL --light L --output x.png`.
use glam::Vec3;
use glview::frame::FrameSettings;
use glview::options::Options;
use glview::scene::{Mesh, Scene, Vertex};
use glview::session::{frame_settings, load_scene};
use glview::{Error, Result};
use std::path::{Path, PathBuf};

/// Where a scene's model comes from.
#[derive(Clone, Debug)]
pub enum Model {
    /// The built-in glass-holder scene.
    Builtin,
    /// A file in the repository (relative to the working directory).
    Project(&'static str),
    /// A file under the shared models folder.
    Shared(&'static str),
}

#[derive(Clone, Debug)]
pub struct SceneSpec {
    pub name: &'static str,
    pub model: Model,
    /// `--light` values (none: the default kit).
    pub lights: &'static [&'static str],
    /// Add a floor under the model (in code), so it casts a shadow on something.
    pub floor: bool,
    /// Part of the `--quick` subset.
    pub quick: bool,
}

/// The default set: the built-in scene (glass and self-shadowing), a sphere (smooth
/// shading, the shadow terminator, acne), a box over a floor under a directional light (a
/// hard shadow edge), a box on a floor under a point light (a perspective shadow map, contact
/// shadow), and the Stanford bunny and dragon over a floor (fine geometry, detailed shadows).
pub fn default_set() -> Vec<SceneSpec> {
    vec![
        SceneSpec {
            name: "glass_holder",
            model: Model::Builtin,
            lights: &[],
            floor: false,
            quick: false,
        },
        SceneSpec {
            name: "sphere",
            model: Model::Project("models/sphere.obj"),
            lights: &[],
            floor: false,
            quick: true,
        },
        SceneSpec {
            name: "box_floor",
            model: Model::Project("models/box_floor.obj"),
            lights: &["dir:0.3,-0.8,-0.55"],
            floor: false,
            quick: true,
        },
        SceneSpec {
            name: "box_point",
            model: Model::Project("models/box_on_floor.obj"),
            lights: &["point:1.2,2.5,1.5"],
            floor: false,
            quick: false,
        },
        SceneSpec {
            name: "bunny_floor",
            model: Model::Shared("stanford-bunny/stanford-bunny.obj"),
            lights: &[],
            floor: true,
            quick: false,
        },
        SceneSpec {
            name: "dragon_floor",
            model: Model::Shared("dragon-200k/dragon_vrip_res2.obj"),
            lights: &[],
            floor: true,
            quick: false,
        },
    ]
}

/// A scene loaded and ready: its settings at the default knobs.
pub struct LoadedScene {
    pub name: String,
    /// The command line that reproduces the default render (without knob options).
    pub command: String,
    pub scene: Scene,
    pub settings: FrameSettings,
}

impl SceneSpec {
    pub fn path(&self, models_dir: &Path) -> Option<PathBuf> {
        match self.model {
            Model::Builtin => None,
            Model::Project(p) => Some(PathBuf::from(p)),
            Model::Shared(p) => Some(models_dir.join(p)),
        }
    }

    /// The scene's options, and the command-line words that reproduce them (the table's
    /// command column).
    fn options(&self, model: Option<PathBuf>, size: (u32, u32)) -> (Options, Vec<String>) {
        let mut words: Vec<String> = model.iter().map(|p| p.display().to_string()).collect();
        words.extend(["--size".into(), format!("{}x{}", size.0, size.1)]);
        for light in self.lights {
            words.extend(["--light".into(), light.to_string()]);
        }
        let opts = {
            let mut o: Options = Options::default();
            o.load.model = model;
            o.picture.size = size;
            o.light.lights = self
                .lights
                .iter()
                .map(|l| l.parse().expect("a bench light"))
                .collect();
            o
        };
        (opts, words)
    }

    pub fn load(&self, models_dir: &Path, size: (u32, u32)) -> Result<LoadedScene> {
        let path = self.path(models_dir);
        if let Some(p) = &path {
            if !p.is_file() {
                return Err(Error::Usage(format!(
                    "bench scene {}: {} is missing (run from the repository root, with \
                     ../shared beside it, or pass --models-dir)",
                    self.name,
                    p.display()
                )));
            }
        }
        let (args, words) = self.options(path, size);
        let mut scene = load_scene(&args)?;
        if self.floor {
            add_floor(&mut scene);
        }
        let (settings, _) = frame_settings(&args, &scene)?;
        let mut command = words.join(" ");
        if self.floor {
            command.push_str("  (+ floor added in code)");
        }
        Ok(LoadedScene {
            name: self.name.to_string(),
            command,
            scene,
            settings,
        })
    }
}

/// Adds a square floor touching the bottom of the bounds, three times the model's width.
pub fn add_floor(scene: &mut Scene) {
    let Some(first) = scene.meshes.first() else {
        return;
    };
    let b = scene.bounds;
    let c = b.center();
    let half = 1.5 * (b.max.x - b.min.x).max(b.max.z - b.min.z);
    let y = b.min.y;
    let v = |x: f32, z: f32| Vertex {
        position: [c.x + x * half, y, c.z + z * half],
        normal: [0.0, 1.0, 0.0],
        uv: [0.0, 0.0],
    };
    let mut floor = Mesh {
        name: "floor".into(),
        vertices: vec![v(-1.0, 1.0), v(1.0, 1.0), v(1.0, -1.0), v(-1.0, -1.0)],
        indices: vec![0, 1, 2, 0, 2, 3],
        ..first.clone()
    };
    floor.has_uv = false;
    floor.generated_normals = 0;
    for p in &floor.vertices {
        scene.bounds.include(Vec3::from(p.position));
    }
    scene.file_bounds = (
        scene.origin + scene.bounds.min.as_dvec3(),
        scene.origin + scene.bounds.max.as_dvec3(),
    );
    scene.meshes.push(floor);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The options built in code are the ones the printed command line parses to, so every
    /// row of the table is reproduced by its command.
    #[test]
    fn options_equal_their_command_line() {
        for spec in default_set() {
            let (built, words) = spec.options(spec.path(Path::new("../shared/models")), (64, 48));
            let parsed = Options::from_words(words.clone()).expect("the command parses");
            assert_eq!(built, parsed, "{}", spec.name);
        }
    }
}
