//! Mailboxing (Amanatides & Woo 1987; Arnaldi et al. 1987) without per-ray allocation: a per-thread array of ray
//! stamps, one per primitive. A ray takes a fresh stamp; a primitive whose stamp equals the ray's was already
//! tested by this ray (it spans several cells) and is skipped. The arrays live in a thread-local cache keyed by
//! the accelerator's unique id (a few accelerators per thread at most), so concurrent rays never share one and the
//! hot loop never allocates; stamps wrap around by clearing the array once every 2^32 rays.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

/// How many accelerators' stamp arrays a thread keeps (least recently used one is replaced).
const CACHED: usize = 4;

struct Stamps {
    owner: u64,
    ray: u32,
    stamps: Vec<u32>,
}

thread_local! {
    static CACHE: RefCell<Vec<Stamps>> = const { RefCell::new(Vec::new()) };
}

/// A new id for an accelerator that uses mailboxes.
pub fn new_owner_id() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// The mailbox of one ray.
pub struct Mailbox<'a> {
    ray: u32,
    stamps: &'a mut [u32],
}

impl Mailbox<'_> {
    /// True the first time `prim` is seen by this ray (and marks it), false afterwards.
    #[inline(always)]
    pub fn first_visit(&mut self, prim: u32) -> bool {
        let s = &mut self.stamps[prim as usize];
        if *s == self.ray {
            false
        } else {
            *s = self.ray;
            true
        }
    }
}

/// Run `f` with a fresh mailbox for `num_prims` primitives of accelerator `owner` on this thread.
#[inline]
pub fn with_mailbox<R>(owner: u64, num_prims: usize, f: impl FnOnce(&mut Mailbox) -> R) -> R {
    CACHE.with(|cache| {
        let mut cache = cache.borrow_mut();
        let i = match cache.iter().position(|s| s.owner == owner) {
            Some(i) => i,
            None => {
                if cache.len() == CACHED {
                    cache.remove(0);
                }
                cache.push(Stamps { owner, ray: 0, stamps: vec![0; num_prims] });
                cache.len() - 1
            }
        };
        // Most recently used last.
        let last = cache.len() - 1;
        if i != last {
            let s = cache.remove(i);
            cache.push(s);
        }
        let entry = &mut cache[last];
        if entry.stamps.len() < num_prims {
            entry.stamps.resize(num_prims, 0);
        }
        entry.ray = entry.ray.wrapping_add(1);
        if entry.ray == 0 {
            entry.stamps.fill(0);
            entry.ray = 1;
        }
        f(&mut Mailbox { ray: entry.ray, stamps: &mut entry.stamps })
    })
}
