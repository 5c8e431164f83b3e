//! The kd-tree photon map (Jensen's, the seed's structure): a balanced kd-tree stored implicitly in the photon array.
//! A range `[lo, hi)` is a node whose splitting photon sits at the median `mid = (lo + hi) / 2`, split on the axis
//! of the range's largest extent (stored per photon); the left subtree is `[lo, mid)`, the right `(mid, hi)`. Built
//! every iteration by recursive median selection (O(n log n), subtrees in parallel, deterministic), queried by a
//! sphere range search that visits the near side first. Offered beside the hash grid so both lookups can be
//! measured on the same photons.

use super::photons::Photon;
use glam::Vec3A;

#[derive(Default)]
pub struct PhotonKdTree {
    photons: Vec<Photon>,
    axes: Vec<u8>,
}

/// Ranges smaller than this are built on the calling thread.
const PARALLEL_MIN: usize = 8192;

fn build_range(photons: &mut [Photon], axes: &mut [u8]) {
    let n = photons.len();
    if n <= 1 {
        return;
    }
    let (lo, hi) = photons
        .iter()
        .fold((Vec3A::splat(f32::INFINITY), Vec3A::splat(f32::NEG_INFINITY)), |(a, b), p| (a.min(p.p), b.max(p.p)));
    let ext = hi - lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    let mid = n / 2;
    photons.select_nth_unstable_by(mid, |a, b| a.p[axis].total_cmp(&b.p[axis]));
    axes[mid] = axis as u8;
    let (pl, pr) = photons.split_at_mut(mid);
    let (al, ar) = axes.split_at_mut(mid);
    let (pr, ar) = (&mut pr[1..], &mut ar[1..]);
    if n >= PARALLEL_MIN {
        rayon::join(|| build_range(pl, al), || build_range(pr, ar));
    } else {
        build_range(pl, al);
        build_range(pr, ar);
    }
}

impl PhotonKdTree {
    /// Rebuild over `chunks` (concatenated in order).
    pub fn build(&mut self, chunks: &[Vec<Photon>]) {
        self.photons.clear();
        for c in chunks {
            self.photons.extend_from_slice(c);
        }
        self.axes.clear();
        self.axes.resize(self.photons.len(), 0);
        build_range(&mut self.photons, &mut self.axes);
    }

    /// Call `f` for every photon within distance `r` of `p`.
    #[inline]
    pub fn query(&self, p: Vec3A, r: f32, mut f: impl FnMut(&Photon)) {
        let r2 = r * r;
        // Explicit stack of ranges (depth <= log2 n + 1).
        let mut stack = [(0usize, 0usize); 64];
        let mut top = 0;
        stack[0] = (0, self.photons.len());
        top += 1;
        while top > 0 {
            top -= 1;
            let (lo, hi) = stack[top];
            if lo >= hi {
                continue;
            }
            let mid = (lo + hi) / 2;
            let ph = &self.photons[mid];
            if hi - lo == 1 {
                if (ph.p - p).length_squared() < r2 {
                    f(ph);
                }
                continue;
            }
            let axis = self.axes[mid] as usize;
            let d = p[axis] - ph.p[axis];
            let (near, far) = if d < 0.0 { ((lo, mid), (mid + 1, hi)) } else { ((mid + 1, hi), (lo, mid)) };
            if d * d < r2 && top < stack.len() {
                stack[top] = far;
                top += 1;
            }
            if (ph.p - p).length_squared() < r2 {
                f(ph);
            }
            if top < stack.len() {
                stack[top] = near;
                top += 1;
            }
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.photons.capacity() * std::mem::size_of::<Photon>() + self.axes.capacity()
    }
}
