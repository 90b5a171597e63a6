//! Compiled pipelines kept per device, so that a second renderer or evaluator of the same kind
//! (an engine draws many meshes) reuses the first one's instead of compiling its shaders again.
//!
//! A pipeline bundle is stored under its type and a key that names everything its shader
//! source and state depend on (normal mode, displacement kind, target formats, basis, ...).
//! wgpu's handles are reference-counted, so a cached bundle is cloned out cheaply. Bind group
//! layouts inside a bundle are compatible with any layout of the same entries (wgpu and
//! WebGPU compare them by their entries), so bind groups made elsewhere still fit.

use std::any::{Any, TypeId};
use std::collections::HashMap;
use std::sync::Mutex;

// On the web wgpu's handles are not `Send`; natively they are, and the cache must be too.
#[cfg(not(target_arch = "wasm32"))]
type Entry = Box<dyn Any + Send + Sync>;
#[cfg(target_arch = "wasm32")]
type Entry = Box<dyn Any>;

/// The pipelines of one device (shared by a context's clones).
#[derive(Default)]
pub(crate) struct PipelineCache {
    entries: Mutex<HashMap<(TypeId, String), Entry>>,
}

impl PipelineCache {
    /// The bundle stored under `key`, made by `make` (and stored) the first time.
    pub(crate) fn get_or_insert<T>(&self, key: &str, make: impl FnOnce() -> T) -> T
    where
        T: Clone + wgpu::WasmNotSendSync + 'static,
    {
        let id = (TypeId::of::<T>(), key.to_string());
        if let Some(found) = self.lock().get(&id) {
            return found
                .downcast_ref::<T>()
                .expect("the entry's type is in its key")
                .clone();
        }
        // Made outside the lock: compiling can take long and may use the context.
        let made = make();
        self.lock()
            .entry(id)
            .or_insert_with(|| Box::new(made.clone()));
        made
    }

    /// Bundles stored.
    pub(crate) fn len(&self) -> usize {
        self.lock().len()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<(TypeId, String), Entry>> {
        // A panic while holding the lock cannot leave the map half-written (one insert).
        self.entries.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_is_made_once_per_type() {
        let cache = PipelineCache::default();
        let mut made = 0;
        for _ in 0..3 {
            let v: u32 = cache.get_or_insert("a", || {
                made += 1;
                7
            });
            assert_eq!(v, 7);
        }
        let s: String = cache.get_or_insert("a", || "other type".to_string());
        assert_eq!((made, s.as_str(), cache.len()), (1, "other type", 2));
    }
}
