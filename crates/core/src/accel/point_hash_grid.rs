//! A hash grid over points (the design card's photon lookup, shared by `ppm`'s photons and `vcm`'s light
//! vertices): a uniform grid of cubic cells of side `cell` hashed into a table of 2^k slots, built over the
//! **points** (photons, light vertices) once per iteration, and queried for every point within a radius of a
//! query point. Each stored point keeps its cell's key, so points of other cells that share a slot are skipped and
//! no slot is read twice for one cell. A query that would visit more cells than there are points scans the points
//! instead.
//!
//! Why over the stored points and not over the query points (pbrt-v4's SPPM grid is over its visible points): each
//! query then gathers its own sum in parallel and in a fixed order (cell by cell, points in index order), so the
//! result is deterministic without atomic float adds, whose order — and so whose rounding — depends on thread
//! timing.
//!
//! Build: each point's slot is computed in parallel, then a counting sort by slot (histogram, prefix sums, stable
//! scatter) reorders the points into one array with `starts[slot]..starts[slot + 1]` per slot: no linked lists,
//! no order depending on threads, and the arrays are reused between iterations (memory stays flat).
//!
//! Parameters: `cell`, the cell side (world units, positive); callers choose about twice the typical query radius,
//! so a query touches 2 x 2 x 2 cells.

use glam::{IVec3, Vec3A};
use rayon::prelude::*;

/// A point the grid can store: where it is.
pub trait GridPoint: Copy + Send + Sync {
    /// The point's position, world space.
    fn position(&self) -> Vec3A;
}

/// The hash grid over points of type `T` (see the module doc).
pub struct PointHashGrid<T> {
    origin: Vec3A,
    inv_cell: f32,
    mask: u32,
    starts: Vec<u32>,
    slots: Vec<u32>,
    points: Vec<T>,
    /// The cell key of each point (`points[i]`'s cell).
    keys: Vec<u64>,
}

impl<T> Default for PointHashGrid<T> {
    fn default() -> Self {
        PointHashGrid {
            origin: Vec3A::ZERO,
            inv_cell: 0.0,
            mask: 0,
            starts: Vec::new(),
            slots: Vec::new(),
            points: Vec::new(),
            keys: Vec::new(),
        }
    }
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

impl<T: GridPoint> PointHashGrid<T> {
    #[inline]
    fn cell_of(&self, p: Vec3A) -> IVec3 {
        cell_at(self.origin, self.inv_cell, p)
    }

    /// Rebuild over the points of `chunks` (concatenated in order) with cells of side `cell` (> 0).
    pub fn build(&mut self, chunks: &[Vec<T>], cell: f32) {
        let n: usize = chunks.iter().map(Vec::len).sum();
        let table = (2 * n).next_power_of_two().max(1024);
        self.mask = table as u32 - 1;
        self.inv_cell = 1.0 / cell;
        self.origin = chunks
            .iter()
            .flatten()
            .fold(Vec3A::splat(f32::INFINITY), |m, p| m.min(p.position()))
            .min(Vec3A::splat(f32::MAX));
        // Slots of every point, in parallel (each chunk writes its own range).
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
                *s = hash_cell(cell_at(origin, inv_cell, ph.position())) & mask;
            }
        });
        // Counting sort by slot: histogram, exclusive prefix sums, stable scatter in point order.
        self.starts.clear();
        self.starts.resize(table + 1, 0);
        for &s in &self.slots {
            self.starts[s as usize + 1] += 1;
        }
        for i in 0..table {
            self.starts[i + 1] += self.starts[i];
        }
        let mut cursor = self.starts[..table].to_vec();
        self.points.clear();
        let Some(&first) = chunks.iter().flatten().next() else {
            self.keys.clear();
            return;
        };
        self.points.resize(n, first);
        self.keys.clear();
        self.keys.resize(n, 0);
        for (&s, ph) in self.slots.iter().zip(chunks.iter().flatten()) {
            let c = &mut cursor[s as usize];
            self.points[*c as usize] = *ph;
            self.keys[*c as usize] = cell_key(cell_at(origin, inv_cell, ph.position()));
            *c += 1;
        }
    }

    /// Call `f` for every point within distance `r` of `p` (each once, in a fixed order).
    #[inline]
    pub fn query(&self, p: Vec3A, r: f32, mut f: impl FnMut(&T)) {
        if self.points.is_empty() {
            return;
        }
        let lo = self.cell_of(p - Vec3A::splat(r));
        let hi = self.cell_of(p + Vec3A::splat(r));
        let r2 = r * r;
        // A radius far above the cell size (a pixel whose visible point is much farther than most: cells follow
        // the median radius) would visit more cells than there are points: scan the points instead, which
        // costs at most what the cells would and never walks billions of empty cells.
        let span = |a: i32, b: i32| (b as i64 - a as i64 + 1).max(0) as u64;
        let cells = span(lo.x, hi.x).saturating_mul(span(lo.y, hi.y)).saturating_mul(span(lo.z, hi.z));
        if cells >= self.points.len() as u64 {
            for ph in &self.points {
                if (ph.position() - p).length_squared() < r2 {
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
                    for (ph, &k) in self.points[a..b].iter().zip(&self.keys[a..b]) {
                        if k == key && (ph.position() - p).length_squared() < r2 {
                            f(ph);
                        }
                    }
                }
            }
        }
    }

    /// Bytes held by the structure (point copies, slots, table).
    pub fn memory_bytes(&self) -> usize {
        self.points.capacity() * std::mem::size_of::<T>() + (self.slots.capacity() + self.starts.capacity()) * 4
    }
}
