//! `prism compare TEST REF [--json]`.

use crate::compare::compare;
use crate::io::read_image;
use std::path::Path;

pub fn run(test: &Path, reference: &Path, json: bool) -> anyhow::Result<()> {
    let a = read_image(test)?;
    let b = read_image(reference)?;
    let m = compare(&a, &b)?;
    let text = if json {
        format!("{}\n", m.to_json())
    } else {
        let v = |a: [f64; 3]| format!("({:.6}, {:.6}, {:.6})", a[0], a[1], a[2]);
        format!(
            "RMSE    {:.6}\nrelMSE  {:.6}\nMAE     {:.6}\nmean    {}  reference {}\n",
            m.rmse,
            m.relmse,
            m.mae,
            v(m.mean_test),
            v(m.mean_reference)
        )
    };
    super::print_stdout(&text)?;
    Ok(())
}
