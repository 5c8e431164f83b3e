//! Building the uniform grid (see the parent module for the structure and its traversal): the resolution
//! (fixed and checked, or automatic: [`auto_resolution`]), insertion of every bounded primitive into the cells it
//! overlaps (exact triangle-box test, analytic shapes' own conservative test), and the nested grids of crowded
//! cells. Parameters: the resolution and `lambda` (cells per cube root of the primitive count along the longest
//! axis).

use super::{
    AUTO_MAX_CELLS_PER_PRIM, AUTO_MAX_PER_AXIS, Cell, CellRange, DEFAULT_LAMBDA, Level, MAX_CANDIDATES, MAX_CELLS,
    MAX_CELLS_PER_AXIS, MAX_NEST_DEPTH, NEST_THRESHOLD, NESTED, UniformGrid,
};
use crate::accel::clip::padded;
use crate::accel::mailbox::new_owner_id;
use crate::accel::tri_box::triangle_overlaps_box;
use crate::error::{PrismError, Result};
use crate::geometry::{Bounds, TriSoa};
use crate::primitives::Primitives;
use crate::settings::GridResolution;
use glam::Vec3A;
use rayon::prelude::*;
use std::time::Duration;

impl UniformGrid {
    /// Build over the bounded primitives of `prims` at `resolution` (automatic ones with [`DEFAULT_LAMBDA`]).
    /// Errors for a fixed resolution [`check_resolution`] rejects, or one so fine that insertion would take more
    /// than [`MAX_CANDIDATES`] cell tests.
    pub fn build(prims: &Primitives, resolution: GridResolution) -> Result<Self> {
        Self::build_with_lambda(prims, resolution, DEFAULT_LAMBDA)
    }

    /// Build with an explicit `lambda` for automatic resolutions (for measuring the best `lambda`).
    pub fn build_with_lambda(prims: &Primitives, resolution: GridResolution, lambda: f32) -> Result<Self> {
        if !(lambda.is_finite() && lambda > 0.0) {
            return Err(PrismError::invalid(format!("grid: lambda must be positive, got {lambda}")));
        }
        let n = prims.num_bounded();
        let mut grid = UniformGrid {
            levels: Vec::new(),
            refs: Vec::new(),
            ref_tris: Vec::new(),
            num_tris: prims.num_tris(),
            owner: new_owner_id(),
            num_prims: n,
            resolution,
            build_time: Duration::ZERO,
        };
        let bounds = if n == 0 { Bounds::new(Vec3A::ZERO, Vec3A::ZERO) } else { prims.bounds };
        let bounds = padded(&bounds);
        let res = match resolution {
            GridResolution::Fixed(r) => {
                check_resolution(r)?;
                r
            }
            GridResolution::Auto => auto_resolution(n as usize, bounds.diagonal(), lambda),
        };
        let ids: Vec<u32> = (0..n).collect();
        let nest = matches!(resolution, GridResolution::Auto);
        grid.build_level(prims, &ids, bounds, res, 0, nest, lambda)?;
        grid.compact_refs();
        let nt = grid.num_tris;
        grid.ref_tris = grid
            .refs
            .iter()
            .map(|&id| if id < nt { TriSoa::new(&prims.tris[id as usize]) } else { TriSoa::default() })
            .collect();
        Ok(grid)
    }

