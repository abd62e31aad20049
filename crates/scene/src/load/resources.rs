//! Where the loaders read files: a model and what it names (MTL libraries, images, glTF
//! buffers). Natively the file system (`Files`); in the browser the files a page fetched,
//! held in memory by name ([`Memory`]). Every read of the scene crate goes through the
//! [`Resources`] set with [`set`] (the process's file system by default in native builds,
//! an empty [`Memory`] elsewhere), so the loaders build for wasm32 and never touch a platform.
//! The mesh cache (native only) reads and writes its own folder directly.
use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, RwLock};

/// What is at a path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A regular file of this many bytes.
    File(u64),
    Dir,
    /// A device, a FIFO, a socket: never read (it could hang).
    Other,
}

/// A source of files, by path.
pub trait Resources: Send + Sync {
    /// What is at `path`; an error (NotFound) when nothing is.
    fn kind(&self, path: &Path) -> std::io::Result<Kind>;
    /// The first `limit` bytes of the regular file at `path` (all of a shorter one).
    fn read(&self, path: &Path, limit: u64) -> std::io::Result<Vec<u8>>;
    /// `path` with `.`, `..` and links resolved, for the model folder's rule; it must exist.
    fn canonical(&self, path: &Path) -> std::io::Result<PathBuf>;
    /// The names of what folder `dir` holds (case-insensitive lookups of exporters' paths).
    fn names(&self, dir: &Path) -> std::io::Result<Vec<String>>;
}

/// The process's file system.
#[cfg(feature = "native")]
pub struct Files;

#[cfg(feature = "native")]
impl Resources for Files {
    fn kind(&self, path: &Path) -> std::io::Result<Kind> {
        let m = std::fs::metadata(path)?;
        Ok(if m.is_file() {
            Kind::File(m.len())
        } else if m.is_dir() {
            Kind::Dir
        } else {
            Kind::Other
        })
    }

    fn read(&self, path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
        use std::io::Read;
        let mut out = Vec::new();
        std::fs::File::open(path)?
            .take(limit)
            .read_to_end(&mut out)?;
        Ok(out)
    }

    fn canonical(&self, path: &Path) -> std::io::Result<PathBuf> {
        path.canonicalize()
    }

    fn names(&self, dir: &Path) -> std::io::Result<Vec<String>> {
        Ok(std::fs::read_dir(dir)?
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect())
    }
}

/// Files held in memory, by path (the browser's fetched files; tests): folders are the
/// paths' parents, and there are no links.
#[derive(Default)]
pub struct Memory {
    files: HashMap<PathBuf, Arc<[u8]>>,
}

impl Memory {
    /// Holds `bytes` as the file `path` (made absolute and normalised lexically).
    pub fn insert(&mut self, path: impl AsRef<Path>, bytes: impl Into<Arc<[u8]>>) {
        self.files.insert(normal(path.as_ref()), bytes.into());
    }

    fn is_dir(&self, dir: &Path) -> bool {
        self.files.keys().any(|f| f.starts_with(dir) && f != dir)
    }
}

/// `path` absolute (under `/`) with `.` and `..` taken out, as a link-free file system
/// resolves it.
fn normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::from("/");
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::Normal(n) => out.push(n),
            Component::CurDir | Component::RootDir | Component::Prefix(_) => {}
        }
    }
    out
}

fn not_found(path: &Path) -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::NotFound,
        format!("{} is not among the files given", path.display()),
    )
}

impl Resources for Memory {
    fn kind(&self, path: &Path) -> std::io::Result<Kind> {
        let p = normal(path);
        match self.files.get(&p) {
            Some(b) => Ok(Kind::File(b.len() as u64)),
            None if self.is_dir(&p) => Ok(Kind::Dir),
            None => Err(not_found(path)),
        }
    }

    fn read(&self, path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
        let b = self
            .files
            .get(&normal(path))
            .ok_or_else(|| not_found(path))?;
        Ok(b[..b.len().min(usize::try_from(limit).unwrap_or(usize::MAX))].to_vec())
    }

    fn canonical(&self, path: &Path) -> std::io::Result<PathBuf> {
        let p = normal(path);
        if self.files.contains_key(&p) || self.is_dir(&p) {
            Ok(p)
        } else {
            Err(not_found(path))
        }
    }

    fn names(&self, dir: &Path) -> std::io::Result<Vec<String>> {
        let d = normal(dir);
        let mut names: Vec<String> = self
            .files
            .keys()
            .filter_map(|f| f.strip_prefix(&d).ok()?.components().next())
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names.dedup();
        Ok(names)
    }
}

