//! A top-down BVH2 with spatial splits (SBVH; Stich, Friedrich & Dietrich, "Spatial Splits in Bounding Volume
//! Hierarchies", HPG 2009): a binned SAH over the references' centroids (32 bins on every axis), and beside it, where
//! the two children of the best such split overlap by more than [`OVERLAP_ALPHA`] of the root's area, a split of
//! space: a plane through the node's box at one of [`SPATIAL_BINS`] bin boundaries per axis, every triangle that
//! straddles it referenced on both sides with its box clipped to the triangle's part on that side (the binning
//! clips each reference to every bin it spans, exactly: boxes merely chopped at the planes gave a tree with 1%
//! more node tests per ray). The cheaper of the two by SAH is taken. Long or slanted triangles no longer stretch a
//! node's box across space they do not occupy, so rays test fewer boxes and triangles.
//!
//! Parameters: [`SPATIAL_BINS`] bins per axis, [`OVERLAP_ALPHA`] (Stich's alpha), and a budget of at most
//! [`REFERENCE_BUDGET`] x the primitive count in extra references (duplicated triangles); what a split leaves of
//! its node's budget is shared between the children in proportion to their references. Shapes other than
//! triangles are never split: they go whole to one side by their centroid.
//!
//! Correctness: a triangle's part inside a node's box is covered by the union of its references' boxes in the
//! children (the clipped boxes of its two halves, closed at the plane), and every clipped box is padded as the
//! primitives' boxes are (`padded_prim_aabbs`), so the robust box test finds every hit. A leaf may reference a
//! triangle that also lies in another leaf; the triangle test is the same kernel, so the hit is the same wherever
//! it is found. One reference per leaf, as `topdown.rs` (the wide BVH collapses leaves afterwards).

use glam::Vec3A;
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;

/// Bins per axis of the spatial split search (and of the object split's centroid binning).
pub const SPATIAL_BINS: usize = 32;
/// A spatial split is searched only where the best object split's children overlap by more than this share of the
/// root's surface area (Stich et al.'s alpha). Measured on the dragon (100k triangles; nodes and triangle lanes
/// per bounce ray, build time on one thread): no spatial splits 9.23 / 14.34, 110 ms for both candidates; alpha
/// 1e-5: 8.64 / 13.79, 790 ms; 1e-4: 8.64 / 13.87, 475 ms; **1e-3: 8.66 / 13.93, 300 ms**; 1e-2: 8.78 / 14.15.
pub const OVERLAP_ALPHA: f32 = 1e-3;
/// Most extra references, as a share of the primitive count (memory stays within 1.5x whatever the input). The
/// dragon uses about 12% (0.1: 8.73 / 14.02 per bounce ray; 0.25 to 1: the same as 0.5).
pub const REFERENCE_BUDGET: f32 = 0.5;
/// From this depth on every split is a median split of the centroids (bounds the tree's depth on any input).
const SAH_DEPTH: usize = 48;

/// One reference: a primitive and the box of its part in the current node, packed in 28 bytes (a glam `Aabb` with
/// its 16-byte alignment would make it 48: the build's memory is mostly references).
#[derive(Clone, Copy, Debug)]
struct Ref {
    id: u32,
    min: [f32; 3],
    max: [f32; 3],
}

impl Ref {
    fn new(id: u32, b: &Aabb) -> Self {
        Ref { id, min: b.min.to_array(), max: b.max.to_array() }
    }

    /// The reference's box.
    #[inline]
    fn b(&self) -> Aabb {
        Aabb::new(Vec3A::from_array(self.min), Vec3A::from_array(self.max))
    }

    /// Its box's centre along `axis`.
    #[inline]
    fn centre(&self, axis: usize) -> f32 {
        (self.min[axis] + self.max[axis]) * 0.5
    }
}