    /// Insert `ids` into a new level over `bounds`; returns its index. With `auto` (automatic resolution) the
    /// resolution shrinks while primitives span too many cells, and crowded cells become nested levels.
    #[allow(clippy::too_many_arguments)]
    fn build_level(
        &mut self,
        prims: &Primitives,
        ids: &[u32],
        bounds: Bounds,
        res: [u32; 3],
        depth: u32,
        auto: bool,
        lambda: f32,
    ) -> Result<usize> {
        let diag = bounds.diagonal();
        let cell = diag / Vec3A::new(res[0] as f32, res[1] as f32, res[2] as f32);
        let mut level = Level {
            bounds,
            res: res.map(|r| r as i32),
            cell,
            inv_cell: Vec3A::ONE / cell,
            cells: vec![Cell::default(); res.iter().map(|&r| r as usize).product()],
            occupied: Vec::new(),
            depth,
        };
        // Candidate cells: the cell range of each primitive's bounds.
        let candidate_ranges = |level: &Level| -> (Vec<CellRange>, u64) {
            let ranges: Vec<CellRange> = ids
                .par_iter()
                .map(|&id| {
                    let b = prims.prim_bounds(id);
                    (level.cell_of(b.min), level.cell_of(b.max))
                })
                .collect();
            let n = ranges.iter().map(|(lo, hi)| (0..3).map(|a| (hi[a] - lo[a] + 1) as u64).product::<u64>()).sum();
            (ranges, n)
        };
        let (mut ranges, mut candidates) = candidate_ranges(&level);
        // Automatic resolutions assume primitives small next to the cells; when they are not (huge or identical
        // triangles), halve the resolution until each primitive spans few cells.
        let mut res = res;
        while auto && candidates > AUTO_MAX_CELLS_PER_PRIM * ids.len() as u64 && res.iter().any(|&r| r > 1) {
            res = res.map(|r| (r / 2).max(1));
            let cell = diag / Vec3A::new(res[0] as f32, res[1] as f32, res[2] as f32);
            level.res = res.map(|r| r as i32);
            level.cell = cell;
            level.inv_cell = Vec3A::ONE / cell;
            level.cells = vec![Cell::default(); res.iter().map(|&r| r as usize).product()];
            (ranges, candidates) = candidate_ranges(&level);
        }
        if candidates > MAX_CANDIDATES {
            return Err(PrismError::invalid(format!(
                "grid {}x{}x{} is too fine for these primitives ({candidates} cell overlap tests, at most \
                 {MAX_CANDIDATES}); use a coarser grid",
                res[0], res[1], res[2]
            )));
        }
        // (cell, primitive) pairs in primitive order; a counting sort keeps that order within each cell.
        let level_ref = &level;
        let pairs: Vec<(u32, u32)> = ids
            .par_iter()
            .zip(ranges.par_iter())
            .flat_map_iter(|(&id, &(lo, hi))| {
                let mut out = Vec::new();
                for z in lo[2]..=hi[2] {
                    for y in lo[1]..=hi[1] {
                        for x in lo[0]..=hi[0] {
                            let c = [x, y, z];
                            if overlaps(prims, id, &level_ref.cell_bounds(c)) {
                                out.push((level_ref.index(c) as u32, id));
                            }
                        }
                    }
                }
                out
            })
            .collect();
        if self.refs.len() + pairs.len() > u32::MAX as usize / 2 {
            return Err(PrismError::invalid("grid: too many primitive references"));
        }
        for &(c, _) in &pairs {
            level.cells[c as usize].count += 1;
        }
        let base = self.refs.len();
        let mut start = base as u32;
        for c in level.cells.iter_mut() {
            c.start = start;
            start += c.count;
        }
        self.refs.resize(base + pairs.len(), 0);
        let mut fill: Vec<u32> = level.cells.iter().map(|c| c.start).collect();
        for &(c, id) in &pairs {
            self.refs[fill[c as usize] as usize] = id;
            fill[c as usize] += 1;
        }
        level.update_occupancy();
        let index = self.levels.len();
        self.levels.push(level);
        if auto && depth < MAX_NEST_DEPTH {
            self.nest_crowded_cells(prims, index, lambda)?;
        }
        Ok(index)
    }

    /// Drop the references of cells that became nested grids (their primitives are listed in the nested grid).
    fn compact_refs(&mut self) {
        let old = std::mem::take(&mut self.refs);
        let mut refs = Vec::with_capacity(old.len());
        for cell in self.levels.iter_mut().flat_map(|l| l.cells.iter_mut()) {
            if cell.count != NESTED && cell.count > 0 {
                let start = refs.len() as u32;
                refs.extend_from_slice(&old[cell.start as usize..(cell.start + cell.count) as usize]);
                cell.start = start;
            }
        }
        self.refs = refs;
    }

