//! SAH kd-tree construction in O(N log N) (Wald & Havran, "On building fast kd-trees for ray tracing, and on doing
//! that in O(N log N)", 2006).
//!
//! Every node keeps, per axis, the sorted list of its primitives' events (start and end of their bounds along the
//! axis, or one "planar" event for bounds that are flat along it). One linear sweep over each list evaluates the
//! surface area heuristic at every candidate plane with the exact counts left, right and in the plane (planar
//! primitives go to whichever side is cheaper). After the best plane is chosen, primitives are classified in one
//! pass; the events of primitives entirely on one side are split off in order, so no list is ever sorted again,
//! and only the straddling primitives get new events: their triangles are clipped to each child ("perfect
//! splits"), the few new events sorted and merged in. Each level therefore costs O(N): O(N log N) in total, the
//! initial sort included. Subtrees with many primitives are built in parallel (rayon) and then appended.
//!
//! Termination and robustness: a node becomes a leaf when no split beats the cost of testing all its primitives,
//! when it holds at most `max_leaf` primitives, or at the depth limit. A split that would cut off a flat empty
//! slab at the node's boundary (no progress) is never taken, so flat input (all triangles in one plane), stacks of
//! identical triangles and huge overlapping triangles end in leaves after at most a few empty-space cuts instead
//! of recursing to the depth limit with copies.

use super::{KdNode, KdParams, KdTreeData, MAX_DEPTH};
use crate::accel::triangle_clip::clipped_triangle_bounds;
use crate::geometry::Bounds;
use crate::primitives::Primitives;
use glam::Vec3A;

const END: u8 = 0;
const PLANAR: u8 = 1;
const START: u8 = 2;

/// Nodes with more primitives than this build their two subtrees in parallel.
const PARALLEL_MIN_PRIMS: usize = 4096;

#[derive(Clone, Copy, Debug)]
struct Event {
    pos: f32,
    /// Index into the node's primitive list.
    prim: u32,
    kind: u8,
}

#[inline]
fn event_order(a: &Event, b: &Event) -> std::cmp::Ordering {
    a.pos.total_cmp(&b.pos).then(a.kind.cmp(&b.kind))
}

/// A node under construction.
struct NodeInput {
    voxel: Bounds,
    /// Global primitive ids.
    ids: Vec<u32>,
    events: [Vec<Event>; 3],
    /// References the subtree may hold: the root's [`REFERENCE_BUDGET`] times the primitives, shared between the
    /// children of every split in proportion to what each receives.
    budget: u64,
}

/// References a kd-tree may hold per primitive, at most. Splits duplicate the primitives that straddle their plane;
/// where most straddle every plane (the slivers of a fan-triangulated polygon, which all meet at one vertex) the SAH
/// keeps accepting splits and the references grow geometrically with depth (558 per primitive on a 10,000-triangle
/// fan). A split that would exceed its node's share of the budget makes the node a leaf instead; ordinary scenes stay
/// far below (2 to 4 references per primitive), so their trees do not change.
pub const REFERENCE_BUDGET: u64 = 8;

#[derive(Clone, Copy, Debug)]
struct Split {
    axis: usize,
    pos: f32,
    planar_left: bool,
    /// Primitives on each side (straddling ones on both).
    counts: (u32, u32),
}

struct Ctx<'a> {
    prims: &'a Primitives,
    params: KdParams,
    max_depth: u32,
}

#[derive(Default)]
struct Out {
    nodes: Vec<KdNode>,
    prims: Vec<u32>,
    max_depth: u32,
}

impl Out {
    fn append(&mut self, o: Out) {
        let (node_offset, prim_offset) = (self.nodes.len() as u32, self.prims.len() as u32);
        self.nodes.extend(o.nodes.iter().map(|n| n.relocated(node_offset, prim_offset)));
        self.prims.extend_from_slice(&o.prims);
        self.max_depth = self.max_depth.max(o.max_depth);
    }
}

/// Build the tree over all bounded primitives inside `root` (the padded scene bounds).
pub fn build_tree(prims: &Primitives, root: Bounds, params: KdParams) -> KdTreeData {
    let n = prims.num_bounded();
    let auto_depth = (8.0 + 1.3 * (n.max(1) as f32).log2()).round() as u32;
    let ctx = Ctx { prims, params, max_depth: params.max_depth.unwrap_or(auto_depth).min(MAX_DEPTH) };
    let ids: Vec<u32> = (0..n).collect();
    let mut events: [Vec<Event>; 3] = Default::default();
    for (local, &id) in ids.iter().enumerate() {
        let b = prims.prim_bounds(id);
        let b = Bounds::new(b.min.max(root.min), b.max.min(root.max));
        push_events(&b, local as u32, &mut events);
    }
    use rayon::prelude::*;
    events.par_iter_mut().for_each(|e| e.sort_unstable_by(event_order));
    let mut out = Out::default();
    let budget = (n as u64).saturating_mul(REFERENCE_BUDGET).max(1);
    build_node(&ctx, NodeInput { voxel: root, ids, events, budget }, 0, &mut out);
    KdTreeData { nodes: out.nodes, prims: out.prims, max_depth: out.max_depth }
}