/// A BVH2 over primitives with padded boxes `aabbs`, of which the first `tris.len()` are the triangles `tris`
/// (node 0 the root, children in adjacent pairs, one reference per leaf; `primitive_indices` may name a triangle
/// more than once). Subtrees of more than [`PARALLEL_REFS`] references are built in parallel; each child's share
/// of the budget is fixed by its reference count, so the tree does not depend on the thread count.
///
/// `budget`: the most extra references as a share of the primitive count ([`REFERENCE_BUDGET`] for the spatial
/// splits; 0 for none, which leaves the binned SAH of the centroids alone).
pub fn build_sbvh2(aabbs: &[Aabb], tris: &[[Vec3A; 3]], budget: f32) -> Bvh2 {
    let n = aabbs.len();
    let refs: Vec<Ref> = aabbs.iter().enumerate().map(|(i, b)| Ref::new(i as u32, b)).collect();
    let root_area = refs.iter().fold(Aabb::empty(), |a, r| a.union(&r.b())).half_area();
    let ctx = Ctx { aabbs, tris, root_area };
    let t = ctx.subtree(refs, 0, (n as f32 * budget.max(0.0)) as usize);
    Bvh2 {
        nodes: t.nodes,
        primitive_indices: t.indices,
        max_depth: obvhs::bvh2::DEFAULT_MAX_STACK_DEPTH.max(t.depth + 1),
        ..Default::default()
    }
}

/// Subtrees with more references than this are built with their sibling in parallel.
const PARALLEL_REFS: usize = 4096;

/// What every node's split reads.
struct Ctx<'a> {
    aabbs: &'a [Aabb],
    tris: &'a [[Vec3A; 3]],
    root_area: f32,
}

/// A built subtree: its nodes (its root first, children in adjacent pairs, indices local), its leaves' references
/// and its depth below its root.
struct Subtree {
    nodes: Vec<Bvh2Node>,
    indices: Vec<u32>,
    depth: usize,
}

impl Ctx<'_> {
    fn subtree(&self, mut refs: Vec<Ref>, depth: usize, budget: usize) -> Subtree {
        if refs.len() <= PARALLEL_REFS {
            return self.sequential(refs, depth, budget);
        }
        let bounds = refs.iter().fold(Aabb::empty(), |a, r| a.union(&r.b()));
        let mut left_budget = budget;
        let right = split(&mut refs, &bounds, self, depth, &mut left_budget);
        let (lb, rb) = share(left_budget, refs.len(), right.len());
        let (l, r) = rayon::join(|| self.subtree(refs, depth + 1, lb), || self.subtree(right, depth + 1, rb));
        join_subtrees(bounds, l, r)
    }

    /// The same tree as [`Ctx::subtree`] builds, on one thread into one node array (no copies of subtrees).
    fn sequential(&self, refs: Vec<Ref>, depth: usize, budget: usize) -> Subtree {
        let mut nodes = vec![Bvh2Node::new(Aabb::empty(), 0, 0)];
        let mut indices = Vec::with_capacity(refs.len());
        let mut stack = vec![(0usize, refs, depth, budget)];
        let mut deepest = depth;
        while let Some((node, mut refs, depth, budget)) = stack.pop() {
            deepest = deepest.max(depth);
            let bounds = refs.iter().fold(Aabb::empty(), |a, r| a.union(&r.b()));
            if refs.len() == 1 {
                nodes[node] = Bvh2Node::new(bounds, 1, indices.len() as u32);
                indices.push(refs[0].id);
                continue;
            }
            let mut left_budget = budget;
            let right = split(&mut refs, &bounds, self, depth, &mut left_budget);
            let (lb, rb) = share(left_budget, refs.len(), right.len());
            let left = nodes.len();
            nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
            nodes.push(Bvh2Node::new(Aabb::empty(), 0, 0));
            nodes[node] = Bvh2Node::new(bounds, 0, left as u32);
            stack.push((left + 1, right, depth + 1, rb));
            stack.push((left, refs, depth + 1, lb));
        }
        Subtree { nodes, indices, depth: deepest - depth }
    }
}

/// The budget left after a split, shared in proportion to the references on each side.
fn share(budget: usize, left: usize, right: usize) -> (usize, usize) {
    let l = (budget as f64 * left as f64 / (left + right) as f64) as usize;
    (l, budget - l)
}

