//! Where precomputed maps are kept between runs, given by the caller: the renderer has no
//! files. The native library keeps them in the mesh cache's folder (`ibl_cache.rs` there);
//! the browser build keeps none, so every start computes them.
use super::precompute::{IblData, IblSettings};
use super::EnvSource;
use std::sync::{Arc, OnceLock};

/// A store of precomputed maps. Anything it cannot read is a miss, never an error.
pub trait MapStore: Send + Sync {
    /// The key of these maps, or `None` when they cannot be keyed (an unreadable file).
    fn key(&self, source: &EnvSource, settings: &IblSettings) -> Option<u64>;
    fn get(&self, key: u64) -> Option<IblData>;
    fn put(&self, key: u64, data: &IblData);
}

static STORE: OnceLock<Arc<dyn MapStore>> = OnceLock::new();

/// Gives the renderer its store, once (later calls change nothing).
pub fn set_store(s: Arc<dyn MapStore>) {
    let _ = STORE.set(s);
}

pub(crate) fn store() -> Option<&'static Arc<dyn MapStore>> {
    STORE.get()
}
