//! `prism tessellate SPLINE.txt -o OUT.obj [--curve N] [--revolution N] [--patch N] [--bezier F] [--bspline F]`:
//! the 6.837 curve editor without its window. Every surface of a spline file (surfaces of revolution, Bézier
//! patches) is tessellated into one OBJ mesh with exact vertices, analytic normals and uvs (a file holding only
//! curves is written as OBJ polylines, `l`); `--bezier` / `--bspline` write the splines converted to that basis.
//! `prism curve_editor -input F -output F.obj -curve_tessellation N -revolution_tessellation N
//! -patch_tessellation N -output_bezier F -output_bspline F` is the course's own command line (`-gui` ignored).

use clap::Args;
use prism_core::error::PrismError;
use prism_core::shapes::CurveKind;
use prism_core::shapes::tessellate::{check_resolution, curve_tessellation, to_obj};
use prism_load::mit6837::spline::{SplineTxt, Tessellation, parse_spline_file, tessellate_splines, write_splines};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Args, Debug, Clone)]
pub struct TessellateArgs {
    /// A 6.837 spline file (`spline8_*.txt`).
    pub input: PathBuf,
    /// The OBJ mesh to write.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Segments per cubic piece of a curve or profile (`-curve_tessellation`).
    #[arg(long, default_value_t = 10)]
    pub curve: usize,
    /// Steps around a surface of revolution (`-revolution_tessellation`).
    #[arg(long, default_value_t = 10)]
    pub revolution: usize,
    /// Quads along each side of a Bézier patch (`-patch_tessellation`).
    #[arg(long, default_value_t = 10)]
    pub patch: usize,
    /// Write the splines with Bézier control points (`-output_bezier`).
    #[arg(long)]
    pub bezier: Option<PathBuf>,
    /// Write the splines as uniform B-splines (`-output_bspline`).
    #[arg(long)]
    pub bspline: Option<PathBuf>,
}

#[derive(Args, Debug, Clone)]
pub struct CurveEditorArgs {
    /// The course's options, e.g. `-input spline8_06_torus.txt -curve_tessellation 30 -revolution_tessellation 60
    /// -output torus_high.obj`.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, num_args = 1..)]
    pub args: Vec<String>,
}

fn write(path: &Path, text: &str) -> Result<(), PrismError> {
    std::fs::write(path, text).map_err(|e| PrismError::io(path, e))
}

pub fn run(a: TessellateArgs) -> anyhow::Result<()> {
    let res = Tessellation { curve: a.curve, revolution: a.revolution, patch: a.patch };
    for (what, n) in [("--curve", a.curve), ("--revolution", a.revolution), ("--patch", a.patch)] {
        check_resolution(what, n).map_err(PrismError::invalid)?;
    }
    if a.output.is_none() && a.bezier.is_none() && a.bspline.is_none() {
        return Err(PrismError::invalid("nothing to write: give -o OUT.obj, --bezier F or --bspline F").into());
    }
    if !a.input.is_file() {
        return Err(PrismError::io(
            &a.input,
            std::io::Error::new(std::io::ErrorKind::NotFound, "spline file not found"),
        )
        .into());
    }
    let items = parse_spline_file(&a.input)?;
    let name = a.input.display().to_string();
    for (path, kind) in [(&a.bezier, CurveKind::Bezier), (&a.bspline, CurveKind::BSpline)] {
        if let Some(p) = path {
            let text = write_splines(&items, kind).map_err(|e| PrismError::invalid(format!("{name}: {e}")))?;
            write(p, &text)?;
        }
    }
    if let Some(out) = &a.output {
        let header = format!(
            "{} tessellated by prism (curve {}, revolution {}, patch {})",
            a.input.file_name().map_or_else(String::new, |n| n.to_string_lossy().into()),
            res.curve,
            res.revolution,
            res.patch
        );
        let text = match tessellate_splines(&items, res).map_err(|e| PrismError::invalid(format!("{name}: {e}")))? {
            Some(mesh) => to_obj(&mesh, &header),
            None => curves_obj(&items, res.curve, &header).map_err(|e| PrismError::invalid(format!("{name}: {e}")))?,
        };
        write(out, &text)?;
    }
    Ok(())
}

/// Curves alone as OBJ polylines.
fn curves_obj(items: &[SplineTxt], n: usize, header: &str) -> Result<String, String> {
    let mut s = format!("# {header}\n");
    let mut base = 1;
    for item in items {
        if let SplineTxt::Curve { curve, .. } = item {
            let pts = curve_tessellation(curve, n)?;
            for p in &pts {
                let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
            }
            let idx: Vec<String> = (base..base + pts.len()).map(|i| i.to_string()).collect();
            let _ = writeln!(s, "l {}", idx.join(" "));
            base += pts.len();
        }
    }
    Ok(s)
}

/// The course's `curve_editor` options as `prism tessellate` arguments.
pub fn parse_curve_editor(args: &[String]) -> Result<TessellateArgs, PrismError> {
    let mut t = TessellateArgs {
        input: PathBuf::new(),
        output: None,
        curve: 10,
        revolution: 10,
        patch: 10,
        bezier: None,
        bspline: None,
    };
    let mut input = None;
    let mut i = 0;
    let value = |i: &mut usize, opt: &str| -> Result<String, PrismError> {
        *i += 1;
        args.get(*i).cloned().ok_or_else(|| PrismError::invalid(format!("{opt}: missing value")))
    };
    let number = |s: String, opt: &str| -> Result<usize, PrismError> {
        s.parse().map_err(|_| PrismError::invalid(format!("{opt}: `{s}` is not a non-negative integer")))
    };
    while i < args.len() {
        let opt = args[i].as_str();
        match opt {
            "-input" => input = Some(PathBuf::from(value(&mut i, opt)?)),
            "-output" => t.output = Some(value(&mut i, opt)?.into()),
            "-output_bezier" => t.bezier = Some(value(&mut i, opt)?.into()),
            "-output_bspline" => t.bspline = Some(value(&mut i, opt)?.into()),
            "-curve_tessellation" => t.curve = number(value(&mut i, opt)?, opt)?,
            "-revolution_tessellation" => t.revolution = number(value(&mut i, opt)?, opt)?,
            "-patch_tessellation" => t.patch = number(value(&mut i, opt)?, opt)?,
            "-gui" => {}
            other => {
                return Err(PrismError::invalid(format!(
                    "unsupported curve_editor option `{other}` (supported: -input -output -output_bezier \
                     -output_bspline -curve_tessellation -revolution_tessellation -patch_tessellation; -gui is \
                     ignored)"
                )));
            }
        }
        i += 1;
    }
    t.input = input.ok_or_else(|| PrismError::invalid("-input SPLINE.txt is required"))?;
    Ok(t)
}

pub fn run_curve_editor(a: CurveEditorArgs) -> anyhow::Result<()> {
    run(parse_curve_editor(&a.args)?)
}