/// One subtree of root `bounds` over children `l` and `r`: the root, the children's roots as its pair, then the
/// rest of `l`'s nodes and of `r`'s, their child and leaf indices moved along.
fn join_subtrees(bounds: Aabb, l: Subtree, r: Subtree) -> Subtree {
    let (nl, il) = (l.nodes.len(), l.indices.len() as u32);
    // Where node i of a child goes: its root to 1 or 2, the rest after the pair.
    let place_l = |i: usize| if i == 0 { 1 } else { i + 2 };
    let place_r = |i: usize| if i == 0 { 2 } else { i + nl + 1 };
    let mut nodes = vec![Bvh2Node::new(bounds, 0, 1); l.nodes.len() + r.nodes.len() + 1];
    for (sub, place, leaf_offset) in
        [(&l, &place_l as &dyn Fn(usize) -> usize, 0), (&r, &place_r as &dyn Fn(usize) -> usize, il)]
    {
        for (i, nd) in sub.nodes.iter().enumerate() {
            let mut nd = *nd;
            nd.first_index =
                if nd.prim_count > 0 { nd.first_index + leaf_offset } else { place(nd.first_index as usize) as u32 };
            nodes[place(i)] = nd;
        }
    }
    let mut indices = l.indices;
    indices.extend(r.indices);
    Subtree { nodes, indices, depth: 1 + l.depth.max(r.depth) }
}

/// Split `refs` (at least 2, bounds `bounds`): `refs` keeps the left part and the right part is returned, both
/// non-empty.
fn split(refs: &mut Vec<Ref>, bounds: &Aabb, ctx: &Ctx, depth: usize, budget: &mut usize) -> Vec<Ref> {
    let (aabbs, tris, root_area) = (ctx.aabbs, ctx.tris, ctx.root_area);
    let cb = refs.iter().fold(Aabb::empty(), |a, r| {
        let c = r.b().center();
        a.union(&Aabb::new(c, c))
    });
    if depth >= SAH_DEPTH || refs.len() <= 4 {
        return median_split(refs, &cb);
    }
    let object = best_object_split(refs, &cb);
    let spatial = match &object {
        Some(o) if *budget > 0 && o.overlap > OVERLAP_ALPHA * root_area => best_spatial_split(refs, bounds, tris),
        None if *budget > 0 => best_spatial_split(refs, bounds, tris),
        _ => None,
    };
    if let Some(s) = spatial
        && object.as_ref().is_none_or(|o| s.cost < o.cost)
    {
        let (left, right) = partition_spatial(refs, &s, aabbs, tris);
        let extra = (left.len() + right.len()).saturating_sub(refs.len());
        if !left.is_empty() && !right.is_empty() && extra <= *budget {
            *budget -= extra;
            *refs = left;
            return right;
        }
    }
    let Some(o) = object else {
        return median_split(refs, &cb);
    };
    let (lo, extent) = (cb.min[o.axis], cb.max[o.axis] - cb.min[o.axis]);
    // Partition in place: the left part keeps the buffer.
    let mut m = 0;
    for j in 0..refs.len() {
        if centroid_bin(refs[j].centre(o.axis), lo, extent) <= o.bin {
            refs.swap(m, j);
            m += 1;
        }
    }
    if m == 0 || m == refs.len() {
        return median_split(refs, &cb);
    }
    refs.split_off(m)
}

/// The median split of the centroids along their longest axis.
fn median_split(refs: &mut Vec<Ref>, cb: &Aabb) -> Vec<Ref> {
    let axis = cb.largest_axis();
    let m = refs.len() / 2;
    refs.select_nth_unstable_by(m, |a, b| a.centre(axis).total_cmp(&b.centre(axis)));
    refs.split_off(m)
}

/// The bin of coordinate `c` (a centroid, or a box face for the spatial bins) among [`SPATIAL_BINS`] over
/// `[lo, lo + extent]`.
fn centroid_bin(c: f32, lo: f32, extent: f32) -> usize {
    (((c - lo) / extent * SPATIAL_BINS as f32) as usize).min(SPATIAL_BINS - 1)
}

/// The best binned-SAH split of the centroids: its cost, axis, last left bin and its children's overlap area.
struct ObjectSplit {
    cost: f32,
    axis: usize,
    bin: usize,
    overlap: f32,
}