fn push_events(b: &Bounds, local: u32, events: &mut [Vec<Event>; 3]) {
    for (a, list) in events.iter_mut().enumerate() {
        if b.min[a] == b.max[a] {
            list.push(Event { pos: b.min[a], prim: local, kind: PLANAR });
        } else {
            list.push(Event { pos: b.min[a], prim: local, kind: START });
            list.push(Event { pos: b.max[a], prim: local, kind: END });
        }
    }
}

fn build_node(ctx: &Ctx, node: NodeInput, depth: u32, out: &mut Out) {
    let n = node.ids.len();
    let split = if n as u32 > ctx.params.max_leaf && depth < ctx.max_depth { find_plane(ctx, &node) } else { None };
    let split = split.filter(|s| s.counts.0 as u64 + s.counts.1 as u64 <= node.budget);
    let Some(split) = split else {
        out.nodes.push(KdNode::leaf(out.prims.len() as u32, n as u32));
        out.prims.extend_from_slice(&node.ids);
        out.max_depth = out.max_depth.max(depth);
        return;
    };
    let (left, right) = partition(ctx, node, split);
    let me = out.nodes.len();
    out.nodes.push(KdNode::default());
    let above = if left.ids.len() + right.ids.len() > PARALLEL_MIN_PRIMS {
        let (lo, ro) = rayon::join(
            || {
                let mut o = Out::default();
                build_node(ctx, left, depth + 1, &mut o);
                o
            },
            || {
                let mut o = Out::default();
                build_node(ctx, right, depth + 1, &mut o);
                o
            },
        );
        out.append(lo);
        let above = out.nodes.len();
        out.append(ro);
        above
    } else {
        build_node(ctx, left, depth + 1, out);
        let above = out.nodes.len();
        build_node(ctx, right, depth + 1, out);
        above
    };
    out.nodes[me] = KdNode::interior(split.axis, split.pos, above as u32);
}

/// The voxel cut at `pos` along `axis`.
fn split_voxel(v: &Bounds, axis: usize, pos: f32) -> (Bounds, Bounds) {
    let mut l = *v;
    let mut r = *v;
    l.max[axis] = pos;
    r.min[axis] = pos;
    (l, r)
}

/// The cheapest plane by the SAH, or `None` when a leaf is cheaper.
fn find_plane(ctx: &Ctx, node: &NodeInput) -> Option<Split> {
    let n = node.ids.len() as u32;
    let p = &ctx.params;
    let area = node.voxel.area();
    if area.is_nan() || area <= 0.0 {
        return None;
    }
    let leaf_cost = p.intersection_cost * n as f32;
    let mut best: Option<(f32, Split)> = None;
    for (axis, ev) in node.events.iter().enumerate() {
        let (vmin, vmax) = (node.voxel.min[axis], node.voxel.max[axis]);
        let (mut nl, mut nr) = (0u32, n);
        let mut i = 0;
        while i < ev.len() {
            let pos = ev[i].pos;
            let (mut pe, mut pp, mut ps) = (0u32, 0u32, 0u32);
            while i < ev.len() && ev[i].pos == pos && ev[i].kind == END {
                pe += 1;
                i += 1;
            }
            while i < ev.len() && ev[i].pos == pos && ev[i].kind == PLANAR {
                pp += 1;
                i += 1;
            }
            while i < ev.len() && ev[i].pos == pos && ev[i].kind == START {
                ps += 1;
                i += 1;
            }
            nr -= pp + pe;
            let np = pp;
            if pos >= vmin && pos <= vmax {
                let (l, r) = split_voxel(&node.voxel, axis, pos);
                let (pl, pr) = (l.area() / area, r.area() / area);
                for planar_left in [true, false] {
                    let (a, b) = if planar_left { (nl + np, nr) } else { (nl, nr + np) };
                    // A flat empty side at the boundary cuts nothing off: no progress.
                    if (pos <= vmin && a == 0) || (pos >= vmax && b == 0) {
                        continue;
                    }
                    let bonus = if a == 0 || b == 0 { p.empty_bonus } else { 1.0 };
                    let cost = bonus * (p.traversal_cost + p.intersection_cost * (pl * a as f32 + pr * b as f32));
                    if best.is_none_or(|(c, _)| cost < c) {
                        best = Some((cost, Split { axis, pos, planar_left, counts: (a, b) }));
                    }
                }
            }
            nl += ps + pp;
        }
    }
    best.filter(|(c, _)| *c < leaf_cost).map(|(_, s)| s)
}

