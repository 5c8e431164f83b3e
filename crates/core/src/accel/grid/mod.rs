//! Uniform grid (the 6.837 assignment 5 accelerator, done robustly): the padded world bounds of the bounded
//! primitives cut into `nx x ny x nz` equal cells, each listing the primitives that overlap it, traversed cell by
//! cell with a 3D-DDA (Amanatides & Woo, "A Fast Voxel Traversal Algorithm for Ray Tracing", 1987).
//!
//! Parameters: the resolution, fixed (`render: (accel: grid, grid: (nx, ny, nz))`, `--grid NX NY NZ`) or automatic
//! ([`GridResolution::Auto`]): `lambda * cbrt(N)` cells along the longest axis of the bounds and proportionally
//! fewer along the others (cells as close to cubes as the integer counts allow), at most [`AUTO_MAX_PER_AXIS`]
//! per axis, halved while the primitives' bounds span more than [`AUTO_MAX_CELLS_PER_PRIM`] cells on average
//! (huge or identical triangles, where finer cells only multiply references). `lambda` = [`DEFAULT_LAMBDA`],
//! chosen by measurement (see `docs/decisions/0026-grid-resolution.md`).
//!
//! Insertion. Primitives are world-space already (nested transforms composed): a triangle goes into every cell
//! its exact vertices' triangle overlaps (separating-axis test against the cell, `tri_box.rs`); an analytic shape
//! into the cells its own conservative test accepts (`AnalyticShape::overlaps_box`: a world-space sphere by the
//! distance from its centre, an ellipsoid by its box, revolutions and patches by the boxes of their seeding
//! structures' leaves). Cells are padded by a few ulps so rounding never loses a
//! reference. Planes are unbounded and stay outside (the `Scene` tests them).
//!
//! Traversal. The ray is clipped to the grid; the DDA steps to the neighbouring cell across the nearest cell
//! face, with every face position recomputed from its index (no accumulated drift). Axis-parallel rays never step
//! along their parallel axes. In each cell, primitives not yet tested by this ray are tested (per-thread
//! mailboxes, `mailbox.rs`: no primitive is tested twice, nothing allocated per ray); a hit may lie beyond the
//! current cell (a primitive spanning cells): it shortens the ray but traversal stops only once the closest hit
//! so far lies within the cells visited, so a nearer primitive in a later cell is never missed.
//!
//! Nested grids (automatic resolution only). A cell holding more than [`NEST_THRESHOLD`] references after
//! insertion gets its own automatic grid over the part of the cell its primitives occupy, recursively up to
//! [`MAX_NEST_DEPTH`] levels, when most of those primitives are small next to the cell and the nested grid
//! spreads them out (its fullest cell holds at most half as many), within a budget of `4 N + 4096` nested cells. This is the fix for the teapot in a stadium: a uniform grid sized for the stadium
//! puts the whole teapot in one or two cells, so every ray through the teapot tests all its triangles.
//!
//! The build (resolution, insertion, nesting) is in `build.rs`; this file holds the structure and its traversal.
//!
//! Bad resolutions (0 cells, more than [`MAX_CELLS_PER_AXIS`] per axis, more than [`MAX_CELLS`] in total, or a
//! resolution so fine that primitives would need more than [`MAX_CANDIDATES`] cell tests) are errors.

use super::clip::{RayInv, clip_ray};
use super::mailbox::{Mailbox, with_mailbox};
use super::work::{NoCount, TraversalWork, WorkCounter};
use super::{AccelStats, Accelerator};
use crate::geometry::{Bounds, Ray, TriSoa, WatertightRay};
use crate::primitives::{Hit, Primitives};
use crate::settings::GridResolution;
use glam::Vec3A;
use std::time::Duration;

mod build;
pub use build::{auto_resolution, check_resolution};

