//! A tight bound of one flat piece of a profile: the rectangle, aligned with the piece's chord, that holds its
//! Bézier control points (so the piece itself: convex hull property), revolved about the y axis. In the chord's
//! frame (origin `A` = the first control point, unit `e` along the chord, unit `m` normal to it) the rectangle is
//! `lambda in [lam0, lam1]`, `mu in [mu0, mu1]`; for a flat piece `mu` spans about the flatness, so the revolved
//! strip is a thin shell around the surface band (a ring, `profile_tree.rs`, is an axis-aligned rectangle and is
//! thick for slanted pieces).
//!
//! Along a ray, with `rho(t)` the distance from the axis (the square root of a quadratic) and `y(t)` linear,
//! each side of the rectangle is a condition `alpha rho(t) + beta t + gamma <= 0`. Its boundary points are roots of
//! the quadratic `alpha^2 rho^2(t) = (beta t + gamma)^2` (squaring may add roots: they only add break points);
//! between consecutive break points the sign is constant and is read at the middle. The result is the set of `t`
//! (at most a few intervals) where the ray is inside the strip: every root of the piece lies in it.
//! Only pieces on one side of the axis have a strip (a piece whose control points straddle the axis keeps its
//! ring).

use super::profile_tree::RingRay;
use glam::DVec3;

/// Up to four parameter intervals, increasing.
#[derive(Clone, Copy, Debug)]
pub struct Spans {
    /// The intervals `(lo, hi)` of ray parameters; only the first `n` are used.
    pub iv: [(f64, f64); 4],
    /// Number of intervals in use, 0 to 4.
    pub n: usize,
}

impl Spans {
    /// No interval.
    pub const EMPTY: Spans = Spans { iv: [(0.0, 0.0); 4], n: 0 };

    /// The interval `[lo, hi]` alone, or none when `lo > hi`.
    pub fn one(lo: f64, hi: f64) -> Spans {
        let mut s = Spans::EMPTY;
        if lo <= hi {
            s.iv[0] = (lo, hi);
            s.n = 1;
        }
        s
    }

    fn push(&mut self, lo: f64, hi: f64) {
        if lo > hi {
            return;
        }
        if self.n > 0 && lo <= self.iv[self.n - 1].1 {
            self.iv[self.n - 1].1 = self.iv[self.n - 1].1.max(hi);
        } else if self.n < 4 {
            self.iv[self.n] = (lo, hi);
            self.n += 1;
        } else {
            // Out of room: merge into the last (conservative).
            self.iv[3].1 = hi;
        }
    }

    /// The intervals in use, increasing.
    pub fn as_slice(&self) -> &[(f64, f64)] {
        &self.iv[..self.n]
    }
}

/// A leaf's oriented bound in the half-plane (radius, height).
#[derive(Clone, Copy, Debug)]
pub struct Strip {
    /// Chord origin (radius, height), unit chord direction and unit normal.
    ax: f64,
    ay: f64,
    e: (f64, f64),
    m: (f64, f64),
    lam: (f64, f64),
    mu: (f64, f64),
}

impl Strip {
    /// The strip of a piece with control points `c` (x = signed radius), padded by `pad`; `None` when the
    /// control points straddle the axis or the chord has no length.
    pub fn new(c: &[DVec3; 4], pad: f64) -> Option<Strip> {
        let sign = if c.iter().all(|p| p.x >= 0.0) {
            1.0
        } else if c.iter().all(|p| p.x <= 0.0) {
            -1.0
        } else {
            return None;
        };
        let pts = c.map(|p| (sign * p.x, p.y));
        let (ax, ay) = pts[0];
        let (dx, dy) = (pts[3].0 - ax, pts[3].1 - ay);
        let len = (dx * dx + dy * dy).sqrt();
        if len <= pad {
            return None;
        }
        let e = (dx / len, dy / len);
        let m = (-e.1, e.0);
        let (mut lam, mut mu) = ((f64::INFINITY, f64::NEG_INFINITY), (f64::INFINITY, f64::NEG_INFINITY));
        for (x, y) in pts {
            let (l, n) = ((x - ax) * e.0 + (y - ay) * e.1, (x - ax) * m.0 + (y - ay) * m.1);
            lam = (lam.0.min(l), lam.1.max(l));
            mu = (mu.0.min(n), mu.1.max(n));
        }
        Some(Strip { ax, ay, e, m, lam: (lam.0 - pad, lam.1 + pad), mu: (mu.0 - pad, mu.1 + pad) })
    }

