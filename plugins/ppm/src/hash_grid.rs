//! The hash-grid photon lookup (the design card's): a uniform grid of cubic cells of side `cell` (twice the
//! current median gather radius, so a typical query touches 2 x 2 x 2 cells and a pixel with a larger radius a few
//! more; a query that would visit more cells than there are photons scans the photons instead) hashed into a table
//! of 2^k slots, built over the **photons** every iteration. Each stored photon keeps its
//! cell's key, so photons of other cells that share a slot are skipped and no slot is read twice for one cell.
//!
//! Why over the photons and not over the visible points (pbrt-v4's choice): with photons in the grid, every visible
//! point gathers its own sum in parallel and in a fixed order (cell by cell, photons in index order), so the result
//! is deterministic without atomic float adds, whose order — and so whose rounding — depends on thread timing. It
//! also lets the kd-tree lookup work on the very same photons, so the two structures can be timed against each
//! other on the same image.
//!
//! Build: each photon's slot is computed in parallel, then a counting sort by slot (histogram, prefix sums, stable
//! scatter) reorders the photons into one array with `starts[slot]..starts[slot + 1]` per slot: no linked lists,
//! no order depending on threads, and the arrays are reused between iterations (memory stays flat).

use super::photons::Photon;
use glam::{IVec3, Vec3A};
use rayon::prelude::*;

#[derive(Default)]
pub struct PhotonHashGrid {
    origin: Vec3A,
    inv_cell: f32,
    mask: u32,
    starts: Vec<u32>,
    slots: Vec<u32>,
    photons: Vec<Photon>,
    /// The cell key of each photon (`photons[i]`'s cell).
    keys: Vec<u64>,
}

/// A cell's coordinates packed into one integer (21 bits each; coordinates are clamped to that range).
#[inline]
fn cell_key(c: IVec3) -> u64 {
    let f = |v: i32| (v.clamp(-(1 << 20), (1 << 20) - 1) + (1 << 20)) as u64;
    f(c.x) | (f(c.y) << 21) | (f(c.z) << 42)
}

#[inline]
fn hash_cell(c: IVec3) -> u32 {
    (c.x as u32).wrapping_mul(73_856_093)
        ^ (c.y as u32).wrapping_mul(19_349_663)
        ^ (c.z as u32).wrapping_mul(83_492_791)
}

#[inline]
fn cell_at(origin: Vec3A, inv_cell: f32, p: Vec3A) -> IVec3 {
    let q = (p - origin) * inv_cell;
    IVec3::new(q.x.floor() as i32, q.y.floor() as i32, q.z.floor() as i32)
}

impl PhotonHashGrid {
    #[inline]
    fn cell_of(&self, p: Vec3A) -> IVec3 {
        cell_at(self.origin, self.inv_cell, p)
    }

    /// Rebuild over `chunks` (concatenated in order) with cells of side `cell` (> 0).
    pub fn build(&mut self, chunks: &[Vec<Photon>], cell: f32) {
        let n: usize = chunks.iter().map(Vec::len).sum();
        let table = (2 * n).next_power_of_two().max(1024);
        self.mask = table as u32 - 1;
        self.inv_cell = 1.0 / cell;
        self.origin =
            chunks.iter().flatten().fold(Vec3A::splat(f32::INFINITY), |m, p| m.min(p.p)).min(Vec3A::splat(f32::MAX));
        // Slots of every photon, in parallel (each chunk writes its own range).
        let (origin, inv_cell, mask) = (self.origin, self.inv_cell, self.mask);
        self.slots.resize(n, 0);
        let mut rest: &mut [u32] = &mut self.slots;
        let mut parts = Vec::with_capacity(chunks.len());
        for c in chunks {
            let (head, tail) = rest.split_at_mut(c.len());
            parts.push(head);
            rest = tail;
        }
        parts.into_par_iter().zip(chunks.par_iter()).for_each(|(out, c)| {
            for (s, ph) in out.iter_mut().zip(c) {
                *s = hash_cell(cell_at(origin, inv_cell, ph.p)) & mask;
            }
        });
        // Counting sort by slot: histogram, exclusive prefix sums, stable scatter in photon order.
        self.starts.clear();
        self.starts.resize(table + 1, 0);
        for &s in &self.slots {
            self.starts[s as usize + 1] += 1;
        }
        for i in 0..table {
            self.starts[i + 1] += self.starts[i];
        }
        let mut cursor = self.starts[..table].to_vec();
        self.photons.clear();
        self.photons
            .resize(n, Photon { p: Vec3A::ZERO, wi: Vec3A::ZERO, ng: Vec3A::ZERO, beta: glam::Vec3::ZERO, depth: 0 });
        self.keys.clear();
        self.keys.resize(n, 0);
        for (&s, ph) in self.slots.iter().zip(chunks.iter().flatten()) {
            let c = &mut cursor[s as usize];
            self.photons[*c as usize] = *ph;
            self.keys[*c as usize] = cell_key(cell_at(origin, inv_cell, ph.p));
            *c += 1;
        }
    }

    /// Call `f` for every photon within distance `r` of `p` (each once, in a fixed order).
    #[inline]
    pub fn query(&self, p: Vec3A, r: f32, mut f: impl FnMut(&Photon)) {
        if self.photons.is_empty() {
            return;
        }
        let lo = self.cell_of(p - Vec3A::splat(r));
        let hi = self.cell_of(p + Vec3A::splat(r));
        let r2 = r * r;
        // A radius far above the cell size (a pixel whose visible point is much farther than most: cells follow
        // the median radius) would visit more cells than there are photons: scan the photons instead, which
        // costs at most what the cells would and never walks billions of empty cells.
        let span = |a: i32, b: i32| (b as i64 - a as i64 + 1).max(0) as u64;
        let cells = span(lo.x, hi.x).saturating_mul(span(lo.y, hi.y)).saturating_mul(span(lo.z, hi.z));
        if cells >= self.photons.len() as u64 {
            for ph in &self.photons {
                if (ph.p - p).length_squared() < r2 {
                    f(ph);
                }
            }
            return;
        }
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for x in lo.x..=hi.x {
                    let c = IVec3::new(x, y, z);
                    let slot = (hash_cell(c) & self.mask) as usize;
                    let key = cell_key(c);
                    let (a, b) = (self.starts[slot] as usize, self.starts[slot + 1] as usize);
                    for (ph, &k) in self.photons[a..b].iter().zip(&self.keys[a..b]) {
                        if k == key && (ph.p - p).length_squared() < r2 {
                            f(ph);
                        }
                    }
                }
            }
        }
    }

    /// Bytes held by the structure (photon copies, slots, table).
    pub fn memory_bytes(&self) -> usize {
        self.photons.capacity() * std::mem::size_of::<Photon>() + (self.slots.capacity() + self.starts.capacity()) * 4
    }
}