/// Cells along the longest axis = `DEFAULT_LAMBDA * cbrt(N)` for automatic resolutions.
pub const DEFAULT_LAMBDA: f32 = 2.0;
/// Largest automatic resolution along one axis.
pub const AUTO_MAX_PER_AXIS: u32 = 512;
/// Largest accepted resolution along one axis.
pub const MAX_CELLS_PER_AXIS: u32 = 4096;
/// Largest accepted number of cells (8 bytes each: 256 MiB).
pub const MAX_CELLS: u64 = 1 << 25;
/// Largest accepted number of (cell, primitive) overlap tests during insertion.
pub const MAX_CANDIDATES: u64 = 1 << 28;
/// Automatic resolutions are halved while primitives' bounds span more cells than this on average.
pub const AUTO_MAX_CELLS_PER_PRIM: u64 = 24;
/// Cells holding more references than this get a nested grid (automatic resolution only).
pub const NEST_THRESHOLD: u32 = 48;
/// Nesting depth limit (the top grid is depth 0).
pub const MAX_NEST_DEPTH: u32 = 3;

/// The first and last cell (inclusive) a primitive's bounds overlap.
type CellRange = ([i32; 3], [i32; 3]);

/// Marks a cell whose content is a nested grid (`start` is then the index of its level).
const NESTED: u32 = u32::MAX;

#[derive(Clone, Copy, Debug, Default)]
struct Cell {
    start: u32,
    count: u32,
}

/// One grid: the top level or a nested grid inside a cell of its parent.
#[derive(Clone, Debug)]
struct Level {
    bounds: Bounds,
    res: [i32; 3],
    cell: Vec3A,
    inv_cell: Vec3A,
    cells: Vec<Cell>,
    /// One bit per cell, set when the cell holds something: the traversal skips empty cells by reading this
    /// small array (a few KiB) instead of the cells themselves.
    occupied: Vec<u64>,
    depth: u32,
}

impl Level {
    #[inline(always)]
    fn is_occupied(&self, i: usize) -> bool {
        self.occupied[i >> 6] & (1 << (i & 63)) != 0
    }

    fn update_occupancy(&mut self) {
        self.occupied = vec![0; self.cells.len().div_ceil(64)];
        for (i, c) in self.cells.iter().enumerate() {
            if c.count != 0 {
                self.occupied[i >> 6] |= 1 << (i & 63);
            }
        }
    }

    #[inline(always)]
    fn index(&self, c: [i32; 3]) -> usize {
        (c[0] + self.res[0] * (c[1] + self.res[1] * c[2])) as usize
    }

    /// Position of cell face `k` (0..=res) along axis `a`.
    #[inline(always)]
    fn face(&self, a: usize, k: i32) -> f32 {
        if k >= self.res[a] { self.bounds.max[a] } else { self.bounds.min[a] + k as f32 * self.cell[a] }
    }

    fn cell_bounds(&self, c: [i32; 3]) -> Bounds {
        let lo = Vec3A::new(self.face(0, c[0]), self.face(1, c[1]), self.face(2, c[2]));
        let hi = Vec3A::new(self.face(0, c[0] + 1), self.face(1, c[1] + 1), self.face(2, c[2] + 1));
        Bounds::new(lo, hi)
    }

    /// Cell coordinates containing `p` (clamped into the grid).
    #[inline(always)]
    fn cell_of(&self, p: Vec3A) -> [i32; 3] {
        let f = ((p - self.bounds.min) * self.inv_cell).floor();
        [0, 1, 2].map(|a| (f[a] as i32).clamp(0, self.res[a] - 1))
    }
}

/// 3D-DDA state over one level.
struct Dda {
    c: [i32; 3],
    next: [f32; 3],
    step: [i32; 3],
}

