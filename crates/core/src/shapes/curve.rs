//! Piecewise cubic curves: Bézier (control points `3k + 1`, segment `i` uses points `3i..3i+3`, C0 at the joins)
//! and uniform cubic B-splines (`n >= 4` points, `n - 3` segments, C2; a point repeated three times makes the curve
//! pass through it, with a zero derivative there: a cusp or a corner, as in the 6.837 file `spline8_05`).
//!
//! A curve is evaluated through its Bézier segments (a B-spline is converted once, exactly): the global parameter
//! `s` runs over `[0, segments]`, segment `floor(s)` at local parameter `s - floor(s)`. Evaluation, first and
//! second derivatives are exact polynomial evaluations in f64. Conversions between the two bases are exact:
//! B-spline to Bézier always; Bézier to B-spline when the Bézier segments join with C2 continuity (one segment
//! always does), else an error naming the first join that is not C2.
//!
//! The uniform cubic B-spline basis in Bézier form (points `P0..P3` of one B-spline segment):
//! `B0 = (P0 + 4 P1 + P2) / 6`, `B1 = (2 P1 + P2) / 3`, `B2 = (P1 + 2 P2) / 3`, `B3 = (P1 + 4 P2 + P3) / 6`.

use glam::DVec3;

/// The basis a curve's control points are given in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveKind {
    /// Piecewise cubic Bézier: `3k + 1` points, `k` segments sharing their end points.
    Bezier,
    /// Uniform cubic B-spline: `n >= 4` points, `n - 3` segments.
    BSpline,
}

impl CurveKind {
    /// The basis's name in scene files: `bezier` or `bspline`.
    pub fn name(self) -> &'static str {
        match self {
            CurveKind::Bezier => "bezier",
            CurveKind::BSpline => "bspline",
        }
    }
}

/// A piecewise cubic curve as given (control points in its basis), with its Bézier segments.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// The basis `points` are given in.
    pub kind: CurveKind,
    /// Control points as given.
    pub points: Vec<DVec3>,
    /// The curve as cubic Bézier segments (exact conversion of `points`).
    segments: Vec<[DVec3; 4]>,
}

/// Largest accepted number of control points of one curve (a guard against absurd input, not a real limit).
pub const MAX_CONTROL_POINTS: usize = 1 << 20;

/// Cubic Bézier point at local parameter `w`.
#[inline]
pub fn bezier(c: &[DVec3; 4], w: f64) -> DVec3 {
    let m = 1.0 - w;
    c[0] * (m * m * m) + c[1] * (3.0 * m * m * w) + c[2] * (3.0 * m * w * w) + c[3] * (w * w * w)
}

/// First derivative of a cubic Bézier at `w`.
#[inline]
pub fn bezier_d1(c: &[DVec3; 4], w: f64) -> DVec3 {
    let m = 1.0 - w;
    ((c[1] - c[0]) * (m * m) + (c[2] - c[1]) * (2.0 * m * w) + (c[3] - c[2]) * (w * w)) * 3.0
}

/// Second derivative of a cubic Bézier at `w`.
#[inline]
pub fn bezier_d2(c: &[DVec3; 4], w: f64) -> DVec3 {
    ((c[2] - c[1] * 2.0 + c[0]) * (1.0 - w) + (c[3] - c[2] * 2.0 + c[1]) * w) * 6.0
}

/// Split a cubic Bézier at `w` (de Casteljau): the control points of `[0, w]` and `[w, 1]`.
pub fn split_bezier(c: &[DVec3; 4], w: f64) -> ([DVec3; 4], [DVec3; 4]) {
    let l = |a: DVec3, b: DVec3| a + (b - a) * w;
    let (p01, p12, p23) = (l(c[0], c[1]), l(c[1], c[2]), l(c[2], c[3]));
    let (p012, p123) = (l(p01, p12), l(p12, p23));
    let mid = l(p012, p123);
    ([c[0], p01, p012, mid], [mid, p123, p23, c[3]])
}

/// The Bézier control points of one uniform cubic B-spline segment.
pub fn bspline_to_bezier(p: &[DVec3; 4]) -> [DVec3; 4] {
    [
        (p[0] + p[1] * 4.0 + p[2]) / 6.0,
        (p[1] * 2.0 + p[2]) / 3.0,
        (p[1] + p[2] * 2.0) / 3.0,
        (p[1] + p[2] * 4.0 + p[3]) / 6.0,
    ]
}

/// The uniform cubic B-spline control points of one Bézier segment (the inverse of [`bspline_to_bezier`]).
pub fn bezier_to_bspline(b: &[DVec3; 4]) -> [DVec3; 4] {
    let p1 = b[1] * 2.0 - b[2];
    let p2 = b[2] * 2.0 - b[1];
    [b[0] * 6.0 - p1 * 4.0 - p2, p1, p2, b[3] * 6.0 - p2 * 4.0 - p1]
}