fn best_object_split(refs: &[Ref], cb: &Aabb) -> Option<ObjectSplit> {
    let mut best: Option<ObjectSplit> = None;
    for axis in 0..3 {
        let (lo, extent) = (cb.min[axis], cb.max[axis] - cb.min[axis]);
        if !(extent > 0.0 && extent.is_finite()) {
            continue;
        }
        // A reference starts and ends in its centroid's bin.
        let mut bins = [(Aabb::empty(), 0usize, 0usize); SPATIAL_BINS];
        for r in refs {
            let b = &mut bins[centroid_bin(r.centre(axis), lo, extent)];
            b.0 = b.0.union(&r.b());
            (b.1, b.2) = (b.1 + 1, b.2 + 1);
        }
        if let Some(s) = cheapest_boundary(&bins)
            && best.as_ref().is_none_or(|b| s.cost < b.cost)
        {
            let overlap = intersection(&s.left, &s.right).map_or(0.0, |o| o.half_area());
            best = Some(ObjectSplit { cost: s.cost, axis, bin: s.last_left, overlap });
        }
    }
    best
}

/// The cheapest boundary between bins by SAH: its cost, the last bin on its left and both sides' boxes.
struct Boundary {
    cost: f32,
    last_left: usize,
    left: Aabb,
    right: Aabb,
}

/// The SAH sweep over `bins` of (box of the parts in the bin, references starting in it, references ending in
/// it): a boundary after bin `k` has on its left the references starting at or before `k`, on its right those
/// ending after it. `None` if every boundary leaves one side empty. Ties keep the first boundary.
fn cheapest_boundary(bins: &[(Aabb, usize, usize); SPATIAL_BINS]) -> Option<Boundary> {
    let mut right = [(Aabb::empty(), 0usize); SPATIAL_BINS];
    let mut acc = (Aabb::empty(), 0usize);
    for k in (1..SPATIAL_BINS).rev() {
        acc = (acc.0.union(&bins[k].0), acc.1 + bins[k].2);
        right[k] = acc;
    }
    let mut best: Option<Boundary> = None;
    let mut left = (Aabb::empty(), 0usize);
    for k in 0..SPATIAL_BINS - 1 {
        left = (left.0.union(&bins[k].0), left.1 + bins[k].1);
        let r = right[k + 1];
        if left.1 == 0 || r.1 == 0 {
            continue;
        }
        let cost = left.0.half_area() * left.1 as f32 + r.0.half_area() * r.1 as f32;
        if best.as_ref().is_none_or(|b| cost < b.cost) {
            best = Some(Boundary { cost, last_left: k, left: left.0, right: r.0 });
        }
    }
    best
}

/// The common part of two boxes, if any.
fn intersection(a: &Aabb, b: &Aabb) -> Option<Aabb> {
    let (min, max) = (a.min.max(b.min), a.max.min(b.max));
    min.cmple(max).all().then(|| Aabb::new(min, max))
}

/// The best spatial split: its cost, axis and plane.
struct SpatialSplit {
    cost: f32,
    axis: usize,
    plane: f32,
}

fn best_spatial_split(refs: &[Ref], bounds: &Aabb, tris: &[[Vec3A; 3]]) -> Option<SpatialSplit> {
    let mut best: Option<SpatialSplit> = None;
    for axis in 0..3 {
        let (lo, extent) = (bounds.min[axis], bounds.max[axis] - bounds.min[axis]);
        if !(extent > 0.0 && extent.is_finite()) {
            continue;
        }
        let plane = |k: usize| lo + extent * (k as f32 / SPATIAL_BINS as f32);
        let bin = |x: f32| centroid_bin(x, lo, extent);
        // Per bin: the box of the references' parts in it, how many references start and end in it.
        let mut bins = [(Aabb::empty(), 0usize, 0usize); SPATIAL_BINS];
        for r in refs {
            let (first, last) = if (r.id as usize) < tris.len() {
                (bin(r.min[axis]), bin(r.max[axis]))
            } else {
                let c = bin(r.centre(axis));
                (c, c)
            };
            if first == last {
                bins[first].0 = bins[first].0.union(&r.b());
            } else {
                let tri = &tris[r.id as usize];
                for (k, b) in bins.iter_mut().enumerate().take(last + 1).skip(first) {
                    let mut slab = r.b();
                    slab.min[axis] = slab.min[axis].max(plane(k));
                    slab.max[axis] = slab.max[axis].min(plane(k + 1));
                    if let Some(part) = slab_part(tri, axis, plane(k), plane(k + 1), &slab) {
                        b.0 = b.0.union(&part);
                    }
                }
            }
            bins[first].1 += 1;
            bins[last].2 += 1;
        }
        if let Some(s) = cheapest_boundary(&bins)
            && best.as_ref().is_none_or(|b| s.cost < b.cost)
        {
            best = Some(SpatialSplit { cost: s.cost, axis, plane: plane(s.last_left + 1) });
        }
    }
    best
}

