//! MIT 6.837 assignment 8 spline files (`spline8_*.txt`, the course's `curve_editor` input):
//!
//! ```text
//! num_splines N
//! bezier | bspline            num_vertices K   x y z  (K times)     a curve
//! surface_of_revolution  bezier | bspline  num_vertices K  ...      its profile revolved about y
//! bezier_patch           x y z  (16 times)                          four rows of four control points
//! ```
//!
//! Every malformed file is a one-line `file:line:col` error: a count that does not match what follows
//! (`num_splines`, `num_vertices`), too few control points for the basis (a Bézier needs `3k + 1`, a B-spline at
//! least 4), a non-numeric, NaN or infinite coordinate, a profile that leaves the xy-plane (z != 0), an unknown
//! keyword, or a file that ends early. Counts are never used to allocate. The same module writes spline files
//! (for the curve editor's basis conversion) and tessellates them into one mesh.

use super::lexer::{Token, tokenize};
use glam::DVec3;
use prism_core::error::{PrismError, Result, SourcePos};
use prism_core::mesh::MeshData;
use prism_core::shapes::curve::MAX_CONTROL_POINTS;
use prism_core::shapes::tessellate::{merge_meshes, patch_tessellation, revolution_tessellation};
use prism_core::shapes::{Curve, CurveKind};
use std::fmt::Write as _;
use std::path::Path;

/// One spline of a spline file, with the line it starts on.
#[derive(Clone, Debug, PartialEq)]
pub enum SplineTxt {
    Curve { line: usize, curve: Curve },
    Revolution { line: usize, profile: Curve },
    Patch { line: usize, points: Box<[DVec3; 16]> },
}

/// The curve editor's tessellation resolutions (`-curve_tessellation`, `-revolution_tessellation`,
/// `-patch_tessellation`; the course's defaults are 10).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tessellation {
    pub curve: usize,
    pub revolution: usize,
    pub patch: usize,
}

impl Default for Tessellation {
    fn default() -> Self {
        Tessellation { curve: 10, revolution: 10, patch: 10 }
    }
}

struct P<'a> {
    tokens: Vec<Token>,
    next: usize,
    file: &'a Path,
}

impl P<'_> {
    fn err(&self, line: usize, col: usize, msg: impl Into<String>) -> PrismError {
        PrismError::Parse { pos: SourcePos { file: self.file.to_path_buf(), line, col }, message: msg.into() }
    }

    fn eof(&self, what: &str) -> PrismError {
        let (line, col) = self.tokens.last().map_or((1, 1), |t| (t.line, t.col + t.text.len()));
        self.err(line, col, format!("unexpected end of file: expected {what}"))
    }

    fn token(&mut self, what: &str) -> Result<Token> {
        let t = self.tokens.get(self.next).cloned().ok_or_else(|| self.eof(what))?;
        self.next += 1;
        Ok(t)
    }

    fn count(&mut self, word: &str) -> Result<usize> {
        let t = self.token(&format!("`{word}`"))?;
        if t.text != word {
            return Err(self.err(t.line, t.col, format!("expected `{word}`, found `{}`", t.text)));
        }
        let n = self.token(&format!("a count after `{word}`"))?;
        n.text.parse::<usize>().map_err(|_| {
            self.err(n.line, n.col, format!("`{word}` must be a non-negative integer, found `{}`", n.text))
        })
    }

    fn coord(&mut self) -> Result<(f64, Token)> {
        let t = self.token("a coordinate")?;
        match t.text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok((v, t)),
            Ok(_) => Err(self.err(t.line, t.col, format!("coordinate `{}` is not finite", t.text))),
            Err(_) => Err(self.err(t.line, t.col, format!("expected a coordinate, found `{}`", t.text))),
        }
    }

    /// A point `x y z`; `planar` requires z = 0 (a profile in the xy-plane).
    fn point(&mut self, planar: bool) -> Result<DVec3> {
        let (x, _) = self.coord()?;
        let (y, _) = self.coord()?;
        let (z, tz) = self.coord()?;
        if planar && z != 0.0 {
            return Err(self.err(
                tz.line,
                tz.col,
                format!("the profile of a surface of revolution leaves the xy-plane: z = {z} (must be 0)"),
            ));
        }
        Ok(DVec3::new(x, y, z))
    }

    fn peek_is_number(&self) -> bool {
        self.tokens.get(self.next).is_some_and(|t| t.text.parse::<f64>().is_ok())
    }

    /// `bezier|bspline num_vertices K points...`
    fn curve(&mut self, planar: bool) -> Result<Curve> {
        let t = self.token("`bezier` or `bspline`")?;
        let kind = match t.text.as_str() {
            "bezier" => CurveKind::Bezier,
            "bspline" => CurveKind::BSpline,
            other => {
                return Err(self.err(t.line, t.col, format!("expected `bezier` or `bspline`, found `{other}`")));
            }
        };
        let k = self.count("num_vertices")?;
        if k > MAX_CONTROL_POINTS {
            return Err(self.err(t.line, t.col, format!("num_vertices {k} is absurd (at most {MAX_CONTROL_POINTS})")));
        }
        let mut pts = Vec::new();
        for i in 0..k {
            if self.next < self.tokens.len() && !self.peek_is_number() {
                let n = &self.tokens[self.next];
                return Err(self.err(
                    n.line,
                    n.col,
                    format!(
                        "num_vertices {k} but the {} lists only {i} control points (found `{}`)",
                        kind.name(),
                        n.text
                    ),
                ));
            }
            pts.push(self.point(planar)?);
        }
        if self.peek_is_number() {
            let n = &self.tokens[self.next];
            return Err(self.err(
                n.line,
                n.col,
                format!("the {} lists more control points than num_vertices {k}", kind.name()),
            ));
        }
        Curve::new(kind, pts).map_err(|e| self.err(t.line, t.col, e))
    }
}