    /// Replace the crowded cells of level `index` by nested grids where that spreads the primitives out.
    fn nest_crowded_cells(&mut self, prims: &Primitives, index: usize, lambda: f32) -> Result<()> {
        let crowded: Vec<usize> = (0..self.levels[index].cells.len())
            .filter(|&i| {
                let c = self.levels[index].cells[i];
                c.count != NESTED && c.count > NEST_THRESHOLD
            })
            .collect();
        for i in crowded {
            let l = &self.levels[index];
            let c = l.cells[i];
            let coords = [i as i32 % l.res[0], (i as i32 / l.res[0]) % l.res[1], i as i32 / (l.res[0] * l.res[1])];
            let cell_bounds = l.cell_bounds(coords);
            let depth = l.depth + 1;
            let ids: Vec<u32> = self.refs[c.start as usize..(c.start + c.count) as usize].to_vec();
            // A finer grid separates only primitives that are small next to the cell; big ones (huge or
            // overlapping triangles) would fill every sub-cell.
            let half = 0.5 * cell_bounds.diagonal();
            let small = ids
                .iter()
                .filter(|&&id| {
                    let b = prims.prim_bounds(id);
                    let clipped = b.max.min(cell_bounds.max) - b.min.max(cell_bounds.min);
                    clipped.cmple(half).all()
                })
                .count();
            let budget = 4 * self.num_prims as usize + 4096;
            let nested_cells: usize = self.levels[1..].iter().map(|l| l.cells.len()).sum();
            if small * 2 < ids.len() || nested_cells >= budget {
                continue;
            }
            // Grid over the part of the cell the primitives occupy.
            let occupied = ids.iter().fold(Bounds::EMPTY, |b, &id| b.union(prims.prim_bounds(id)));
            let occupied = Bounds::new(occupied.min.max(cell_bounds.min), occupied.max.min(cell_bounds.max));
            let sub = padded(&occupied);
            let res = auto_resolution(ids.len(), sub.diagonal(), lambda);
            let (levels_before, refs_before) = (self.levels.len(), self.refs.len());
            let child = self.build_level(prims, &ids, sub, res, depth, true, lambda)?;
            // Keep the nested grid only if its fullest cell holds clearly fewer primitives than the cell did.
            let fullest = self.levels[child].cells.iter().filter(|k| k.count != NESTED).map(|k| k.count).max();
            if fullest.unwrap_or(0) * 2 > c.count && res.iter().product::<u32>() > 1 {
                self.levels.truncate(levels_before);
                self.refs.truncate(refs_before);
                continue;
            }
            self.levels[index].cells[i] = Cell { start: child as u32, count: NESTED };
        }
        Ok(())
    }
}

/// Does bounded primitive `id` overlap the cell `b` (padded by rounding error)? Triangles by the exact
/// separating-axis test; analytic shapes by their own conservative test (one dispatch for every kind).
fn overlaps(prims: &Primitives, id: u32, b: &Bounds) -> bool {
    let ext = b.diagonal().max_element();
    let mag = b.min.abs().max(b.max.abs()).max_element();
    let pad = Vec3A::splat(1e-4 * ext + 8.0 * f32::EPSILON * mag);
    let (lo, hi) = (b.min - pad, b.max + pad);
    if id < prims.num_tris() {
        return triangle_overlaps_box(&prims.tris[id as usize], lo, hi);
    }
    let pb = prims.prim_bounds(id);
    if pb.min.cmpgt(hi).any() || pb.max.cmplt(lo).any() {
        return false;
    }
    prims.analytic_overlaps_box(id, &Bounds::new(lo, hi))
}

/// A clear error for resolutions with an empty axis, too many cells per axis, or too many cells in total.
pub fn check_resolution(r: [u32; 3]) -> Result<()> {
    if r.contains(&0) {
        return Err(PrismError::invalid(format!(
            "grid resolution {}x{}x{} has an axis with 0 cells (each axis needs 1 to {MAX_CELLS_PER_AXIS})",
            r[0], r[1], r[2]
        )));
    }
    if r.iter().any(|&n| n > MAX_CELLS_PER_AXIS) {
        return Err(PrismError::invalid(format!(
            "grid resolution {}x{}x{} is too large (at most {MAX_CELLS_PER_AXIS} cells per axis)",
            r[0], r[1], r[2]
        )));
    }
    let total: u64 = r.iter().map(|&n| n as u64).product();
    if total > MAX_CELLS {
        return Err(PrismError::invalid(format!(
            "grid resolution {}x{}x{} has {total} cells (at most {MAX_CELLS}, {} MiB)",
            r[0],
            r[1],
            r[2],
            (MAX_CELLS * 8) >> 20
        )));
    }
    Ok(())
}

/// `lambda * cbrt(n)` cells along the longest side of a box of size `diag`, the other axes in proportion.
pub fn auto_resolution(n: usize, diag: Vec3A, lambda: f32) -> [u32; 3] {
    let longest = diag.max_element();
    if n == 0 || longest.is_nan() || longest <= 0.0 {
        return [1; 3];
    }
    let per_unit = lambda * (n as f32).cbrt() / longest;
    let mut r = [0, 1, 2].map(|a| ((diag[a] * per_unit).round() as u32).clamp(1, AUTO_MAX_PER_AXIS));
    // Stay well inside the cell budget.
    while r.iter().map(|&x| x as u64).product::<u64>() > MAX_CELLS / 2 {
        r = r.map(|x| (x / 2).max(1));
    }
    r
}