const LEFT: u8 = 1;
const RIGHT: u8 = 2;
const BOTH: u8 = 3;
const NONE: u32 = u32::MAX;

/// Classify the node's primitives by the split and build both children's inputs.
fn partition(ctx: &Ctx, node: NodeInput, s: Split) -> (NodeInput, NodeInput) {
    let n = node.ids.len();
    let mut side = vec![BOTH; n];
    for e in &node.events[s.axis] {
        match e.kind {
            END if e.pos <= s.pos => side[e.prim as usize] = LEFT,
            START if e.pos >= s.pos => side[e.prim as usize] = RIGHT,
            PLANAR => {
                side[e.prim as usize] = if e.pos < s.pos || (e.pos == s.pos && s.planar_left) { LEFT } else { RIGHT }
            }
            _ => {}
        }
    }
    let (vl, vr) = split_voxel(&node.voxel, s.axis, s.pos);
    let mut map_l = vec![NONE; n];
    let mut map_r = vec![NONE; n];
    let (mut ids_l, mut ids_r) = (Vec::new(), Vec::new());
    let (mut new_l, mut new_r): ([Vec<Event>; 3], [Vec<Event>; 3]) = Default::default();
    for (local, &id) in node.ids.iter().enumerate() {
        match side[local] {
            LEFT => {
                map_l[local] = ids_l.len() as u32;
                ids_l.push(id);
            }
            RIGHT => {
                map_r[local] = ids_r.len() as u32;
                ids_r.push(id);
            }
            _ => {
                if let Some(b) = clipped_bounds(ctx.prims, id, &vl) {
                    map_l[local] = ids_l.len() as u32;
                    push_events(&b, map_l[local], &mut new_l);
                    ids_l.push(id);
                }
                if let Some(b) = clipped_bounds(ctx.prims, id, &vr) {
                    map_r[local] = ids_r.len() as u32;
                    push_events(&b, map_r[local], &mut new_r);
                    ids_r.push(id);
                }
            }
        }
    }
    let mut ev_l: [Vec<Event>; 3] = Default::default();
    let mut ev_r: [Vec<Event>; 3] = Default::default();
    for (axis, events) in node.events.into_iter().enumerate() {
        let mut only_l = Vec::with_capacity(events.len() / 2);
        let mut only_r = Vec::with_capacity(events.len() / 2);
        for e in events {
            match side[e.prim as usize] {
                LEFT => only_l.push(Event { prim: map_l[e.prim as usize], ..e }),
                RIGHT => only_r.push(Event { prim: map_r[e.prim as usize], ..e }),
                _ => {}
            }
        }
        let mut nl = std::mem::take(&mut new_l[axis]);
        let mut nr = std::mem::take(&mut new_r[axis]);
        nl.sort_unstable_by(event_order);
        nr.sort_unstable_by(event_order);
        ev_l[axis] = merge(only_l, nl);
        ev_r[axis] = merge(only_r, nr);
    }
    // The children share the node's budget in proportion to what each holds.
    let (l, r) = (ids_l.len() as u64, ids_r.len() as u64);
    let budget_l = if l + r == 0 { 0 } else { (node.budget as u128 * l as u128 / (l + r) as u128) as u64 };
    (
        NodeInput { voxel: vl, ids: ids_l, events: ev_l, budget: budget_l },
        NodeInput { voxel: vr, ids: ids_r, events: ev_r, budget: node.budget - budget_l },
    )
}

/// Merge two sorted event lists.
fn merge(a: Vec<Event>, b: Vec<Event>) -> Vec<Event> {
    if b.is_empty() {
        return a;
    }
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        if event_order(&a[i], &b[j]).is_le() {
            out.push(a[i]);
            i += 1;
        } else {
            out.push(b[j]);
            j += 1;
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

/// Bounds of primitive `id` within voxel `v` (clipped triangle; the analytic shape's own clipped bounds), grown by rounding error along
/// non-flat axes and clamped to `v`; `None` if it misses `v`.
fn clipped_bounds(prims: &Primitives, id: u32, v: &Bounds) -> Option<Bounds> {
    let b = if id < prims.num_tris() {
        // Clip against the voxel grown a little, so a triangle touching it within rounding error is kept.
        let mag = v.min.abs().max(v.max.abs());
        let grow = 4.0 * f32::EPSILON * mag + Vec3A::splat(1e-6) * v.diagonal();
        clipped_triangle_bounds(&prims.tris[id as usize], &Bounds::new(v.min - grow, v.max + grow))?
    } else {
        prims.analytic_clip_bounds(id, v)?
    };
    let mag = b.min.abs().max(b.max.abs());
    let flat = b.min.cmpeq(b.max);
    let pad = Vec3A::select(flat, Vec3A::ZERO, 2.0 * f32::EPSILON * mag);
    let r = Bounds::new((b.min - pad).max(v.min), (b.max + pad).min(v.max));
    (!r.is_empty()).then_some(r)
}
