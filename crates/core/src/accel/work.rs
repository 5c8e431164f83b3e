//! Counting traversal work per ray (nodes or cells visited, primitives tested) for heat maps and statistics.
//!
//! Traversal code is generic over [`WorkCounter`]: the normal path uses [`NoCount`], whose methods are empty and
//! compile away, so counting costs nothing unless asked for through `Accel::intersect_counted` with a
//! [`TraversalWork`].

/// Something that is told about every node/cell visit and every primitive test of one ray.
pub trait WorkCounter: Copy {
    /// A BVH node, kd-tree node or grid cell was visited.
    fn node(&mut self);
    /// A primitive was tested for intersection.
    fn prim(&mut self);
}

/// The counter of the normal path: counts nothing.
#[derive(Clone, Copy, Debug)]
pub struct NoCount;

impl WorkCounter for NoCount {
    #[inline(always)]
    fn node(&mut self) {}
    #[inline(always)]
    fn prim(&mut self) {}
}

/// Work done for one ray: nodes (BVH nodes tested, kd-tree nodes visited, grid cells visited) and primitive tests.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalWork {
    /// Nodes tested (BVH), nodes visited (kd-tree) or cells visited (grid).
    pub nodes: u32,
    /// Primitive intersection tests.
    pub prims: u32,
}

impl WorkCounter for TraversalWork {
    #[inline(always)]
    fn node(&mut self) {
        self.nodes += 1;
    }
    #[inline(always)]
    fn prim(&mut self) {
        self.prims += 1;
    }
}
