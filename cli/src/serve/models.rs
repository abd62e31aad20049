//! The models a server offers: PATH's one model, or every model file under PATH's folder,
//! each named by its path relative to PATH. Clients name models by this list only, so no
//! request ever becomes a path; links are resolved before the list is made and whatever
//! resolves outside PATH is left out, and resolved again at every open (a link swapped in
//! after the start is not followed). Viewers see names, never the server's paths
//! ([`Models::scrub`]).
use glview::{Error, Result};
use std::path::{Path, PathBuf};

/// How deep the folder scan goes, and how many models it lists at most (a folder of
/// everything must not make the list, or the scan, unbounded).
const MAX_DEPTH: usize = 6;
const MAX_MODELS: usize = 2000;

/// Names shown for the built-in scene (no PATH given).
pub const BUILTIN: &str = "built-in";

pub struct Models {
    /// (name, canonical path, the path as listed); None is the built-in scene.
    entries: Vec<(String, Option<(PathBuf, PathBuf)>)>,
    /// The folder served (a single model's own folder): what viewers' strings are relative to.
    root: Option<PathBuf>,
}

fn is_model(p: &Path) -> bool {
    let name = p
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let name = name.strip_suffix(".gz").unwrap_or(&name);
    [".obj", ".stl", ".ply", ".gltf", ".glb"]
        .iter()
        .any(|e| name.ends_with(e))
}

impl Models {
    /// The list for PATH (None: the built-in scene).
    pub fn scan(path: Option<&Path>) -> Result<Models> {
        let Some(path) = path else {
            return Ok(Models {
                entries: vec![(BUILTIN.into(), None)],
                root: None,
            });
        };
        let root = path.canonicalize().map_err(|e| Error::io(path, e))?;
        if root.is_file() {
            let name = root
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| "model".into());
            return Ok(Models {
                entries: vec![(name, Some((root.clone(), root.clone())))],
                root: root.parent().map(Path::to_path_buf),
            });
        }
        let mut entries = Vec::new();
        walk(&root, &root, 0, &mut entries);
        entries.sort();
        if entries.is_empty() {
            return Err(Error::model(
                path,
                None,
                "no model files (.obj, .stl, .ply, .gltf, .glb) in this folder",
            ));
        }
        Ok(Models {
            entries: entries.into_iter().map(|(n, p)| (n, Some(p))).collect(),
            root: Some(root),
        })
    }

    pub fn names(&self) -> Vec<String> {
        self.entries.iter().map(|(n, _)| n.clone()).collect()
    }

    /// The first model: what a new viewer sees.
    pub fn first(&self) -> (&str, Option<&Path>) {
        let (n, p) = &self.entries[0];
        (n, p.as_ref().map(|(real, _)| real.as_path()))
    }

    /// The model of this name in the list (a name, never a path: `../x` is no name), its
    /// listed path resolved again now: whatever it resolves to must still be a file inside
    /// the folder. The error is the viewer's, the same whether or not a file outside exists.
    pub fn open(&self, name: &str) -> std::result::Result<Option<PathBuf>, String> {
        let Some((_, entry)) = self.entries.iter().find(|(n, _)| n == name) else {
            return Err(format!(
                "no model named {:?} (the server lists {})",
                crate::serve::http::clip(name),
                self.entries.len()
            ));
        };
        let Some((_, listed)) = entry else {
            return Ok(None);
        };
        let inside = |real: &PathBuf| {
            real.is_file() && self.root.as_ref().is_none_or(|r| real.starts_with(r))
        };
        match listed.canonicalize() {
            Ok(real) if inside(&real) => Ok(Some(real)),
            _ => Err(format!(
                "{name}: no longer a model inside the served folder"
            )),
        }
    }

    /// The name of the model at this path.
    pub fn name_of(&self, path: Option<&Path>) -> String {
        self.entries
            .iter()
            .find(|(_, p)| p.as_ref().map(|(real, _)| real.as_path()) == path)
            .map_or_else(|| BUILTIN.to_string(), |(n, _)| n.clone())
    }

    /// `s` as a viewer may read it: the served folder's path taken out (names are relative
    /// to it), so no frame, PNG text or error tells where the server keeps its files.
    pub fn scrub(&self, s: &str) -> String {
        let Some(root) = self.root.as_ref().and_then(|r| r.to_str()) else {
            return s.to_string();
        };
        let root = root.trim_end_matches('/');
        if root.is_empty() {
            return s.to_string();
        }
        s.replace(&format!("{root}/"), "")
    }
}