impl Dda {
    #[inline(always)]
    fn new(l: &Level, ray: &Ray, ri: &RayInv, t0: f32) -> Self {
        let c = l.cell_of(ray.origin + ray.dir * t0);
        let mut next = [f32::INFINITY; 3];
        let mut step = [0; 3];
        for a in 0..3 {
            if ri.parallel[a] {
                continue;
            }
            step[a] = if ray.dir[a] > 0.0 { 1 } else { -1 };
            let k = if step[a] > 0 { c[a] + 1 } else { c[a] };
            next[a] = (l.face(a, k) - ray.origin[a]) * ri.inv[a];
        }
        Dda { c, next, step }
    }

    /// The axis whose face the ray crosses first, and where.
    #[inline(always)]
    fn exit(&self) -> (usize, f32) {
        let n = self.next;
        if n[0] < n[1] {
            if n[0] < n[2] { (0, n[0]) } else { (2, n[2]) }
        } else if n[1] < n[2] {
            (1, n[1])
        } else {
            (2, n[2])
        }
    }

    /// Step across the face on `axis`; false when that leaves the level.
    #[inline(always)]
    fn advance(&mut self, l: &Level, ray: &Ray, ri: &RayInv, axis: usize) -> bool {
        let c = self.c[axis] + self.step[axis];
        if c < 0 || c >= l.res[axis] {
            return false;
        }
        self.c[axis] = c;
        let k = if self.step[axis] > 0 { c + 1 } else { c };
        self.next[axis] = (l.face(axis, k) - ray.origin[axis]) * ri.inv[axis];
        true
    }
}

/// A cell of the grid (or of a nested grid) and how many primitive references it holds.
#[derive(Clone, Copy, Debug)]
pub struct GridCell {
    /// The cell's box, world space.
    pub bounds: Bounds,
    /// Primitive references listed in the cell.
    pub count: u32,
    /// Nesting depth (0 = the top grid).
    pub depth: u32,
}

/// The first occupied cell a ray enters (for the `-visualize_grid` view).
#[derive(Clone, Copy, Debug)]
pub struct CellHit {
    /// Ray parameter where the ray enters the cell (0 when the ray starts inside it).
    pub t: f32,
    /// Outward normal of the cell face the ray entered through.
    pub normal: Vec3A,
    /// The cell entered.
    pub cell: GridCell,
}

/// `--accel grid`: a uniform grid whose cells list the bounded primitives overlapping them, with nested grids in
/// crowded cells, traversed by 3D-DDA (see the module notes).
pub struct UniformGrid {
    levels: Vec<Level>,
    refs: Vec<u32>,
    /// The vertices of each reference's triangle (zero for analytic shapes), in cell order: a cell's triangles are read
    /// from consecutive memory.
    ref_tris: Vec<TriSoa>,
    num_tris: u32,
    owner: u64,
    num_prims: u32,
    resolution: GridResolution,
    pub(super) build_time: Duration,
}

/// Best hit so far and the current end of the ray.
struct Closest {
    tmax: f32,
    hit: Option<Hit>,
}

