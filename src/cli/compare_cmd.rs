//! `prism compare TEST REF [--json]`.

use crate::compare::compare;
use crate::io::read_image;
use std::path::Path;

pub fn run(test: &Path, reference: &Path, json: bool) -> anyhow::Result<()> {
    let a = read_image(test)?;
    let b = read_image(reference)?;
    let m = compare(&a, &b)?;
    if json {
        println!("{}", m.to_json());
    } else {
        let v = |a: [f64; 3]| format!("({:.6}, {:.6}, {:.6})", a[0], a[1], a[2]);
        println!("RMSE    {:.6}", m.rmse);
        println!("relMSE  {:.6}", m.relmse);
        println!("MAE     {:.6}", m.mae);
        println!("mean    {}  reference {}", v(m.mean_test), v(m.mean_reference));
    }
    Ok(())
}