impl Curve {
    /// A curve from control points; errors (as a message) for a count the basis cannot use or non-finite points.
    pub fn new(kind: CurveKind, points: Vec<DVec3>) -> Result<Curve, String> {
        if points.len() > MAX_CONTROL_POINTS {
            return Err(format!("{} control points (at most {MAX_CONTROL_POINTS})", points.len()));
        }
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(format!("control point {i} is not finite: {:?}", points[i].to_array()));
        }
        let segments: Vec<[DVec3; 4]> = match kind {
            CurveKind::Bezier => {
                if points.len() < 4 || !(points.len() - 1).is_multiple_of(3) {
                    return Err(format!(
                        "a Bézier curve needs 3k + 1 control points (4, 7, 10, ...), got {}",
                        points.len()
                    ));
                }
                points.windows(4).step_by(3).map(|w| [w[0], w[1], w[2], w[3]]).collect()
            }
            CurveKind::BSpline => {
                if points.len() < 4 {
                    return Err(format!("a B-spline needs at least 4 control points, got {}", points.len()));
                }
                points.windows(4).map(|w| bspline_to_bezier(&[w[0], w[1], w[2], w[3]])).collect()
            }
        };
        Ok(Curve { kind, points, segments })
    }

    /// The cubic Bézier segments.
    pub fn bezier_segments(&self) -> &[[DVec3; 4]] {
        &self.segments
    }

    /// Number of cubic segments: the parameter runs over `[0, segments]`.
    pub fn num_segments(&self) -> usize {
        self.segments.len()
    }

    /// Segment and local parameter of global parameter `s` (clamped to the curve).
    #[inline]
    pub fn locate(&self, s: f64) -> (usize, f64) {
        let n = self.segments.len();
        let s = s.clamp(0.0, n as f64);
        let i = (s.floor() as usize).min(n - 1);
        (i, s - i as f64)
    }

    /// Point at global parameter `s`.
    pub fn eval(&self, s: f64) -> DVec3 {
        let (i, w) = self.locate(s);
        bezier(&self.segments[i], w)
    }

    /// Derivative with respect to the global parameter `s`.
    pub fn derivative(&self, s: f64) -> DVec3 {
        let (i, w) = self.locate(s);
        bezier_d1(&self.segments[i], w)
    }

    /// Second derivative with respect to `s`.
    pub fn second_derivative(&self, s: f64) -> DVec3 {
        let (i, w) = self.locate(s);
        bezier_d2(&self.segments[i], w)
    }

    /// The same curve with Bézier control points (`3 * segments + 1` points).
    pub fn to_bezier(&self) -> Curve {
        let mut points = vec![self.segments[0][0]];
        for s in &self.segments {
            points.extend_from_slice(&s[1..]);
        }
        Curve { kind: CurveKind::Bezier, points, segments: self.segments.clone() }
    }

    /// The same curve as a uniform cubic B-spline (`segments + 3` points). Exact; fails when two Bézier segments
    /// do not join with C2 continuity (within `1e-9` of the curve's size), which no B-spline can represent.
    pub fn to_bspline(&self) -> Result<Curve, String> {
        if self.kind == CurveKind::BSpline {
            return Ok(self.clone());
        }
        let scale = self.points.iter().fold(0.0f64, |m, p| m.max(p.abs().max_element())).max(1e-300);
        let first = bezier_to_bspline(&self.segments[0]);
        let mut points = first.to_vec();
        for (k, seg) in self.segments.iter().enumerate().skip(1) {
            let b = bezier_to_bspline(seg);
            let n = points.len();
            let (p1, p2) = (points[n - 2], points[n - 1]);
            if (b[1] - p1).abs().max_element() > 1e-9 * scale || (b[2] - p2).abs().max_element() > 1e-9 * scale {
                return Err(format!(
                    "Bézier segments {} and {} do not join with C2 continuity: no uniform B-spline has this shape",
                    k - 1,
                    k
                ));
            }
            points.push(b[3]);
        }
        Ok(Curve { kind: CurveKind::BSpline, points, segments: self.segments.clone() })
    }

    /// `n` segments per cubic piece: `segments * n + 1` points from start to end (the 6.837 `-curve_tessellation`).
    pub fn tessellate(&self, n: usize) -> Vec<DVec3> {
        let n = n.max(1);
        let mut out = Vec::with_capacity(self.segments.len() * n + 1);
        for (i, seg) in self.segments.iter().enumerate() {
            let start = if i == 0 { 0 } else { 1 };
            for k in start..=n {
                out.push(bezier(seg, k as f64 / n as f64));
            }
        }
        out
    }

    /// Bounds (min, max) of the control points of the Bézier segments: they contain the curve.
    pub fn hull_bounds(&self) -> (DVec3, DVec3) {
        let mut lo = DVec3::splat(f64::INFINITY);
        let mut hi = DVec3::splat(f64::NEG_INFINITY);
        for p in self.segments.iter().flatten() {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        (lo, hi)
    }
}