impl UniformGrid {
    /// Walk level `li` over `[t0, t1]`; true when the query is answered (a hit for occlusion, or the closest hit
    /// lies within the cells visited).
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn walk<const ANY: bool, C: WorkCounter>(
        &self,
        li: usize,
        prims: &Primitives,
        ray: &Ray,
        wt: &WatertightRay,
        ri: &RayInv,
        t0: f32,
        t1: f32,
        best: &mut Closest,
        mailbox: &mut Mailbox,
        counter: &mut C,
    ) -> bool {
        let l = &self.levels[li];
        let mut dda = Dda::new(l, ray, ri, t0);
        let mut t_enter = t0;
        loop {
            counter.node();
            let (axis, t_face) = dda.exit();
            let t_exit = t_face.min(t1);
            let index = l.index(dda.c);
            let cell = if l.is_occupied(index) { l.cells[index] } else { Cell::default() };
            if cell.count == NESTED {
                if let Some(child) = self.levels.get(cell.start as usize)
                    && let Some((c0, c1)) = clip_ray(&child.bounds, ray.origin, ri, t_enter, t_exit)
                    && self.walk::<ANY, C>(cell.start as usize, prims, ray, wt, ri, c0, c1, best, mailbox, counter)
                {
                    return true;
                }
            } else if cell.count > 0 {
                let range = cell.start as usize..(cell.start + cell.count) as usize;
                for (&id, tri) in self.refs[range.clone()].iter().zip(&self.ref_tris[range]) {
                    if !mailbox.first_visit(id) {
                        continue;
                    }
                    counter.prim();
                    let hit = if id < self.num_tris {
                        wt.intersect_soa(tri, best.tmax).map(|h| Hit { t: h.t, prim: id, b1: h.b1, b2: h.b2 })
                    } else if ANY {
                        let r = Ray { tmax: best.tmax, ..*ray };
                        prims.occludes_analytic(id, &r).then_some(Hit { t: 0.0, prim: id, b1: 0.0, b2: 0.0 })
                    } else {
                        prims.intersect_analytic(id, &Ray { tmax: best.tmax, ..*ray })
                    };
                    if let Some(h) = hit {
                        best.tmax = h.t;
                        best.hit = Some(h);
                        if ANY {
                            return true;
                        }
                    }
                }
            }
            if best.tmax <= t_exit {
                return true;
            }
            if t_face >= t1 || !dda.advance(l, ray, ri, axis) {
                return false;
            }
            t_enter = t_face;
        }
    }

    #[inline]
    fn query<const ANY: bool, C: WorkCounter>(&self, prims: &Primitives, ray: &Ray, counter: &mut C) -> Option<Hit> {
        if self.num_prims == 0 {
            return None;
        }
        let ri = RayInv::new(ray.dir);
        let (t0, t1) = clip_ray(&self.levels[0].bounds, ray.origin, &ri, 0.0, ray.tmax)?;
        let wt = WatertightRay::new(ray);
        let mut best = Closest { tmax: ray.tmax, hit: None };
        with_mailbox(self.owner, self.num_prims as usize, |mb| {
            self.walk::<ANY, C>(0, prims, ray, &wt, &ri, t0, t1, &mut best, mb, counter);
        });
        best.hit
    }

    /// Bounds of the top grid (the primitives' bounds, padded by rounding error).
    pub fn bounds(&self) -> Bounds {
        self.levels.first().map_or(Bounds::EMPTY, |l| l.bounds)
    }

    /// Position of cell face `k` (0 to the resolution) of the top grid along `axis`, exactly as traversal
    /// computes it (for tests that aim rays along cell borders).
    pub fn face_position(&self, axis: usize, k: u32) -> f32 {
        self.levels.first().map_or(0.0, |l| l.face(axis, k as i32))
    }

    /// Resolution of the top grid.
    pub fn resolution(&self) -> [u32; 3] {
        self.levels.first().map_or([0; 3], |l| l.res.map(|r| r as u32))
    }

    /// Number of nested grids.
    pub fn nested_grids(&self) -> usize {
        self.levels.len().saturating_sub(1)
    }

    /// Total primitive references (a primitive counts once per cell it is listed in).
    pub fn references(&self) -> usize {
        self.refs.len()
    }

    /// Every occupied cell that holds primitives (nested grids' cells instead of the cells they refine).
    pub fn occupied_cells(&self) -> Vec<GridCell> {
        let mut out = Vec::new();
        for l in &self.levels {
            for z in 0..l.res[2] {
                for y in 0..l.res[1] {
                    for x in 0..l.res[0] {
                        let c = l.cells[l.index([x, y, z])];
                        if c.count != NESTED && c.count > 0 {
                            out.push(GridCell { bounds: l.cell_bounds([x, y, z]), count: c.count, depth: l.depth });
                        }
                    }
                }
            }
        }
        out
    }