    /// The parts of `within` where the ray is inside the strip.
    pub fn clip(&self, ray: &RingRay, within: &[(f64, f64)]) -> Spans {
        let (o, d) = (ray.o, ray.d);
        // u . (q(t) - A) = u.0 rho(t) + u.1 (o.y + t d.y - ay) - u.0 ax
        let lin = |u: (f64, f64)| (u.0, u.1 * d.y, u.1 * (o.y - self.ay) - u.0 * self.ax);
        let (le, lm) = (lin(self.e), lin(self.m));
        // Four conditions alpha rho + beta t + gamma <= 0.
        let conds = [
            (le.0, le.1, le.2 - self.lam.1),
            (-le.0, -le.1, -le.2 + self.lam.0),
            (lm.0, lm.1, lm.2 - self.mu.1),
            (-lm.0, -lm.1, -lm.2 + self.mu.0),
        ];
        let mut cur = Spans::EMPTY;
        for &(lo, hi) in within {
            cur.push(lo, hi);
        }
        for (alpha, beta, gamma) in conds {
            let mut next = Spans::EMPTY;
            for &(lo, hi) in cur.as_slice() {
                clip_one(ray, alpha, beta, gamma, lo, hi, &mut next);
            }
            cur = next;
            if cur.n == 0 {
                break;
            }
        }
        cur
    }
}

/// Append to `out` the parts of `[lo, hi]` where `alpha rho(t) + beta t + gamma <= 0`.
fn clip_one(ray: &RingRay, alpha: f64, beta: f64, gamma: f64, lo: f64, hi: f64, out: &mut Spans) {
    let h = |t: f64| alpha * ray.rho2(t).max(0.0).sqrt() + beta * t + gamma;
    // Break points: roots of alpha^2 rho^2(t) - (beta t + gamma)^2, in tau = t - tc (rho^2 = a tau^2 + cmin):
    // k2 tau^2 + 2 k1 tau + k0.
    let (a, tc, cmin) = ray.centered();
    let g = beta * tc + gamma;
    let a2 = alpha * alpha;
    let (k2, k1, k0) = (a2 * a - beta * beta, -beta * g, a2 * cmin - g * g);
    let mut br = [lo, 0.0, 0.0, hi];
    let mut nb = 1;
    let mut add = |tau: f64| {
        let t = tau + tc;
        if t > lo && t < hi && t.is_finite() {
            br[nb] = t;
            nb += 1;
        }
    };
    let scale = k2.abs().max(k1.abs()).max(k0.abs());
    if k2.abs() <= 1e-13 * scale {
        if k1 != 0.0 {
            add(-k0 / (2.0 * k1));
        }
    } else {
        let disc = k1 * k1 - k2 * k0;
        if disc >= 0.0 {
            let q = -(k1 + disc.sqrt().copysign(k1));
            if q != 0.0 {
                let (r0, r1) = (q / k2, k0 / q);
                add(r0.min(r1));
                add(r0.max(r1));
            } else {
                add(0.0);
            }
        } else if disc > -1e-12 * (k1 * k1 + (k2 * k0).abs()) {
            // A tangency lost to rounding: keep the touching point as a break point.
            add(-k1 / k2);
        }
    }
    br[nb] = hi;
    let pts = &mut br[..nb + 1];
    pts.sort_unstable_by(|x, y| x.total_cmp(y));
    for w in pts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        let inside = h(0.5 * (t0 + t1)) <= 0.0 || h(t0) <= 0.0 && h(t1) <= 0.0;
        if inside {
            out.push(t0, t1);
        }
    }
    // A single point (lo == hi) interval.
    if lo == hi && h(lo) <= 0.0 {
        out.push(lo, hi);
    }
}
