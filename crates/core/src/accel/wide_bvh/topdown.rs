//! A top-down BVH2 builder for inputs that make PLOC degenerate: binned SAH over the primitives' centroids, built
//! iteratively. (The wide BVH's second candidate tree, binned SAH with spatial splits, is `spatial_split.rs`.)
//!
//! - **Inputs that make PLOC degenerate** ([`Binning::FALLBACK`]). PLOC merges mutual nearest neighbours in Morton
//!   order. When many primitives share one Morton cell (identical or concentric primitives: an OBJ with 50000 copies
//!   of one face), their merge costs tie, only one pair merges per round, and the build turns quadratic and its tree
//!   into a chain as deep as the group, which overflows the recursive CWBVH conversion. [`needs_fallback`] detects
//!   such groups (more than [`MAX_CELL_GROUP`] primitives in one cell of the 2^21-per-axis Morton grid over the
//!   centroids); the tree is then built here with 12 bins on the longest axis.
//!
//! Either way an object median split is taken when the centroids coincide or SAH cannot separate them, and median
//! splits below depth 48, so the tree is at most `48 + log2(N)` deep and the build is O(N log N) on any input. One
//! primitive per leaf (the CWBVH conversion expects it; the wide BVH collapses leaves afterwards).

use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;
use rayon::prelude::*;

/// Largest group of primitives in one Morton cell that PLOC is left to handle (its cost is quadratic in it).
pub const MAX_CELL_GROUP: usize = 256;

/// How a node's split is searched: `bins` equal bins of the centroids' extent along their longest axis (at most
/// [`MAX_BINS`]).
#[derive(Clone, Copy, Debug)]
pub struct Binning {
    pub bins: usize,
}

impl Binning {
    /// The degenerate-input build: 12 bins on the longest axis.
    pub const FALLBACK: Binning = Binning { bins: 12 };
}

const MAX_BINS: usize = 32;
/// Below this depth every split is a median split (bounds the tree's depth whatever SAH would do).
const SAH_DEPTH: usize = 48;

/// Mean overlap of the primitives' boxes above which PLOC is not used: the sum of their surface areas over the
/// surface area of their union. Ordinary meshes stay below 6 (the Stanford bunny 3.5, the dragon 5.8, the Cornell
/// box 5.7); the slivers of a fan-triangulated polygon, which all meet at one vertex, reach about a sixth of their
/// count (1,592 for 10,000), and PLOC, whose merge costs then nearly tie, turns quadratic (40,000 slivers: 10 s).
pub const MAX_MEAN_OVERLAP: f64 = 64.0;

/// True when some Morton cell of the centroids holds more than [`MAX_CELL_GROUP`] primitives, or when the boxes
/// overlap on average more than [`MAX_MEAN_OVERLAP`] times.
pub fn needs_fallback(aabbs: &[Aabb]) -> bool {
    if aabbs.len() <= MAX_CELL_GROUP {
        return false;
    }
    let union = aabbs.iter().fold(Aabb::empty(), |b, a| b.union(a));
    let area = |a: &Aabb| {
        let d = a.diagonal().as_dvec3();
        d.x * d.y + d.y * d.z + d.z * d.x
    };
    // In order, so the choice is the same on every run.
    let sum: f64 = aabbs.iter().map(area).sum();
    if sum > MAX_MEAN_OVERLAP * area(&union) {
        return true;
    }
    let total = aabbs.iter().fold(Aabb::empty(), |b, a| b.union(&Aabb::new(a.center(), a.center())));
    let scale = total.diagonal().as_dvec3();
    let cell = |a: &Aabb| {
        let q = (a.center() - total.min).as_dvec3() / scale.max(glam::DVec3::splat(f64::MIN_POSITIVE));
        let c = |v: f64| ((v.clamp(0.0, 1.0) * ((1u64 << 21) - 1) as f64) as u64) & ((1 << 21) - 1);
        c(q.x) | (c(q.y) << 21) | (c(q.z) << 42)
    };
    let mut keys: Vec<u64> = aabbs.par_iter().map(cell).collect();
    keys.par_sort_unstable();
    let mut run = 1;
    for w in keys.windows(2) {
        run = if w[0] == w[1] { run + 1 } else { 1 };
        if run > MAX_CELL_GROUP {
            return true;
        }
    }
    false
}

