//! Scene loading on a thread with a stack sized for the deepest nesting Prism accepts
//! ([`prism_core::limits::MAX_NESTING_DEPTH`] levels of RON `children` or 6.837 `Group`/`Transform` blocks). The
//! parsers, the 6.837-to-RON conversion, serde's RON deserialiser, the spawner and the drops of the nested
//! descriptions all recurse once per level; their depth is checked against the limit with an error at the user's
//! `file:line`, and this stack holds that many levels with a wide margin. Only the pages a scene actually touches
//! are committed, so a flat scene costs nothing extra.

use prism_core::error::{PrismError, Result};

/// Stack reserved for loading: about 40 KiB per nesting level at the limit (measured: under 10 KiB per level in
/// release builds, under 25 KiB in debug builds).
pub const LOADER_STACK_BYTES: usize = 512 << 20;

/// ron's own recursion limit (nested structs, lists and maps): each entity level is an entity struct and its
/// `children` list, so four levels per entity leaves room for the values around them.
pub const RON_RECURSION_LIMIT: usize = 4 * prism_core::limits::MAX_NESTING_DEPTH + 64;

/// Run `f` on a thread with [`LOADER_STACK_BYTES`] of stack and return its result (a panic in `f` is resumed
/// on the calling thread).
pub fn with_loader_stack<T: Send>(f: impl FnOnce() -> Result<T> + Send) -> Result<T> {
    std::thread::scope(|s| {
        let handle = std::thread::Builder::new()
            .name("prism-load".into())
            .stack_size(LOADER_STACK_BYTES)
            .spawn_scoped(s, f)
            .map_err(|e| PrismError::invalid(format!("cannot start the scene loader thread: {e}")))?;
        match handle.join() {
            Ok(r) => r,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}