/// Another source, with every file read through it kept: what a page must be handed to load
/// the same scene (`glview export --live` loads the model once through one).
pub struct Recording {
    inner: Arc<dyn Resources>,
    read: std::sync::Mutex<HashMap<PathBuf, Arc<[u8]>>>,
}

impl Recording {
    pub fn new(inner: Arc<dyn Resources>) -> Recording {
        Recording {
            inner,
            read: Default::default(),
        }
    }

    /// The files read so far, by the path they were asked by, the longest read of each.
    pub fn files(&self) -> Vec<(PathBuf, Arc<[u8]>)> {
        let read = self.read.lock().unwrap_or_else(|e| e.into_inner());
        let mut out: Vec<_> = read.iter().map(|(p, b)| (p.clone(), b.clone())).collect();
        out.sort_by(|a, b| a.0.cmp(&b.0));
        out
    }
}

impl Resources for Recording {
    fn kind(&self, path: &Path) -> std::io::Result<Kind> {
        self.inner.kind(path)
    }

    fn read(&self, path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
        let bytes = self.inner.read(path, limit)?;
        let mut read = self.read.lock().unwrap_or_else(|e| e.into_inner());
        let known = read.get(path).map_or(0, |b| b.len());
        if bytes.len() >= known {
            read.insert(path.to_path_buf(), bytes.as_slice().into());
        }
        Ok(bytes)
    }

    fn canonical(&self, path: &Path) -> std::io::Result<PathBuf> {
        self.inner.canonical(path)
    }

    fn names(&self, dir: &Path) -> std::io::Result<Vec<String>> {
        self.inner.names(dir)
    }
}

static CURRENT: RwLock<Option<Arc<dyn Resources>>> = RwLock::new(None);

/// Makes `r` where every later load reads its files (a browser page's fetched files).
pub fn set(r: Arc<dyn Resources>) {
    *CURRENT.write().unwrap_or_else(|e| e.into_inner()) = Some(r);
}

/// Where loads read their files now: what [`set`] set, else the file system (native) or
/// nothing at all (elsewhere).
pub fn current() -> Arc<dyn Resources> {
    if let Some(r) = CURRENT.read().unwrap_or_else(|e| e.into_inner()).as_ref() {
        return r.clone();
    }
    #[cfg(feature = "native")]
    {
        Arc::new(Files)
    }
    #[cfg(not(feature = "native"))]
    {
        Arc::new(Memory::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_recording_keeps_what_was_read_and_passes_everything_through() {
        let mut m = Memory::default();
        m.insert("/m/a.obj", b"v 0 0 0".to_vec());
        m.insert("/m/b.mtl", b"newmtl x".to_vec());
        let r = Recording::new(Arc::new(m));
        assert_eq!(r.read(Path::new("/m/a.obj"), 3).unwrap(), b"v 0");
        assert_eq!(r.read(Path::new("/m/a.obj"), 99).unwrap(), b"v 0 0 0");
        assert_eq!(r.read(Path::new("/m/a.obj"), 1).unwrap(), b"v");
        assert!(r.read(Path::new("/m/none"), 9).is_err());
        assert_eq!(r.kind(Path::new("/m")).unwrap(), Kind::Dir);
        let files = r.files();
        assert_eq!(files.len(), 1, "only what was read");
        assert_eq!(
            (&*files[0].0, &*files[0].1),
            (Path::new("/m/a.obj"), &b"v 0 0 0"[..])
        );
    }

    #[test]
    fn memory_files_resolve_like_a_file_system_without_links() {
        let mut m = Memory::default();
        m.insert("/lesson/model.gltf", b"{}".to_vec());
        m.insert("lesson/tex/Wood.png", vec![1, 2, 3]);
        assert_eq!(
            m.kind(Path::new("/lesson/model.gltf")).unwrap(),
            Kind::File(2)
        );
        assert_eq!(m.kind(Path::new("/lesson/tex")).unwrap(), Kind::Dir);
        assert!(m.kind(Path::new("/lesson/nothing.bin")).is_err());
        assert_eq!(
            m.read(Path::new("/lesson/x/../tex/Wood.png"), 2).unwrap(),
            [1, 2]
        );
        assert_eq!(
            m.canonical(Path::new("/lesson/./tex/../model.gltf"))
                .unwrap(),
            PathBuf::from("/lesson/model.gltf")
        );
        assert_eq!(
            m.names(Path::new("/lesson")).unwrap(),
            ["model.gltf", "tex"]
        );
    }
}