/// The padded box of the part of `tri` with coordinate `axis` in `[lo, hi]`, kept inside `within` (the
/// reference's own box cut to the slab; the box of the part of the whole triangle, clamped to it, holds the part
/// of the reference's piece), or `None` if the triangle has no such part. The part is a convex polygon whose
/// corners are the triangle's corners in the slab and its edges' crossings of the two planes (the crossings' own
/// coordinate set to the plane exactly); its box is padded as `padded_prim_aabbs` pads a primitive's, which covers
/// the rounding of the crossings' other coordinates and of the ray–box test.
fn slab_part(tri: &[Vec3A; 3], axis: usize, lo: f32, hi: f32, within: &Aabb) -> Option<Aabb> {
    let (mut min, mut max) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
    for (i, &p) in tri.iter().enumerate() {
        if p[axis] >= lo && p[axis] <= hi {
            (min, max) = (min.min(p), max.max(p));
        }
        let q = tri[(i + 1) % 3];
        for plane in [lo, hi] {
            if (p[axis] < plane && q[axis] > plane) || (p[axis] > plane && q[axis] < plane) {
                let mut x = p + (q - p) * ((plane - p[axis]) / (q[axis] - p[axis]));
                x[axis] = plane;
                (min, max) = (min.min(x), max.max(x));
            }
        }
    }
    if !min.cmple(max).all() {
        return None;
    }
    let extent = tri[0].max(tri[1]).max(tri[2]) - tri[0].min(tri[1]).min(tri[2]);
    let pad =
        4.0 * f32::EPSILON * min.abs().max(max.abs()) + Vec3A::splat(1e-6 * extent.max_element() + f32::MIN_POSITIVE);
    let (min, max) = ((min - pad).max(within.min), (max + pad).min(within.max));
    min.cmple(max).all().then(|| Aabb::new(min, max))
}

/// The references of each side of `s.plane`: whole where they lie on one side, clipped to each side where a
/// triangle straddles it (a straddling shape of another kind goes whole to its centroid's side).
fn partition_spatial(refs: &[Ref], s: &SpatialSplit, aabbs: &[Aabb], tris: &[[Vec3A; 3]]) -> (Vec<Ref>, Vec<Ref>) {
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for r in refs {
        let a = s.axis;
        if r.max[a] <= s.plane {
            left.push(*r);
        } else if r.min[a] >= s.plane {
            right.push(*r);
        } else if (r.id as usize) < tris.len() {
            let tri = &tris[r.id as usize];
            let (mut lb, mut rb) = (r.b(), r.b());
            lb.max[a] = s.plane;
            rb.min[a] = s.plane;
            // Pad across the plane as well: the two halves overlap by the padding, never leave a gap.
            let pad = 4.0 * f32::EPSILON * s.plane.abs() + 1e-6 * aabbs[r.id as usize].diagonal().max_element();
            lb.max[a] = (lb.max[a] + pad).min(r.max[a]);
            rb.min[a] = (rb.min[a] - pad).max(r.min[a]);
            let left_part = slab_part(tri, a, f32::NEG_INFINITY, lb.max[a], &lb);
            match (left_part, slab_part(tri, a, rb.min[a], f32::INFINITY, &rb)) {
                (Some(l), Some(rr)) => {
                    left.push(Ref::new(r.id, &l));
                    right.push(Ref::new(r.id, &rr));
                }
                (Some(_), None) => left.push(*r),
                (None, Some(_)) => right.push(*r),
                (None, None) => {
                    if r.centre(a) < s.plane {
                        left.push(*r)
                    } else {
                        right.push(*r)
                    }
                }
            }
        } else if r.centre(a) < s.plane {
            left.push(*r);
        } else {
            right.push(*r);
        }
    }
    (left, right)
}
