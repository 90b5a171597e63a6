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
    /// The bundle stored under `key`, made by `make` (and stored, when it is `Ok`) the first
    /// time: a bundle that failed is made again by the next caller, never handed out.
    pub(crate) fn get_or_try_insert<T, E>(
        &self,
        key: &str,
        make: impl FnOnce() -> Result<T, E>,
    ) -> Result<T, E>
    where
        T: Clone + wgpu::WasmNotSendSync + 'static,
    {
        let id = (TypeId::of::<T>(), key.to_string());
        if let Some(found) = self.lock().get(&id) {
            return Ok(found
                .downcast_ref::<T>()
                .expect("the entry's type is in its key")
                .clone());
        }
        // Made outside the lock: compiling can take long and may use the context.
        let made = make()?;
        self.lock()
            .entry(id)
            .or_insert_with(|| Box::new(made.clone()));
        Ok(made)
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
    fn a_key_is_made_once_per_type_and_failures_are_not_kept() {
        let cache = PipelineCache::default();
        let mut made = 0;
        for _ in 0..3 {
            let v: Result<u32, ()> = cache.get_or_try_insert("a", || {
                made += 1;
                Ok(7)
            });
            assert_eq!(v, Ok(7));
        }
        let s: Result<String, ()> = cache.get_or_try_insert("a", || Ok("other type".into()));
        assert_eq!(
            (made, s.unwrap().as_str(), cache.len()),
            (1, "other type", 2)
        );
        let failed: Result<u32, &str> = cache.get_or_try_insert("b", || Err("broken"));
        assert_eq!((failed, cache.len()), (Err("broken"), 2));
        let v: Result<u32, &str> = cache.get_or_try_insert("b", || Ok(9));
        assert_eq!((v, cache.len()), (Ok(9), 3));
    }
}