    /// The first occupied cell along the ray (descending into nested grids), with the face it was entered by.
    pub fn first_occupied_cell(&self, ray: &Ray) -> Option<CellHit> {
        let ri = RayInv::new(ray.dir);
        let l = self.levels.first()?;
        let (t0, t1) = clip_ray(&l.bounds, ray.origin, &ri, 0.0, ray.tmax)?;
        self.first_occupied_in(0, ray, &ri, t0, t1)
    }

    fn first_occupied_in(&self, li: usize, ray: &Ray, ri: &RayInv, t0: f32, t1: f32) -> Option<CellHit> {
        let l = &self.levels[li];
        let mut dda = Dda::new(l, ray, ri, t0);
        let mut t_enter = t0;
        loop {
            let (axis, t_face) = dda.exit();
            let t_exit = t_face.min(t1);
            let cell = l.cells[l.index(dda.c)];
            if cell.count == NESTED {
                let child = &self.levels[cell.start as usize];
                if let Some((c0, c1)) = clip_ray(&child.bounds, ray.origin, ri, t_enter, t_exit)
                    && let Some(h) = self.first_occupied_in(cell.start as usize, ray, ri, c0, c1)
                {
                    return Some(h);
                }
            } else if cell.count > 0 {
                let bounds = l.cell_bounds(dda.c);
                return Some(CellHit {
                    t: t_enter,
                    normal: entry_normal(&bounds, ray.at(t_enter), ray.dir),
                    cell: GridCell { bounds, count: cell.count, depth: l.depth },
                });
            }
            if t_face >= t1 || !dda.advance(l, ray, ri, axis) {
                return None;
            }
            t_enter = t_face;
        }
    }
}

/// The outward normal of the face of `b` nearest to `p` (a point on its boundary) that faces against `dir`.
fn entry_normal(b: &Bounds, p: Vec3A, dir: Vec3A) -> Vec3A {
    let size = b.diagonal().max(Vec3A::splat(f32::MIN_POSITIVE));
    let mut best = (f32::INFINITY, Vec3A::ZERO);
    for a in 0..3 {
        let mut n = Vec3A::ZERO;
        let d = if dir[a] > 0.0 {
            n[a] = -1.0;
            (p[a] - b.min[a]).abs()
        } else {
            n[a] = 1.0;
            (b.max[a] - p[a]).abs()
        };
        let d = d / size[a];
        if d < best.0 {
            best = (d, n);
        }
    }
    best.1
}

impl Accelerator for UniformGrid {
    #[inline]
    fn intersect(&self, prims: &Primitives, ray: &Ray) -> Option<Hit> {
        self.query::<false, _>(prims, ray, &mut NoCount)
    }

    #[inline]
    fn occluded(&self, prims: &Primitives, ray: &Ray) -> bool {
        self.query::<true, _>(prims, ray, &mut NoCount).is_some()
    }

    fn intersect_counted(&self, prims: &Primitives, ray: &Ray, work: &mut TraversalWork) -> Option<Hit> {
        self.query::<false, _>(prims, ray, work)
    }

    fn stats(&self) -> AccelStats {
        let cells: usize = self.levels.iter().map(|l| l.cells.len()).sum();
        let r = self.resolution();
        let auto = if matches!(self.resolution, GridResolution::Auto) { " auto" } else { "" };
        AccelStats {
            kind: "grid",
            build_time: self.build_time,
            memory_bytes: cells * std::mem::size_of::<Cell>()
                + self.levels.iter().map(|l| l.occupied.len() * 8).sum::<usize>()
                + self.refs.len() * (4 + std::mem::size_of::<TriSoa>()),
            nodes: cells,
            detail: format!(
                "{}x{}x{}{auto}, {:.2} refs/prim, {} nested",
                r[0],
                r[1],
                r[2],
                self.refs.len() as f64 / self.num_prims.max(1) as f64,
                self.nested_grids()
            ),
        }
    }
}
