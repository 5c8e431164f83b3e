//! `prism compare TEST REF [--json]`: the metrics of `compare.rs`, and where the squared error lies (the share of
//! it in the worst 0.1%, 1% and 10% of the pixels). A reference an integer multiple of the test's size (the same
//! factor in both axes) is box-filtered down to it first, with a note.

use prism_core::io::read_image;
use prism_lab::compare::{compare, error_concentration};
use std::path::Path;

pub fn run(test: &Path, reference: &Path, json: bool) -> anyhow::Result<()> {
    let a = read_image(test)?;
    let mut b = read_image(reference)?;
    if (a.width, a.height) != (b.width, b.height)
        && let Some(small) = prism_lab::compare::box_downsample(&b, a.width, a.height)
    {
        eprintln!(
            "note: {} box-filtered from {}x{} to {}x{}",
            reference.display(),
            b.width,
            b.height,
            a.width,
            a.height
        );
        b = small;
    }
    let m = compare(&a, &b)?;
    let top = error_concentration(&a, &b)?;
    let text = if json {
        format!("{}\n", m.to_json(Some(top)))
    } else {
        let pct = |v: f64| if v.is_finite() { format!("{:.1}%", 100.0 * v) } else { "n/a".to_string() };
        let v = |a: [f64; 3]| format!("({:.6}, {:.6}, {:.6})", a[0], a[1], a[2]);
        format!(
            "RMSE    {:.6}\nrelMSE  {:.6}\nMAE     {:.6}\nmean    {}  reference {}\n\
             squared error in the worst 0.1% / 1% / 10% of pixels: {} / {} / {}\n",
            m.rmse,
            m.relmse,
            m.mae,
            v(m.mean_test),
            v(m.mean_reference),
            pct(top[0]),
            pct(top[1]),
            pct(top[2])
        )
    };
    super::print_stdout(&text)?;
    Ok(())
}