/// A BVH2 over `aabbs` (one primitive per leaf, node 0 the root, children in adjacent pairs), built top-down with
/// `binning`.
pub fn build_bvh2(aabbs: &[Aabb], binning: Binning) -> Bvh2 {
    let n = aabbs.len();
    let mut idx: Vec<u32> = (0..n as u32).collect();
    let centre: Vec<glam::Vec3A> = aabbs.iter().map(|a| a.center()).collect();
    let mut nodes = Vec::with_capacity(2 * n);
    nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
    // (node, first, end, depth) of the ranges still to build.
    let mut stack = vec![(0usize, 0usize, n, 0usize)];
    let mut max_depth = 0;
    while let Some((node, lo, hi, depth)) = stack.pop() {
        max_depth = max_depth.max(depth);
        let bounds = idx[lo..hi].iter().fold(Aabb::empty(), |b, &i| b.union(&aabbs[i as usize]));
        if hi - lo == 1 {
            nodes[node] = Bvh2Node::new(bounds, 1, lo as u32);
            continue;
        }
        let mid = split(&mut idx[lo..hi], &centre, aabbs, depth, binning) + lo;
        let left = nodes.len();
        nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
        nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
        nodes[node] = Bvh2Node::new(bounds, 0, left as u32);
        stack.push((left, lo, mid, depth + 1));
        stack.push((left + 1, mid, hi, depth + 1));
    }
    Bvh2 {
        nodes,
        primitive_indices: idx,
        max_depth: obvhs::bvh2::DEFAULT_MAX_STACK_DEPTH.max(max_depth + 1),
        ..Default::default()
    }
}

/// Partition `ids` (at least 2) and return the size of the left part (1 to len - 1).
fn split(ids: &mut [u32], centre: &[glam::Vec3A], aabbs: &[Aabb], depth: usize, binning: Binning) -> usize {
    let cb = ids.iter().fold(Aabb::empty(), |b, &i| b.union(&Aabb::new(centre[i as usize], centre[i as usize])));
    let longest = cb.largest_axis();
    let median = |ids: &mut [u32]| {
        let m = ids.len() / 2;
        ids.select_nth_unstable_by(m, |&a, &b| centre[a as usize][longest].total_cmp(&centre[b as usize][longest]));
        m
    };
    if depth >= SAH_DEPTH || ids.len() <= 4 {
        return median(ids);
    }
    let nb = binning.bins.clamp(2, MAX_BINS);
    // The bin of primitive `i` along `axis` (whose centroid extent is positive and finite).
    let bin = |i: u32, axis: usize| {
        let (lo, extent) = (cb.min[axis], cb.max[axis] - cb.min[axis]);
        (((centre[i as usize][axis] - lo) / extent * nb as f32) as usize).min(nb - 1)
    };
    let (mut best, mut best_cost) = (None, f32::INFINITY);
    for axis in [longest] {
        let extent = cb.max[axis] - cb.min[axis];
        if !(extent > 0.0 && extent.is_finite()) {
            continue;
        }
        let mut bins = [(Aabb::empty(), 0usize); MAX_BINS];
        for &i in ids.iter() {
            let b = &mut bins[bin(i, axis)];
            b.0 = b.0.union(&aabbs[i as usize]);
            b.1 += 1;
        }
        // SAH cost of splitting after bin k: area(left) * count(left) + area(right) * count(right).
        let mut right_area = [0.0f32; MAX_BINS];
        let mut acc = (Aabb::empty(), 0usize);
        for k in (1..nb).rev() {
            acc = (acc.0.union(&bins[k].0), acc.1 + bins[k].1);
            right_area[k] = if acc.1 > 0 { acc.0.half_area() * acc.1 as f32 } else { 0.0 };
        }
        let mut left = (Aabb::empty(), 0usize);
        for k in 0..nb - 1 {
            left = (left.0.union(&bins[k].0), left.1 + bins[k].1);
            if left.1 == 0 || left.1 == ids.len() {
                continue;
            }
            let cost = left.0.half_area() * left.1 as f32 + right_area[k + 1];
            if cost < best_cost {
                (best, best_cost) = (Some((axis, k)), cost);
            }
        }
    }
    let Some((axis, k)) = best else {
        return median(ids);
    };
    // Partition in place: primitives of bins 0..=k first.
    let mut m = 0;
    for j in 0..ids.len() {
        if bin(ids[j], axis) <= k {
            ids.swap(m, j);
            m += 1;
        }
    }
    if m == 0 || m == ids.len() { median(ids) } else { m }
}