/// Model files under `dir` (canonical, inside `root`), named relative to `root` with `/`:
/// (name, (canonical path, path as listed)).
type Found = (String, (PathBuf, PathBuf));

fn walk(root: &Path, dir: &Path, depth: usize, out: &mut Vec<Found>) {
    let Ok(read) = std::fs::read_dir(dir) else {
        return;
    };
    let mut items: Vec<PathBuf> = read.flatten().map(|e| e.path()).collect();
    items.sort();
    for item in items {
        if out.len() >= MAX_MODELS {
            return;
        }
        // Links are followed only to what stays inside the root.
        let Ok(real) = item.canonicalize() else {
            continue;
        };
        if !real.starts_with(root) {
            continue;
        }
        if real.is_dir() {
            if depth < MAX_DEPTH && real != *dir {
                walk(root, &real, depth + 1, out);
            }
        } else if real.is_file() && is_model(&real) {
            let Ok(rel) = item.strip_prefix(root).or_else(|_| real.strip_prefix(root)) else {
                continue;
            };
            let name = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy())
                .collect::<Vec<_>>()
                .join("/");
            if !out.iter().any(|(_, (p, _))| *p == real) {
                out.push((name, (real, item)));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Symbolic links are the point of this test: unix only (Windows' need privileges).
    #[cfg(unix)]
    #[test]
    fn folder_lists_models_inside_only() {
        let dir = std::env::temp_dir().join(format!("glview-models-{}", std::process::id()));
        let outside = dir.with_extension("outside");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::create_dir_all(&outside).unwrap();
        std::fs::write(dir.join("a.obj"), "v 0 0 0\n").unwrap();
        std::fs::write(dir.join("sub/b.STL"), "solid\n").unwrap();
        std::fs::write(dir.join("notes.txt"), "").unwrap();
        std::fs::write(outside.join("secret.obj"), "v 0 0 0\n").unwrap();
        std::os::unix::fs::symlink(outside.join("secret.obj"), dir.join("link.obj")).unwrap();
        std::os::unix::fs::symlink(&outside, dir.join("away")).unwrap();
        let m = Models::scan(Some(&dir)).unwrap();
        assert_eq!(m.names(), vec!["a.obj", "sub/b.STL"]);
        assert!(m.open("../glview-models.outside/secret.obj").is_err());
        assert!(m.open("link.obj").is_err());
        assert!(m.open("a.obj").unwrap().unwrap().ends_with("a.obj"));
        // A file swapped for a link after the scan is not followed, whether or not the
        // link's target exists (the error is the same).
        std::fs::remove_file(dir.join("a.obj")).unwrap();
        std::os::unix::fs::symlink(outside.join("secret.obj"), dir.join("a.obj")).unwrap();
        let e = m.open("a.obj").unwrap_err();
        std::fs::remove_file(dir.join("a.obj")).unwrap();
        std::os::unix::fs::symlink(outside.join("none.obj"), dir.join("a.obj")).unwrap();
        assert_eq!(m.open("a.obj").unwrap_err(), e);
        assert!(!e.contains(outside.to_str().unwrap()), "{e}");
        let root = dir.canonicalize().unwrap();
        let said = format!("cannot read {}/sub/b.STL: x", root.display());
        assert_eq!(m.scrub(&said), "cannot read sub/b.STL: x");
        let _ = std::fs::remove_dir_all(&dir);
        let _ = std::fs::remove_dir_all(&outside);
    }
}