/// Parse spline-file text; `file` names it in errors.
pub fn parse_splines(text: &str, file: &Path) -> Result<Vec<SplineTxt>> {
    let mut p = P { tokens: tokenize(text), next: 0, file };
    let n = p.count("num_splines")?;
    let mut out = Vec::new();
    while let Some(t) = p.tokens.get(p.next).cloned() {
        if out.len() == n {
            return Err(p.err(t.line, t.col, format!("num_splines {n} but the file has more (`{}`)", t.text)));
        }
        p.next += 1;
        let item = match t.text.as_str() {
            "bezier" | "bspline" => {
                p.next -= 1;
                SplineTxt::Curve { line: t.line, curve: p.curve(false)? }
            }
            "surface_of_revolution" => SplineTxt::Revolution { line: t.line, profile: p.curve(true)? },
            "bezier_patch" => {
                let mut points = [DVec3::ZERO; 16];
                for (i, q) in points.iter_mut().enumerate() {
                    if p.next < p.tokens.len() && !p.peek_is_number() {
                        let n = &p.tokens[p.next];
                        return Err(p.err(
                            n.line,
                            n.col,
                            format!("a bezier_patch needs 16 control points, found {i} (then `{}`)", n.text),
                        ));
                    }
                    *q = p.point(false)?;
                }
                if p.peek_is_number() {
                    let n = &p.tokens[p.next];
                    return Err(p.err(n.line, n.col, "a bezier_patch has exactly 16 control points; found more"));
                }
                SplineTxt::Patch { line: t.line, points: Box::new(points) }
            }
            other => {
                return Err(p.err(
                    t.line,
                    t.col,
                    format!(
                        "unknown spline `{other}` (expected bezier, bspline, surface_of_revolution or bezier_patch)"
                    ),
                ));
            }
        };
        out.push(item);
    }
    if out.len() != n {
        let (line, col) = p.tokens.last().map_or((1, 1), |t| (t.line, t.col + t.text.len()));
        return Err(p.err(line, col, format!("num_splines {n} but the file ends after {} of them", out.len())));
    }
    Ok(out)
}

/// Read and parse a spline file.
pub fn parse_spline_file(path: &Path) -> Result<Vec<SplineTxt>> {
    let text = prism_core::io::read_regular_text(path, "spline file")?;
    parse_splines(&text, path)
}

/// Write splines back in the file format, every curve (and profile) in `kind`'s basis (the curve editor's
/// `-output_bezier` / `-output_bspline`). Fails for a Bézier curve that no B-spline represents.
pub fn write_splines(items: &[SplineTxt], kind: CurveKind) -> std::result::Result<String, String> {
    let mut s = String::new();
    let _ = writeln!(s, "num_splines {}\n", items.len());
    let curve = |s: &mut String, c: &Curve| -> std::result::Result<(), String> {
        let c = match kind {
            CurveKind::Bezier => c.to_bezier(),
            CurveKind::BSpline => c.to_bspline()?,
        };
        let _ = writeln!(s, "{}\nnum_vertices {}", kind.name(), c.points.len());
        for p in &c.points {
            let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
        }
        Ok(())
    };
    for item in items {
        match item {
            SplineTxt::Curve { curve: c, .. } => curve(&mut s, c)?,
            SplineTxt::Revolution { profile, .. } => {
                s += "surface_of_revolution\n";
                curve(&mut s, profile)?;
            }
            SplineTxt::Patch { points, .. } => {
                s += "bezier_patch\n";
                for p in points.iter() {
                    let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
                }
            }
        }
        s += "\n";
    }
    Ok(s)
}

/// Every surface of a spline file as one mesh (curves alone have no surface and are left out); `None` when the
/// file has no surface. Errors (as messages) for bad resolutions.
pub fn tessellate_splines(items: &[SplineTxt], res: Tessellation) -> std::result::Result<Option<MeshData>, String> {
    let mut parts = Vec::new();
    for item in items {
        match item {
            SplineTxt::Curve { .. } => {}
            SplineTxt::Revolution { profile, .. } => {
                parts.push(revolution_tessellation(profile, res.curve, res.revolution)?);
            }
            SplineTxt::Patch { points, .. } => parts.push(patch_tessellation(points, res.patch)?),
        }
    }
    Ok((!parts.is_empty()).then(|| merge_meshes("splines", &parts)))
}
